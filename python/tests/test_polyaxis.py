"""Tests of the Python module: every bound call, its options by the CLI's names, its results as numpy
views, and bad input giving the exception of the CLI's exit code, never a crash.

Run by ctest (python_tests) against the build tree's package, and by tests/package against the
installed one. POLYAXIS_PARTS_DIR names the reference parts, POLYAXIS_CLI the CLI to compare with.
"""

import json
import math
import os
import pathlib
import subprocess
import threading

import numpy as np
import pytest

import polyaxis

PARTS = pathlib.Path(os.environ["POLYAXIS_PARTS_DIR"])
CLI = os.environ["POLYAXIS_CLI"]


def box(sx=20.0, sy=10.0, sz=6.0):
    """A closed box of the given size, as (vertices, triangles) arrays (outward, counter-clockwise)."""
    v = np.array([[x, y, z] for z in (0, sz) for y in (0, sy) for x in (0, sx)], dtype=float)
    t = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                  [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]])
    return v, t


def cylinder(radius, height, segments):
    """A closed cylinder along +Z with SEGMENTS sides."""
    ring = [(radius * math.cos(2 * math.pi * k / segments), radius * math.sin(2 * math.pi * k / segments))
            for k in range(segments)]
    v = [[x, y, 0.0] for x, y in ring] + [[x, y, height] for x, y in ring] + [[0, 0, 0], [0, 0, height]]
    bottom, top = 2 * segments, 2 * segments + 1
    t = []
    for k in range(segments):
        n = (k + 1) % segments
        t += [[k, n, segments + n], [k, segments + n, segments + k], [bottom, n, k], [top, segments + k, segments + n]]
    return np.array(v), np.array(t)


# ---- read_part and inspect --------------------------------------------------------------------

def test_read_part_gives_views_of_the_repaired_mesh():
    part = polyaxis.read_part(PARTS / "l_block.stl")
    assert part.format == "stl-ascii"  # OpenSCAD writes ASCII STL
    assert part.vertices.shape[1] == 3 and part.triangles.shape[1] == 3
    assert part.vertices.dtype == np.float64 and part.triangles.dtype == np.uint32
    assert not part.vertices.flags.writeable
    assert part.vertices.base is not None  # a view into the C++ mesh, not a copy
    assert part.watertight and part.volume_mm3 > 0
    with pytest.raises(ValueError):
        part.vertices[0, 0] = 1.0


def test_read_part_from_arrays_and_scale():
    v, t = box()
    part = polyaxis.read_part((v, t), polyaxis.PartOptions(scale=2.0))
    assert part.volume_mm3 == pytest.approx(20 * 10 * 6 * 8)
    assert part.name == "part"  # arrays are named "part": part.ngc, "part: vertex 3 ..."


def test_inspect_matches_the_cli_json():
    ours = polyaxis.inspect(str(PARTS / "hinge.stl"))
    cli = json.loads(subprocess.run([CLI, "inspect", str(PARTS / "hinge.stl"), "--json"], check=True,
                                    capture_output=True, text=True).stdout)
    for key in ("triangles", "vertices", "volume_mm3", "area_mm2", "shells", "overhang_area_mm2", "repairs"):
        assert ours[key] == cli[key], key


# ---- bad input: the catalogue's rows as exceptions ------------------------------------------------

def test_missing_file_is_invalid_input(tmp_path):
    with pytest.raises(polyaxis.InvalidInputError) as e:
        polyaxis.read_part(tmp_path / "nothing.stl")
    assert e.value.exit_code == 3 and "nothing.stl" in str(e.value)


def test_a_directory_and_garbage_are_invalid_input(tmp_path):
    with pytest.raises(polyaxis.InvalidInputError):
        polyaxis.read_part(tmp_path)
    junk = tmp_path / "junk.stl"
    junk.write_bytes(b"solid x\nfacet normal 0 0 1\n outer loop\n vertex 1 2\n")
    with pytest.raises(polyaxis.InvalidInputError):
        polyaxis.read_part(junk)
    empty = tmp_path / "empty.stl"
    empty.write_bytes(b"")
    with pytest.raises(polyaxis.Error) as e:
        polyaxis.read_part(empty)
    assert e.value.exit_code == 3


