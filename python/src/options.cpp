// Typed option objects with the CLI's names (--merge-mm is merge_mm, --no-tilt is no_tilt, --set is
// set). Each is a plain object: PlanOptions() then plan_options.layers = "planar", or keywords
// PlanOptions(layers="planar") (the keyword constructor is added in polyaxis/__init__.py).
#include <fmt/format.h>

#include <sstream>

#include "bindings.h"

namespace polyaxis::python {
namespace {

// A direction from the CLI's "X,Y,Z" text or a sequence of three numbers.
core::Vec3 direction_vec(const py::object& value) {
  std::vector<double> v;
  if (py::isinstance<py::str>(value)) {
    std::stringstream text(value.cast<std::string>());
    std::string item;
    while (std::getline(text, item, ',')) {
      try {
        std::size_t used = 0;
        v.push_back(std::stod(item, &used));
        if (used != item.size()) throw std::invalid_argument(item);
      } catch (const std::exception&) {
        throw Failure{{core::ErrorCode::kUsage, fmt::format("dir: '{}' is not a number", item)}};
      }
    }
  } else {
    v = value.cast<std::vector<double>>();
  }
  if (v.size() != 3) throw Failure{{core::ErrorCode::kUsage, fmt::format("dir: expected three numbers, got {}", v.size())}};
  return {v[0], v[1], v[2]};
}

std::string direction_text(const py::object& value) {
  const core::Vec3 d = direction_vec(value);
  return fmt::format("{},{},{}", d.x, d.y, d.z);
}

py::tuple direction_tuple(const core::Vec3& d) { return py::make_tuple(d.x, d.y, d.z); }

void bind_part_options(py::module_& m) {
  py::class_<mesh::LoadOptions>(m, "PartOptions", "How a part is read and repaired (the CLI's part options)")
      .def(py::init<>())
      .def_readwrite("scale", &mesh::LoadOptions::scale, "Multiply coordinates by this (1000 for metres, 25.4 for inches)")
      .def_property(
          "merge_mm", [](const mesh::LoadOptions& o) { return o.repair.merge_mm; }, [](mesh::LoadOptions& o, double v) { o.repair.merge_mm = v; },
          "Merge vertices closer than this, mm")
      .def_property(
          "max_hole_edges", [](const mesh::LoadOptions& o) { return o.repair.max_hole_edges; },
          [](mesh::LoadOptions& o, std::uint32_t v) { o.repair.max_hole_edges = v; }, "Fill holes with at most this many edges")
      .def_property(
          "allow_open", [](const mesh::LoadOptions& o) { return o.repair.allow_open; }, [](mesh::LoadOptions& o, bool v) { o.repair.allow_open = v; },
          "Keep larger holes open instead of refusing the part")
      .def_property(
          "strict", [](const mesh::LoadOptions& o) { return o.repair.strict; }, [](mesh::LoadOptions& o, bool v) { o.repair.strict = v; },
          "Refuse self-intersecting parts and dropped 3MF triangles")
      .def_property(
          "self_intersections", [](const mesh::LoadOptions& o) { return o.repair.check_self_intersections; },
          [](mesh::LoadOptions& o, bool v) { o.repair.check_self_intersections = v; },
          "Run the self-intersection check (the CLI's --no-self-intersections turns it off)")
      .def_property(
          "max_triangles", [](const mesh::LoadOptions& o) { return o.read.max_triangles; },
          [](mesh::LoadOptions& o, std::uint64_t v) { o.read.max_triangles = v; }, "Refuse files with more triangles than this")
      .def_property(
          "chordal_mm", [](const mesh::LoadOptions& o) { return o.read.chordal_mm; }, [](mesh::LoadOptions& o, double v) { o.read.chordal_mm = v; },
          "STEP/IGES tessellation: largest chord deviation, mm");
}

void bind_plan_options(py::module_& m) {
  using R = report::PlanRequest;
  py::class_<R>(m, "PlanOptions", "The options of `polyaxis plan`, by the CLI's names")
      .def(py::init(&default_plan_request))
      .def_readwrite("part", &R::part, "PartOptions for reading the part (and the substrate)")
      .def_property(
          "dir", [](const R& r) { return r.dir; }, [](R& r, const py::object& v) { r.dir = direction_text(v); },
          "Build direction X,Y,Z in the part's frame (text or three numbers)")
      .def_readwrite("strategy", &R::strategy, "single, decompose or auto")
      .def_readwrite("decompose", &R::decompose, "The same as strategy='decompose'")
      .def_readwrite("layers", &R::layers, "planar, tilted, conformal or auto")
      .def_readwrite("no_tilt", &R::no_tilt, "Keep the torch along the build direction")
      .def_readwrite("root_base", &R::root_base, "z-min, a face id or 'PX,PY,PZ,NX,NY,NZ'; '' finds it")
      .def_readwrite("substrate", &R::substrate, "A part already on the table (a mesh file in the part's frame)")
      .def_property(
          "prebuilt", [](const R& r) { return r.options.prebuilt; }, [](R& r, std::vector<std::uint32_t> v) { r.options.prebuilt = std::move(v); },
          "Region ids of the decomposition already made")
      .def_property(
          "perimeters", [](const R& r) { return r.options.plan.perimeters; }, [](R& r, int v) { r.options.plan.perimeters = v; },
          "Perimeters per island")
      .def_property(
          "path_tolerance_mm", [](const R& r) { return r.options.gcode.chordal_mm; }, [](R& r, double v) { r.options.gcode.chordal_mm = v; },
          "Largest tool-tip deviation from the path between G-code blocks, mm")
      .def_property(
          "threads", [](const R& r) { return r.options.plan.threads; }, [](R& r, int v) { r.options.plan.threads = v; },
          "Worker threads of this call (0: all cores); the plan does not depend on it")
      .def_property(
          "decompose_budget", [](const R& r) { return r.options.decompose_budget_facet_visits; },
          [](R& r, double v) { r.options.decompose_budget_facet_visits = v; }, "Work a decomposition may do, in facet visits; 0: no limit")
      .def_property(
          "allow_collisions", [](const R& r) { return r.options.allow_collisions; }, [](R& r, bool v) { r.options.allow_collisions = v; },
          "Keep a plan whose program still strikes the plate, the table or the deposit")
      .def_property(
          "redirect_regions", [](const R& r) { return r.options.redirect_regions; }, [](R& r, bool v) { r.options.redirect_regions = v; },
          "Try regions whose program strikes something along other directions before giving up (default True)")
      .def_property(
          "max_output_bytes", [](const R& r) { return r.options.gcode.max_output_bytes; },
          [](R& r, std::uint64_t v) { r.options.gcode.max_output_bytes = v; }, "Refuse a program or file set larger than this (0: no cap)")
      .def_property(
          "machine", [](const R& r) { return r.configs.machine_path; }, [](R& r, std::string v) { r.configs.machine_path = std::move(v); },
          "Machine file; '' for the built-in 5-axis A/C DED machine")
      .def_property(
          "process", [](const R& r) { return r.configs.process_path; }, [](R& r, std::string v) { r.configs.process_path = std::move(v); },
          "Process file; '' for the built-in ded_steel")
      .def_property(
          "set", [](const R& r) { return r.configs.sets; }, [](R& r, std::vector<std::string> v) { r.configs.sets = std::move(v); },
          "Overrides: ['machine.limits.c.max=360', 'process.bead_width_mm=3']");
}

void bind_slice_options(py::module_& m) {
  using S = slicing::SliceOptions;
  py::class_<S>(m, "SliceOptions", "The options of `polyaxis slice`, by the CLI's names")
      .def(py::init<>())
      .def_property(
          "dir", [](const S& s) { return direction_tuple(s.direction); },
          [](S& s, const py::object& v) { s.direction = direction_vec(v); },
          "Build direction X,Y,Z (any length)")
      .def_readwrite("layer", &S::layer_mm, "Uniform layer thickness, mm")
      .def_property(
          "adaptive",
          [](const S& s) {
            py::dict d;
            if (!s.adaptive) return d;
            if (s.limits.cusp_mm) d["cusp"] = *s.limits.cusp_mm;
            if (s.limits.voldiff) d["voldiff"] = *s.limits.voldiff;
            if (s.limits.area_deviation) d["area"] = *s.limits.area_deviation;
            if (s.limits.overhang_deg) d["overhang"] = *s.limits.overhang_deg;
            return d;
          },
          [](S& s, const py::dict& limits) { set_adaptive(s, limits); },
          "Adaptive thickness under limits: {'cusp': mm, 'voldiff': share, 'area': share, 'overhang': deg}; {} for uniform")
      .def_readwrite("min", &S::min_mm, "Adaptive: thinnest layer, mm")
      .def_readwrite("max", &S::max_mm, "Adaptive: thickest layer, mm")
      .def_readwrite("snap", &S::snap_mm, "Adaptive: thicknesses are multiples of this, mm")
      .def_readwrite("thicknesses", &S::thickness_stock_mm, "Adaptive: thicknesses to choose from, mm")
      .def_readwrite("tilted", &S::tilted, "Tilted \"3-D\" layers along the centroidal axis")
      .def_readwrite("threads", &S::threads, "Worker threads (0: all cores); the output does not depend on it");
}

void bind_analyze_options(py::module_& m) {
  py::class_<AnalyzeRequest>(m, "AnalyzeOptions", "The options of `polyaxis analyze`, by the CLI's names")
      .def(py::init<>())
      .def_readwrite("root_base", &AnalyzeRequest::root_base, "z-min, a face id or 'PX,PY,PZ,NX,NY,NZ'; '' finds it")
      .def_property(
          "skeleton", [](const AnalyzeRequest& a) { return a.options.skeleton; }, [](AnalyzeRequest& a, bool v) { a.options.skeleton = v; },
          "Compute the distance-field skeleton (the CLI's --no-skeleton turns it off)")
      .def_property(
          "voxel_mm", [](const AnalyzeRequest& a) { return a.options.voxel_mm; }, [](AnalyzeRequest& a, double v) { a.options.voxel_mm = v; },
          "Skeleton grid step, mm (0: the part's size / 64)")
      .def_property(
          "self_supporting_deg", [](const AnalyzeRequest& a) { return a.options.self_supporting_deg; },
          [](AnalyzeRequest& a, double v) { a.options.self_supporting_deg = v; }, "Self-supporting angle from vertical, degrees")
      .def_property(
          "break_angle_deg", [](const AnalyzeRequest& a) { return a.options.break_angle_deg; },
          [](AnalyzeRequest& a, double v) { a.options.break_angle_deg = v; }, "Centroidal-axis links turning more than this are break links");
}

void bind_simulate_options(py::module_& m) {
  py::class_<SimulateRequest>(m, "SimulateOptions", "The options of `polyaxis simulate`, by the CLI's names")
      .def(py::init<>())
      .def_property(
          "machine", [](const SimulateRequest& s) { return s.configs.machine_path; },
          [](SimulateRequest& s, std::string v) { s.configs.machine_path = std::move(v); }, "Machine file; '' for the built-in one")
      .def_property(
          "process", [](const SimulateRequest& s) { return s.configs.process_path; },
          [](SimulateRequest& s, std::string v) { s.configs.process_path = std::move(v); }, "Process file; '' for the built-in one")
      .def_property(
          "set", [](const SimulateRequest& s) { return s.configs.sets; },
          [](SimulateRequest& s, std::vector<std::string> v) { s.configs.sets = std::move(v); }, "Overrides, as PlanOptions.set")
      .def_readwrite("path_tolerance_mm", &SimulateRequest::path_tolerance_mm, "Tip deviation from the plan counted as on it, mm");
}

void bind_laminate_options(py::module_& m) {
  using L = lamination::LaminateRequest;
  py::class_<L>(m, "LaminateOptions", "The options of `polyaxis laminate`, by the CLI's names")
      .def(py::init(&default_laminate_request))
      .def_readwrite("part", &L::part, "PartOptions for reading the part")
      .def_property(
          "sheets", [](const L& l) { return l.options.sheets_mm; }, [](L& l, std::vector<double> v) { l.options.sheets_mm = std::move(v); },
          "Sheet thicknesses in stock, mm")
      .def_property(
          "sheet_size", [](const L& l) { return py::make_tuple(l.sheet_w_mm, l.sheet_h_mm); },
          [](L& l, std::pair<double, double> v) { l.sheet_w_mm = v.first, l.sheet_h_mm = v.second; }, "Sheet size (W, H), mm")
      .def_property(
          "area_deviation", [](const L& l) { return l.options.area_deviation; }, [](L& l, double v) { l.options.area_deviation = v; },
          "Largest area deviation of a layer's sloped edge from the part")
      .def_property(
          "cusp", [](const L& l) { return l.options.cusp_mm.value_or(0.0); },
          [](L& l, double v) { l.options.cusp_mm = v > 0.0 ? std::optional<double>(v) : std::nullopt; },
          "Largest gap between a cut and the part, mm (off when 0)")
      .def_property(
          "subslice", [](const L& l) { return l.options.subslice_mm; }, [](L& l, double v) { l.options.subslice_mm = v; },
          "Thin sub-slice for convex multi-cuts, mm (0: the thinnest sheet)")
      .def_property(
          "threads", [](const L& l) { return l.options.threads; }, [](L& l, int v) { l.options.threads = v; }, "Worker threads (0: all cores)")
      .def_property(
          "machine", [](const L& l) { return l.configs.machine_path; }, [](L& l, std::string v) { l.configs.machine_path = std::move(v); },
          "Head-head machine file; '' for the built-in waterjet")
      .def_property(
          "process", [](const L& l) { return l.configs.process_path; }, [](L& l, std::string v) { l.configs.process_path = std::move(v); },
          "Waterjet process file; '' for the built-in one")
      .def_property(
          "set", [](const L& l) { return l.configs.sets; }, [](L& l, std::vector<std::string> v) { l.configs.sets = std::move(v); },
          "Overrides, as PlanOptions.set");
}

}  // namespace

void set_adaptive(slicing::SliceOptions& s, const py::dict& limits) {
  s.limits = {};
  s.adaptive = !limits.empty();
  for (const auto& [key, value] : limits) {
    const auto name = key.cast<std::string>();
    const double v = value.cast<double>();
    if (name == "cusp") {
      s.limits.cusp_mm = v;
    } else if (name == "voldiff") {
      s.limits.voldiff = v;
    } else if (name == "area") {
      s.limits.area_deviation = v;
    } else if (name == "overhang") {
      s.limits.overhang_deg = v;
    } else {
      throw Failure{{core::ErrorCode::kUsage, fmt::format("adaptive: unknown limit '{}' (known: cusp, voldiff, area, overhang)", name)}};
    }
  }
}

void bind_options(py::module_& m) {
  bind_part_options(m);
  bind_plan_options(m);
  bind_slice_options(m);
  bind_analyze_options(m);
  bind_simulate_options(m);
  bind_laminate_options(m);
}

}  // namespace polyaxis::python
