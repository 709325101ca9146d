// The calls: read_part, inspect, slice, analyze, plan, simulate, laminate. Each takes a part as a
// path (str or os.PathLike), a polyaxis.Part, or a pair (vertices (n, 3), triangles (m, 3)); the
// options object of its CLI command (None: the CLI's defaults); and, for the long ones, a progress
// callable (stage, done, total, finished). The GIL is released while the library works.
#include <fmt/format.h>

#include "bindings.h"
#include "polyaxis/analysis/root_base.h"
#include "polyaxis/io/text_file.h"
#include "polyaxis/report/layers.h"
#include "polyaxis/report/plan_files.h"
#include "polyaxis/report/plan_view.h"
#include "polyaxis/verify/simulate.h"

namespace polyaxis::python {
namespace {

constexpr std::uint64_t kMaxProgramBytes = 4ull << 30;  // as `polyaxis simulate`

bool is_path(const py::handle& h) {
  return py::isinstance<py::str>(h) || py::hasattr(h, "__fspath__");
}

std::string path_text(const py::handle& h) { return py::module_::import("os").attr("fspath")(h).cast<std::string>(); }

// A pair of arrays as a triangle soup (copied: repair makes its own mesh anyway).
io::RawMesh raw_mesh(const py::handle& part) {
  const auto pair = part.cast<py::tuple>();
  if (pair.size() != 2) throw Failure{{core::ErrorCode::kUsage, "part: give a path, a polyaxis.Part or (vertices, triangles)"}};
  const auto v = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(pair[0]);
  const auto t = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(pair[1]);
  if (!v || !t || v.ndim() != 2 || v.shape(1) != 3 || t.ndim() != 2 || t.shape(1) != 3) {
    throw Failure{{core::ErrorCode::kInvalidInput, "part: vertices must be an (n, 3) array of numbers and triangles an (m, 3) array of indices"}};
  }
  io::RawMesh mesh;
  auto va = v.unchecked<2>();
  for (py::ssize_t i = 0; i < va.shape(0); ++i) mesh.points.push_back({va(i, 0), va(i, 1), va(i, 2)});
  auto ta = t.unchecked<2>();
  for (py::ssize_t i = 0; i < ta.shape(0); ++i) {
    io::Triangle tri{};
    for (int k = 0; k < 3; ++k) {
      const std::int64_t index = ta(i, k);
      if (index < 0 || index > std::int64_t{UINT32_MAX}) {
        throw Failure{{core::ErrorCode::kInvalidInput, fmt::format("part: triangle {} names vertex {}", i, index)}};
      }
      tri[static_cast<std::size_t>(k)] = static_cast<std::uint32_t>(index);
    }
    mesh.triangles.push_back(tri);
  }
  return mesh;
}

// PART as a Part: read from its path or repaired from its arrays with OPTIONS.
Part part_of(const py::handle& part, mesh::LoadOptions options) {
  if (py::isinstance<Part>(part)) return part.cast<Part>();
  if (is_path(part)) {
    options.path = path_text(part);
    auto loaded = without_gil(py::none(), [&] { return mesh::load_part(options); });
    return Part{std::make_shared<const mesh::LoadedPart>(take(std::move(loaded))), options.path};
  }
  io::RawMesh raw = raw_mesh(part);
  const std::string name = "part";
  auto loaded = without_gil(py::none(), [&] { return mesh::load_part(std::move(raw), options, name); });
  return Part{std::make_shared<const mesh::LoadedPart>(take(std::move(loaded))), name};
}

// OPTIONS, or FALLBACK when None.
template <typename T>
T options_or(const py::object& options, T fallback) {
  return options.is_none() ? fallback : options.cast<T>();
}

mesh::LoadOptions part_defaults(bool self_intersections) {
  mesh::LoadOptions o;
  o.repair.check_self_intersections = self_intersections;
  return o;
}

Part read_part(const py::object& part, const py::object& options) { return part_of(part, options_or(options, part_defaults(true))); }

py::object inspect(const py::object& part, const py::object& options, double self_supporting_deg) {
  const mesh::LoadOptions o = options_or(options, part_defaults(true));
  const Part p = part_of(part, o);
  const std::string text = report::inspect_json(*p.loaded, p.name, self_supporting_deg, o.repair.check_self_intersections);
  return py::module_::import("json").attr("loads")(text);
}

Slices slice(const py::object& part, const py::object& options, const py::object& part_options, const py::object& progress) {
  const Part p = part_of(part, options_or(part_options, part_defaults(false)));
  slicing::SliceOptions o = options_or(options, slicing::SliceOptions{});
  if (o.tilted) o.adaptive = false;
  check(slicing::validate(o));
  auto sliced = without_gil(progress, [&] { return slicing::slice(p.loaded->repaired.mesh, o, &p.loaded->repaired.topology); });
  auto result = std::make_shared<const slicing::SliceResult>(take(std::move(sliced)));
  return Slices{result, report::layers_json(*result, report::LayersMeta{p.name, o})};
}

Analysis analyze(const py::object& part, const py::object& options, const py::object& part_options, const py::object& progress) {
  const Part p = part_of(part, options_or(part_options, part_defaults(false)));
  AnalyzeRequest request = options_or(options, AnalyzeRequest{});
  request.options.root_base = take(analysis::parse_root_base(request.root_base));
  auto analyzed = without_gil(progress, [&] { return report::analyze_part(p.loaded->repaired, request.options); });
  auto result = std::make_shared<const report::PartAnalysis>(take(std::move(analyzed)));
  const std::string json = report::analysis_json(p.name, result->overhang, result->axis, result->skeleton, result->tree, result->times);
  return Analysis{result, json};
}

// PART into a job's REQUEST (report::PlanRequest, lamination::LaminateRequest): a path is read by
// the job; a Part goes as its repaired mesh (repaired again: a no-op) and arrays as they are.
template <typename Request>
void set_part(Request& request, const py::handle& part) {
  if (py::isinstance<Part>(part)) {
    const Part p = part.cast<Part>();
    const auto& m = p.loaded->repaired.mesh;
    request.mesh = io::RawMesh{m.vertices, m.triangles};
    request.part.path = p.name;
  } else if (is_path(part)) {
    request.part.path = path_text(part);
  } else {
    request.mesh = raw_mesh(part);
    request.part.path = "part";
  }
}

Plan plan(const py::object& part, const py::object& options, const py::object& progress) {
  report::PlanRequest request = options_or(options, default_plan_request());
  set_part(request, part);
  auto job = without_gil(progress, [&] {
    request.options.progress = {};  // the scope's callback serves every stage
    return report::run_plan_job(request);
  });
  return Plan{std::shared_ptr<const report::PlanJob>(take(std::move(job)).release())};
}

py::object simulate(const py::object& program, const py::object& against, const py::object& options) {
  const SimulateRequest request = options_or(options, SimulateRequest{});
  std::string text;
  std::vector<post::ProgramPoint> points;
  if (py::isinstance<Plan>(program)) {
    const Plan& p = program.cast<const Plan&>();
    text = p.job->set.gcode;
    points = p.job->result.plan.program;
  } else if (py::isinstance<py::str>(program)) {
    text = program.cast<std::string>();
  } else if (py::hasattr(program, "__fspath__")) {
    text = take(io::read_text_file(path_text(program), kMaxProgramBytes));
  } else {
    throw Failure{{core::ErrorCode::kUsage, "simulate: give a polyaxis.Plan, the program's text or a path (pathlib.Path)"}};
  }
  if (!against.is_none()) points = against.cast<const Plan&>().job->result.plan.program;
  const machine::Configs configs = take(machine::load_configs(request.configs));
  auto sim = without_gil(py::none(), [&] {
    return verify::simulate(configs.machine, text, points, &configs.process, request.path_tolerance_mm);
  });
  const verify::SimulationReport report = take(std::move(sim));
  py::object result = py::module_::import("json").attr("loads")(report::simulation_json(report));
  if (report.limit_violations > 0) {
    std::string message = fmt::format("{} limit violations", report.limit_violations);
    for (std::size_t i = 0; i < report.violations.size() && i < 3; ++i) message += "; " + report.violations[i];
    throw Failure{{core::ErrorCode::kMachineLimit, message}};
  }
  return result;
}

Lamination laminate(const py::object& part, const py::object& options, const py::object& progress) {
  lamination::LaminateRequest request = options_or(options, default_laminate_request());
  set_part(request, part);
  auto job = without_gil(progress, [&] { return lamination::run_laminate_job(request); });
  return Lamination{std::make_shared<const lamination::LaminateJob>(take(std::move(job)))};
}

}  // namespace

void bind_calls(py::module_& m) {
  m.def("read_part", &read_part, py::arg("part"), py::arg("options") = py::none(),
        "Reads and repairs a part: a path (STL, OBJ, 3MF, STEP, IGES) or (vertices, triangles) arrays. Returns a Part.");
  m.def("inspect", &inspect, py::arg("part"), py::arg("options") = py::none(), py::arg("self_supporting_deg") = core::kDefaultSelfSupportingDeg,
        "`polyaxis inspect --json` as a dict: sizes, shells, repairs, overhang along +Z.");
  m.def("slice", &slice, py::arg("part"), py::arg("options") = py::none(), py::arg("part_options") = py::none(),
        py::arg("progress") = py::none(), "Cuts a part into layers (SliceOptions). Returns Slices.");
  m.def("analyze", &analyze, py::arg("part"), py::arg("options") = py::none(), py::arg("part_options") = py::none(),
        py::arg("progress") = py::none(), "Overhangs, centroidal axis, skeleton and region tree (AnalyzeOptions). Returns an Analysis.");
  m.def("plan", &plan, py::arg("part"), py::arg("options") = py::none(), py::arg("progress") = py::none(),
        "Plans a part on the machine and process of PlanOptions (None: the CLI's defaults). Returns a Plan.");
  m.def("simulate", &simulate, py::arg("program"), py::arg("plan") = py::none(), py::arg("options") = py::none(),
        "Reads a program back (a Plan, its text, or a pathlib.Path) and compares it with PLAN's points when given. Returns "
        "`polyaxis simulate --json` as a dict; MachineLimitError when the program breaks a limit.");
  m.def("laminate", &laminate, py::arg("part"), py::arg("options") = py::none(), py::arg("progress") = py::none(),
        "Sloped-edge sheet layers, nesting and 5-axis waterjet programs (LaminateOptions with sheets set). Returns a Lamination.");
}

}  // namespace polyaxis::python