def test_bad_arrays_are_invalid_input():
    v, t = box()
    with pytest.raises(polyaxis.InvalidInputError):
        polyaxis.read_part((v, t + 100))  # indices out of range
    bad = v.copy()
    bad[3, 1] = np.nan
    with pytest.raises(polyaxis.InvalidInputError):
        polyaxis.read_part((bad, t))
    with pytest.raises(polyaxis.InvalidInputError):
        polyaxis.read_part((v[:, :2], t))
    with pytest.raises(polyaxis.Error):
        polyaxis.read_part((v, t[:0]))  # no faces


def test_an_open_mesh_is_refused_unless_allowed():
    v, t = box()
    with pytest.raises(polyaxis.Error) as e:
        polyaxis.read_part((v, t[:-2]), polyaxis.PartOptions(max_hole_edges=0))
    assert e.value.exit_code in (3, 4)
    part = polyaxis.read_part((v, t[:-2]), polyaxis.PartOptions(max_hole_edges=0, allow_open=True))
    assert not part.watertight


def test_bad_options_are_usage_errors():
    with pytest.raises(polyaxis.UsageError):
        polyaxis.PlanOptions(no_such_option=1)
    with pytest.raises(polyaxis.UsageError) as e:
        polyaxis.plan(PARTS / "l_block.stl", polyaxis.PlanOptions(layers="sideways"))
    assert "--layers" in str(e.value) and e.value.exit_code == 2
    with pytest.raises(polyaxis.UsageError) as e:
        polyaxis.plan(PARTS / "l_block.stl", polyaxis.PlanOptions(layers="tilted", no_tilt=True))
    assert "contradicts --no-tilt" in str(e.value)
    with pytest.raises(polyaxis.UsageError):
        polyaxis.plan(PARTS / "l_block.stl", polyaxis.PlanOptions(dir="1,x,0"))
    with pytest.raises(polyaxis.UsageError):
        polyaxis.plan(PARTS / "l_block.stl", polyaxis.PlanOptions(set=["machine.no_such_key=1"]))
    with pytest.raises(polyaxis.UsageError):
        polyaxis.slice(PARTS / "l_block.stl", polyaxis.SliceOptions(layer=-1.0))
    with pytest.raises(polyaxis.UsageError):
        polyaxis.SliceOptions(adaptive={"wobble": 1.0})
    with pytest.raises(polyaxis.UsageError):
        polyaxis.analyze(PARTS / "l_block.stl", polyaxis.AnalyzeOptions(root_base="1,2"))


def test_a_deeply_nested_machine_file_is_a_usage_error(tmp_path):
    deep = tmp_path / "deep.json"
    deep.write_text('{"name":' + "[" * 60000 + "]" * 60000 + "}")
    with pytest.raises(polyaxis.UsageError):
        polyaxis.plan(PARTS / "l_block.stl", polyaxis.PlanOptions(machine=str(deep)))


def test_an_unwritable_output_is_an_output_error(tmp_path):
    plan = polyaxis.plan(box(), polyaxis.PlanOptions(strategy="single"))
    blocker = tmp_path / "file"
    blocker.write_text("x")
    with pytest.raises(polyaxis.OutputError) as e:
        plan.write(str(blocker / "out"))
    assert e.value.exit_code == 6


def test_every_error_class_is_a_polyaxis_error():
    for cls, code in ((polyaxis.UsageError, 2), (polyaxis.InvalidInputError, 3), (polyaxis.InfeasibleError, 4),
                      (polyaxis.MachineLimitError, 5), (polyaxis.OutputError, 6), (polyaxis.InternalError, 1)):
        assert issubclass(cls, polyaxis.Error) and cls.exit_code == code


