"""Plan a reference part from Python, plot its layers and the torch tilt along a path, write G-code.

    python3 examples/python/plan_and_plot.py [PART] [OUT_DIR]

PART defaults to examples/parts/impeller.stl, OUT_DIR to ./python-example. Writes OUT_DIR/layers.png,
OUT_DIR/tilt.png and the plan's files (OUT_DIR/<part>.ngc, plan.json, report.json, report.html).
"""

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")  # files, no window
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import polyaxis  # noqa: E402

here = pathlib.Path(__file__).resolve().parent
part = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else here.parent / "parts" / "impeller.stl"
out = pathlib.Path(sys.argv[2]) if len(sys.argv) > 2 else pathlib.Path("python-example")
out.mkdir(parents=True, exist_ok=True)

# %% Plan on the default 5-axis DED machine and process, as `polyaxis plan PART` does.
stages = set()
plan = polyaxis.plan(part, progress=lambda stage, done, total, finished: stages.add(stage))
report = plan.report
print(f"{part.name}: {len(plan.layers)} layers, {report['deposit_length_mm']:.0f} mm of deposit, "
      f"strategy {plan.strategy}, {'support-free' if plan.support_free else 'NOT support-free'}")
for warning in plan.warnings:
    print("warning:", warning)

# %% The layers: every fifth layer's outlines in 3-D (table frame), coloured by height.
fig = plt.figure(figsize=(7, 6))
ax = fig.add_subplot(projection="3d")
heights = [layer["origin"][2] for layer in plan.layers]
lo, hi = min(heights), max(heights)
for layer in plan.layers[::5]:
    colour = plt.cm.viridis((layer["origin"][2] - lo) / max(hi - lo, 1e-9))
    for polygon in layer["polygons"]:
        for ring in [polygon["outer"], *polygon["holes"]]:
            closed = np.vstack([ring, ring[:1]])
            ax.plot(closed[:, 0], closed[:, 1], closed[:, 2], color=colour, linewidth=0.6)
ax.set_xlabel("X mm"), ax.set_ylabel("Y mm"), ax.set_zlabel("Z mm")
ax.set_title(f"{part.stem}: every 5th of {len(plan.layers)} layers")
fig.savefig(out / "layers.png", dpi=110)

# %% The torch tilt along the program: the angle between the tool axis and the region's build
# direction at every deposit point, against the distance along the deposit path.
program = plan.program  # numpy views into the plan, no copy
tip, axis, on = program["tip"], program["axis"], program["process_on"]
step = np.r_[0.0, np.linalg.norm(np.diff(tip, axis=0), axis=1)]
along = np.cumsum(np.where(on, step, 0.0))
layer = program["layer"]
normals = np.array([plan.layers[k]["normal"] for k in range(len(plan.layers))])
rotation = plan.placement["rotation"]  # table = rotation @ part + translation
build = normals[np.minimum(layer, len(normals) - 1)] @ rotation  # the layers' normals in the part frame
tilt = np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", axis, build), -1.0, 1.0)))
fig2, ax2 = plt.subplots(figsize=(8, 3.5))
ax2.plot(along[on] / 1000.0, tilt[on], linewidth=0.4)
ax2.set_xlabel("deposit path, m"), ax2.set_ylabel("torch tilt from the layer normal, deg")
ax2.set_title(f"{part.stem}: largest tilt {tilt[on].max():.1f} deg")
fig2.tight_layout()
fig2.savefig(out / "tilt.png", dpi=110)

# %% The machine program and the report, as the CLI writes them.
plan.write(str(out))
print(f"wrote {out / plan.gcode_name}, {out / 'layers.png'}, {out / 'tilt.png'}; stages: {', '.join(sorted(stages))}")
