// The result classes. Large data comes as read-only numpy views into the C++ result (no copy),
// each keeping its result object alive: a part's vertices and triangles, a program's tips, axes,
// feeds, process flags, layers and regions, a toolpath's points, axes and deposit flags. Small
// data (layer outlines, figures) comes as Python objects; reports as the dicts of their JSON.
#include <fmt/format.h>

#include "bindings.h"
#include "polyaxis/post/program.h"
#include "polyaxis/report/analyze.h"
#include "polyaxis/report/lamination_files.h"
#include "polyaxis/report/plan_files.h"
#include "polyaxis/report/plan_set.h"
#include "polyaxis/toolpath/toolpath.h"

namespace polyaxis::python {
namespace {

py::object from_json(const std::string& text) { return py::module_::import("json").attr("loads")(text); }

py::tuple tuple3(const core::Vec3& v) { return py::make_tuple(v.x, v.y, v.z); }

// A ring of a layer's section, in the part's (or the table's) frame: an (n, 3) array, mm.
py::array ring_array(const slicing::Frame& frame, const geom2d::Ring& ring) {
  py::array_t<double> out({ring.size(), std::size_t{3}});
  auto a = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const core::Vec3 p = frame.to_world(geom2d::to_mm(ring[i].x), geom2d::to_mm(ring[i].y));
    a(i, 0) = p.x, a(i, 1) = p.y, a(i, 2) = p.z;
  }
  return out;
}

// One layer as a dict: index, height_mm, thickness_mm (least, largest), area_mm2, origin, normal
// and polygons, each {"outer": (n, 3) array, "holes": [arrays]} in 3-D.
py::dict layer_dict(const slicing::Layer& layer) {
  py::dict d;
  d["index"] = layer.index;
  d["height_mm"] = layer.height_mm;
  const auto [tmin, tmax] = layer.thickness_range();
  d["thickness_mm"] = py::make_tuple(tmin, tmax);
  d["area_mm2"] = layer.area_mm2;
  d["origin"] = tuple3(layer.frame.origin);
  d["normal"] = tuple3(layer.frame.d);
  d["conformal"] = layer.conformal.has_value();
  py::list polygons;
  for (const geom2d::Polygon& polygon : layer.polygons) {
    py::dict p;
    p["outer"] = ring_array(layer.frame, polygon.outer);
    py::list holes;
    for (const geom2d::Ring& hole : polygon.holes) holes.append(ring_array(layer.frame, hole));
    p["holes"] = holes;
    polygons.append(p);
  }
  d["polygons"] = polygons;
  return d;
}

py::list layer_list(const slicing::SliceResult& slices) {
  py::list out;
  for (const slicing::Layer& layer : slices.layers) out.append(layer_dict(layer));
  return out;
}

// The program points of a plan as arrays: views with the stride of post::ProgramPoint.
py::dict program_arrays(const std::vector<post::ProgramPoint>& points, py::handle owner) {
  constexpr std::size_t kStride = sizeof(post::ProgramPoint);
  const std::size_t n = points.size();
  const post::ProgramPoint* p = n ? points.data() : nullptr;
  py::dict d;
  d["tip"] = view(p ? &p->tip_part_mm.x : nullptr, n, 3, kStride, owner);
  d["axis"] = view(p ? &p->tool_axis_part.x : nullptr, n, 3, kStride, owner);
  d["feed_mm_s"] = view(p ? &p->feed_mm_s : nullptr, n, 0, kStride, owner);
  d["process_on"] = view(p ? &p->process_on : nullptr, n, 0, kStride, owner);
  d["layer"] = view(p ? &p->layer : nullptr, n, 0, kStride, owner);
  d["region"] = view(p ? &p->region : nullptr, n, 0, kStride, owner);
  return d;
}

const char* path_kind(toolpath::PathKind k) {
  switch (k) {
    case toolpath::PathKind::kPerimeter: return "perimeter";
    case toolpath::PathKind::kFill: return "fill";
    case toolpath::PathKind::kTravel: return "travel";
  }
  return "?";
}

// A layer's paths: dicts with kind, region, perimeter_index and views of points, axes and deposit.
py::list toolpath_list(const toolpath::LayerToolpaths& layer, py::handle owner) {
  constexpr std::size_t kStride = sizeof(toolpath::PathPoint);
  py::list out;
  for (const toolpath::Path& path : layer.paths) {
    const std::size_t n = path.points.size();
    const toolpath::PathPoint* p = n ? path.points.data() : nullptr;
    py::dict d;
    d["kind"] = path_kind(path.kind);
    d["region"] = path.region;
    d["perimeter_index"] = path.perimeter_index;
    d["points"] = view(p ? &p->position_mm.x : nullptr, n, 3, kStride, owner);
    d["axes"] = view(p ? &p->tool_axis.x : nullptr, n, 3, kStride, owner);
    d["deposit"] = view(p ? &p->deposit : nullptr, n, 0, kStride, owner);
    out.append(d);
  }
  return out;
}

void bind_part(py::module_& m) {
  py::class_<Part>(m, "Part", "A part as read and repaired (polyaxis.read_part)")
      .def_property_readonly("name", [](const Part& p) { return p.name; })
      .def_property_readonly("format", [](const Part& p) { return std::string(io::format_name(p.loaded->format)); })
      .def_property_readonly(
          "vertices",
          [](py::object self) {
            const auto& v = self.cast<const Part&>().loaded->repaired.mesh.vertices;
            return view(v.empty() ? nullptr : &v.front().x, v.size(), 3, sizeof(core::Vec3), self);
          },
          "(n, 3) float64, mm, read-only view")
      .def_property_readonly(
          "triangles",
          [](py::object self) {
            const auto& t = self.cast<const Part&>().loaded->repaired.mesh.triangles;
            return view(t.empty() ? nullptr : t.front().data(), t.size(), 3, sizeof(mesh::Triangle), self);
          },
          "(m, 3) uint32 vertex indices, counter-clockwise seen from outside, read-only view")
      .def_property_readonly("warnings", [](const Part& p) { return p.loaded->warnings; })
      .def_property_readonly("watertight", [](const Part& p) { return p.loaded->repaired.watertight; })
      .def_property_readonly("volume_mm3", [](const Part& p) { return report::solid_measure(p.loaded->repaired).volume_mm3; })
      .def("__repr__", [](const Part& p) {
        return fmt::format("<polyaxis.Part {} ({} triangles)>", p.name, p.loaded->repaired.mesh.triangles.size());
      });
}

void bind_slices(py::module_& m) {
  py::class_<Slices>(m, "Slices", "Layers of a part (polyaxis.slice)")
      .def("__len__", [](const Slices& s) { return s.result->layers.size(); })
      .def_property_readonly("layers", [](const Slices& s) { return layer_list(*s.result); }, "One dict per layer (see Plan.layers)")
      .def_property_readonly("report", [](const Slices& s) { return from_json(s.json); }, "layers.json as a dict")
      .def_property_readonly("total_area_mm2", [](const Slices& s) { return s.result->total_area_mm2; })
      .def_property_readonly("volume_estimate_mm3", [](const Slices& s) { return s.result->volume_estimate_mm3; });
}

void bind_analysis(py::module_& m) {
  py::class_<Analysis>(m, "Analysis", "Overhangs, centroidal axis, skeleton and regions (polyaxis.analyze)")
      .def_property_readonly("report", [](const Analysis& a) { return from_json(a.json); }, "analysis.json as a dict")
      .def_property_readonly(
          "regions",
          [](py::object self) {
            py::list out;
            for (const analysis::Region& r : self.cast<const Analysis&>().result->tree.regions) {
              py::dict d;
              d["id"] = r.id;
              d["direction"] = tuple3(r.build_direction);
              d["support_free"] = r.support_free;
              const auto& v = r.mesh.vertices;
              const auto& t = r.mesh.triangles;
              d["vertices"] = view(v.empty() ? nullptr : &v.front().x, v.size(), 3, sizeof(core::Vec3), self);
              d["triangles"] = view(t.empty() ? nullptr : t.front().data(), t.size(), 3, sizeof(mesh::Triangle), self);
              out.append(d);
            }
            return out;
          },
          "The regions: id, build direction, support_free and their closed meshes (views)");
}

void bind_plan(py::module_& m) {
  py::class_<Plan>(m, "Plan", "A plan of a part for a machine (polyaxis.plan)")
      .def_property_readonly("gcode", [](const Plan& p) { return p.job->set.gcode; }, "The machine program, as the CLI writes it")
      .def_property_readonly("gcode_name", [](const Plan& p) { return p.job->meta.gcode; }, "Its file name (<part>.ngc, .mpf, ...)")
      .def_property_readonly("set_id", [](const Plan& p) { return p.job->set.set_id; })
      .def_property_readonly("report", [](const Plan& p) { return from_json(p.job->set.report_json); }, "report.json as a dict")
      .def_property_readonly("simulation", [](const Plan& p) { return from_json(report::simulation_json(p.job->result.simulation)); },
                             "The program read back (as `polyaxis simulate --json`)")
      .def_property_readonly("strategy", [](const Plan& p) { return std::string(planner::strategy_name(p.job->result.strategy_used)); })
      .def_property_readonly("choice", [](const Plan& p) { return p.job->result.choice; })
      .def_property_readonly("warnings", [](const Plan& p) { return p.job->warnings; })
      .def_property_readonly("support_free", [](const Plan& p) { return p.job->result.plan.unsupported_area_mm2 == 0.0; })
      .def_property_readonly(
          "program", [](py::object self) { return program_arrays(self.cast<const Plan&>().job->result.plan.program, self); },
          "Program points, part frame: tip (n,3) mm, axis (n,3), feed_mm_s, process_on, layer, region (read-only views)")
      .def_property_readonly(
          "placement",
          [](const Plan& p) {
            const planner::Placement& pl = p.job->result.plan.placement;
            py::array_t<double> rotation({std::size_t{3}, std::size_t{3}});
            auto r = rotation.mutable_unchecked<2>();
            for (int i = 0; i < 3; ++i) {
              for (int j = 0; j < 3; ++j) r(i, j) = pl.rows[i][j];
            }
            py::dict d;
            d["rotation"] = rotation;
            d["translation_mm"] = tuple3(pl.translation_mm);
            return d;
          },
          "Where the part stands: table = rotation @ part + translation_mm")
      .def_property_readonly("layers", [](const Plan& p) { return layer_list(p.job->result.plan.layers); },
                             "One dict per layer in build order, table frame: index, height_mm, thickness_mm, area_mm2, origin, "
                             "normal, polygons")
      .def(
          "toolpaths",
          [](py::object self, std::size_t k) {
            const auto& paths = self.cast<const Plan&>().job->result.plan.toolpaths;
            if (k >= paths.size()) throw py::index_error(fmt::format("layer {} of {}", k, paths.size()));
            return toolpath_list(paths[k], self);
          },
          py::arg("layer"), "The paths of layer LAYER (build order): kind, region, points, axes, deposit")
      .def(
          "write",
          [](const Plan& p, const std::string& out_dir, bool html, bool svg, std::uint64_t max_output_bytes) {
            const report::PlanFilesOptions files{out_dir, html, svg, max_output_bytes};
            py::gil_scoped_release release;
            check(report::write_plan_files(files, p.job->set, p.job->result, p.job->configs.machine, p.job->configs.process, p.job->meta));
          },
          py::arg("out_dir"), py::arg("html") = true, py::arg("svg") = false, py::arg("max_output_bytes") = 0,
          "Writes the plan's files as `polyaxis plan -o OUT_DIR` does (OutputError when it cannot)")
      .def("__repr__", [](const Plan& p) {
        return fmt::format("<polyaxis.Plan {} layers, {} program points, {}>", p.job->result.plan.layers.layers.size(),
                           p.job->result.plan.program.size(), planner::strategy_name(p.job->result.strategy_used));
      });
}

void bind_lamination(py::module_& m) {
  py::class_<Lamination>(m, "Lamination", "Sheet layers, nesting and waterjet programs (polyaxis.laminate)")
      .def_property_readonly("report",
                             [](const Lamination& l) {
                               return from_json(lamination::lamination_json(l.job->lamination, l.job->sheets, l.job->meta));
                             },
                             "lamination.json as a dict")
      .def_property_readonly("programs",
                             [](const Lamination& l) {
                               py::dict d;
                               for (std::size_t i = 0; i < l.job->programs.size(); ++i) d[py::str(l.job->meta.programs[i])] = l.job->programs[i];
                               return d;
                             },
                             "Each sheet's program by file name")
      .def_property_readonly("warnings", [](const Lamination& l) { return l.job->warnings; })
      .def(
          "write",
          [](const Lamination& l, const std::string& out_dir) {
            py::gil_scoped_release release;
            check(report::write_lamination_files(out_dir, *l.job));
          },
          py::arg("out_dir"), "Writes the files as `polyaxis laminate -o OUT_DIR` does");
}

}  // namespace

void bind_results(py::module_& m) {
  bind_part(m);
  bind_slices(m);
  bind_analysis(m);
  bind_plan(m);
  bind_lamination(m);
}

}  // namespace polyaxis::python