# ---- slice and analyze ----------------------------------------------------------------------------

@pytest.mark.parametrize("segments", [12, 40])
def test_slice_a_cylinder_of_any_tessellation(segments):
    v, t = cylinder(8.0, 5.0, segments)
    slices = polyaxis.slice((v, t), polyaxis.SliceOptions(layer=0.5))
    assert len(slices) == 10
    layer = slices.layers[3]
    outer = layer["polygons"][0]["outer"]
    assert outer.shape[1] == 3
    assert np.allclose(outer[:, 2], layer["height_mm"])
    inscribed = 8.0 * math.cos(math.pi / segments)
    assert np.all(np.hypot(outer[:, 0], outer[:, 1]) >= inscribed - 1e-6)
    assert slices.report["layers"][3]["area_mm2"] == pytest.approx(layer["area_mm2"])


def test_slice_along_a_tilted_direction_and_adaptive():
    v, t = box(10, 10, 10)
    tilted = polyaxis.slice((v, t), polyaxis.SliceOptions(dir=(1, 0, 1), layer=1.0))
    n = tilted.layers[0]["normal"]
    assert n == pytest.approx((math.sqrt(0.5), 0, math.sqrt(0.5)))
    adaptive = polyaxis.slice(PARTS / "dome_sphere.stl", polyaxis.SliceOptions(adaptive={"cusp": 0.05}, min=0.1, max=1.0))
    thick = [layer["thickness_mm"][0] for layer in adaptive.layers]
    assert min(thick) < max(thick)


def test_analyze_the_l_block_into_regions():
    analysis = polyaxis.analyze(PARTS / "l_block.stl", polyaxis.AnalyzeOptions(skeleton=False))
    report = analysis.report
    assert len(analysis.regions) == len(report["regions"]) >= 2
    region = analysis.regions[0]
    assert region["vertices"].shape[1] == 3 and region["triangles"].shape[1] == 3


# ---- plan: the same bytes as the CLI -------------------------------------------------------------

def test_plan_gives_the_cli_program_byte_for_byte(tmp_path):
    part = str(PARTS / "l_block.stl")
    plan = polyaxis.plan(part)
    subprocess.run([CLI, "plan", part, "-o", str(tmp_path / "cli"), "--no-html"], check=True, capture_output=True)
    cli = (tmp_path / "cli" / "l_block.ngc").read_bytes()
    assert plan.gcode.encode() == cli
    assert plan.gcode_name == "l_block.ngc"
    plan.write(str(tmp_path / "py"), html=False)
    assert (tmp_path / "py" / "l_block.ngc").read_bytes() == cli
    assert (tmp_path / "py" / "report.json").read_bytes() == (tmp_path / "cli" / "report.json").read_bytes()


def test_plan_program_arrays_are_views_that_match_the_report():
    plan = polyaxis.plan(PARTS / "pen_rack.stl", polyaxis.PlanOptions(threads=1))
    program = plan.program
    n = len(program["tip"])
    assert n > 1000
    for key in ("axis", "feed_mm_s", "process_on", "layer", "region"):
        assert len(program[key]) == n, key
        assert not program[key].flags.writeable
    assert program["tip"].base is not None
    assert np.allclose(np.linalg.norm(program["axis"], axis=1), 1.0, atol=1e-9)
    assert program["process_on"].dtype == np.bool_ and program["process_on"].any()
    assert (np.diff(program["layer"].astype(np.int64)) >= 0).all() or plan.strategy != "single"
    report = plan.report
    deposit = program["process_on"][1:]
    length = np.linalg.norm(np.diff(program["tip"], axis=0), axis=1)[deposit].sum()
    assert length == pytest.approx(report["deposit_length_mm"], rel=1e-3)
    paths = plan.toolpaths(0)
    assert paths and paths[0]["points"].shape[1] == 3 and paths[0]["deposit"].dtype == np.bool_
    with pytest.raises(IndexError):
        plan.toolpaths(10 ** 6)


def test_plan_of_a_part_object_and_of_arrays():
    v, t = box(30, 12, 8)
    from_arrays = polyaxis.plan((v, t), polyaxis.PlanOptions(strategy="single", perimeters=1))
    part = polyaxis.read_part((v, t))
    from_part = polyaxis.plan(part, polyaxis.PlanOptions(strategy="single", perimeters=1))
    assert from_arrays.gcode == from_part.gcode
    assert from_arrays.support_free
    assert from_arrays.report["layers"] == len(from_arrays.layers)
    assert from_arrays.gcode_name == "part.ngc"  # arrays are named "part"


def test_plan_does_not_depend_on_the_thread_count():
    a = polyaxis.plan(PARTS / "spiral.stl", polyaxis.PlanOptions(threads=1))
    b = polyaxis.plan(PARTS / "spiral.stl", polyaxis.PlanOptions(threads=2))
    assert a.gcode == b.gcode


def test_progress_reaches_the_callback_and_the_gil_is_released():
    events = []
    ticks = []
    stop = threading.Event()

    def ticker():
        while not stop.is_set():
            ticks.append(1)
            stop.wait(0.01)

    thread = threading.Thread(target=ticker)
    thread.start()
    try:
        polyaxis.plan(PARTS / "impeller.stl", polyaxis.PlanOptions(strategy="single"),
                      progress=lambda stage, done, total, finished: events.append((stage, done, total, finished)))
    finally:
        stop.set()
        thread.join()
    stages = {stage for stage, *_ in events}
    assert {"slicing", "toolpaths", "G-code", "simulate"} <= stages, stages  # simulate runs on a worker thread
    ended = [stage for stage, _, _, finished in events if finished]
    assert "toolpaths" in ended and "G-code" in ended
    assert len(ticks) > 10  # the other thread ran while the plan was made


@pytest.mark.filterwarnings("ignore::pytest.PytestUnraisableExceptionWarning")
def test_a_failing_progress_callback_does_not_break_the_plan():
    def bad(*_):
        raise RuntimeError("no")

    plan = polyaxis.plan(box(), polyaxis.PlanOptions(strategy="single"), progress=bad)
    assert plan.gcode


# ---- simulate and laminate -----------------------------------------------------------------------

def test_simulate_a_plan_and_its_file(tmp_path):
    plan = polyaxis.plan(PARTS / "l_block.stl")
    sim = polyaxis.simulate(plan)
    assert sim["compared_with_plan"] and sim["max_tip_deviation_mm"] < 0.02
    path = tmp_path / "p.ngc"
    path.write_text(plan.gcode)
    again = polyaxis.simulate(path, plan=plan)
    assert again["moves"] == sim["moves"]
    assert polyaxis.simulate(plan.gcode)["compared_with_plan"] is False


def test_simulate_a_program_beyond_the_limits_is_a_machine_limit_error():
    plan = polyaxis.plan(PARTS / "l_block.stl")
    tight = polyaxis.SimulateOptions(set=["machine.limits.z.max=5"])
    with pytest.raises(polyaxis.MachineLimitError) as e:
        polyaxis.simulate(plan, options=tight)
    assert e.value.exit_code == 5 and "limit" in str(e.value)


def test_laminate_a_sphere_cap(tmp_path):
    result = polyaxis.laminate(PARTS / "dome_sphere.stl", polyaxis.LaminateOptions(sheets=[1, 2, 3, 6]))
    report = result.report
    assert report["layers"] and result.programs
    result.write(str(tmp_path / "lam"))
    for name, text in result.programs.items():
        assert (tmp_path / "lam" / name).read_text() == text
    with pytest.raises(polyaxis.UsageError):
        polyaxis.laminate(PARTS / "dome_sphere.stl", polyaxis.LaminateOptions())  # no sheets
