#include "polyaxis/lamination/outputs.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

namespace polyaxis::lamination {
namespace {

using nlohmann::json;

constexpr std::size_t kMaxRingPointsInPage = 240;  // per ring in the 3-D view
constexpr std::size_t kRuledLinesPerRing = 48;

double round_to(double v, double step) { return std::round(v / step) * step; }

json ring_json(const geom2d::Ring& ring) {
  json out = json::array();
  for (const auto& p : ring) out.push_back({round_to(geom2d::to_mm(p.x), 1e-4), round_to(geom2d::to_mm(p.y), 1e-4)});
  return out;
}

const char* kind_name(EdgeKind k) { return k == EdgeKind::kConvex ? "convex" : k == EdgeKind::kConcave ? "concave" : "straight"; }

// A loop's samples: [x, y, nx, ny, kind, [[r_ref, slope], …], A, C] (mm, the part's frame; Hayasi's
// angles of the first cut, degrees).
json loop_json(const EdgeLoop& loop) {
  json samples = json::array();
  for (const auto& s : loop.samples) {
    json cuts = json::array();
    for (const auto& c : s.cuts) cuts.push_back({round_to(c.r_mid_mm, 1e-6), round_to(c.slope, 1e-9)});
    samples.push_back({round_to(s.p.x, 1e-6), round_to(s.p.y, 1e-6), round_to(s.n.x, 1e-9), round_to(s.n.y, 1e-9), kind_name(s.kind), cuts,
                       round_to(s.hayasi_a_deg, 1e-4), round_to(s.hayasi_c_deg, 1e-4)});
  }
  return {{"hole", loop.hole}, {"passes", loop.passes()}, {"samples", samples}};
}

json layer_json(const Layer& l) {
  json pieces = json::array();
  for (const auto& p : l.pieces) {
    json loops = json::array({loop_json(p.outer)});
    for (const auto& h : p.holes) loops.push_back(loop_json(h));
    pieces.push_back({{"area_mm2", p.area_mm2}, {"loops", loops}});
  }
  return {{"index", l.index},
          {"z_bottom_mm", l.z_bottom_mm},
          {"thickness_mm", l.thickness_mm},
          {"z_ref_mm", l.z_ref_mm},
          {"sub_slices", l.subslices},
          {"area_deviation", l.area_deviation},
          {"max_gap_mm", l.max_gap_mm},
          {"excess_mm", l.excess_mm},
          {"edges", {{"convex", l.convex_samples}, {"concave", l.concave_samples}, {"straight", l.straight_samples}, {"at_jet_limit", l.at_jet_limit}}},
          {"holes_closed", l.holes_closed},
          {"pieces", pieces}};
}

}  // namespace

std::string lamination_json(const Lamination& lam, const std::vector<Sheet>& sheets, const LaminateMeta& meta) {
  json layers = json::array();
  for (const auto& l : lam.layers) layers.push_back(layer_json(l));
  json js = json::array();
  for (const auto& s : sheets) {
    json pieces = json::array();
    for (const auto& sp : s.pieces) {
      const Piece& piece = lam.layers[sp.layer].pieces[sp.piece];
      geom2d::Ring outer;
      for (const auto& smp : piece.outer.samples) outer.push_back({geom2d::to_units(smp.p.x), geom2d::to_units(smp.p.y)});
      pieces.push_back({{"label", fmt::format("L{}.P{}", sp.layer, sp.piece)},
                        {"layer", sp.layer},
                        {"piece", sp.piece},
                        {"placement", {{"rotation_deg", sp.placement.rotation_deg}, {"dx_mm", sp.placement.dx_mm}, {"dy_mm", sp.placement.dy_mm}}},
                        {"outer", ring_json(place(sp.placement, outer))}});
    }
    js.push_back({{"index", s.index},
                  {"thickness_mm", s.thickness_mm},
                  {"size_mm", {s.size_mm[0], s.size_mm[1]}},
                  {"origin_mm", {s.origin_mm[0], s.origin_mm[1]}},
                  {"utilisation", s.utilisation},
                  {"program", s.index < meta.programs.size() ? meta.programs[s.index] : std::string()},
                  {"pieces", pieces}});
  }
  json doc = {{"format", "polyaxis-lamination"},
              {"version", 1},
              {"part", meta.part},
              {"machine", meta.machine},
              {"process", meta.process},
              {"stock_mm", meta.sheets_mm},
              {"area_deviation_limit", meta.area_deviation},
              {"max_jet_angle_deg", meta.max_jet_angle_deg},
              {"kerf_mm", meta.kerf_mm},
              {"threshold_met", lam.threshold_met},
              {"part_volume_mm3", lam.part_volume_mm3},
              {"sloped_deviation_mm3", lam.sloped_deviation_mm3},
              {"stepped_deviation_mm3", lam.stepped_deviation_mm3},
              {"covering_deviation_mm3", lam.covering_deviation_mm3},
              {"seconds", meta.seconds},
              {"stage_seconds", [&] {
                 json t = json::object();
                 for (const auto& [k, v] : meta.stage_seconds) t[k] = v;
                 return t;
               }()},
              {"layers", layers},
              {"sheets", js}};
  return doc.dump(1) + "\n";
}

std::string sheet_svg(const Lamination& lam, const Sheet& sheet, const WaterjetProcess& process) {
  const double w = sheet.size_mm[0], h = sheet.size_mm[1];
  std::string out = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}mm\" height=\"{1}mm\" viewBox=\"0 0 {0} {1}\">\n"
      "<title>sheet {2}: {3} mm, {4} pieces, {5:.1f} % used</title>\n"
      "<defs><marker id=\"arrow\" markerWidth=\"6\" markerHeight=\"6\" refX=\"5\" refY=\"3\" orient=\"auto\"><path d=\"M0,0 L6,3 L0,6 z\" fill=\"#c0392b\"/></marker></defs>\n"
      "<g transform=\"translate(0 {1}) scale(1 -1)\">\n<rect x=\"0\" y=\"0\" width=\"{0}\" height=\"{1}\" fill=\"#eef1f4\" stroke=\"#555\" stroke-width=\"0.5\"/>\n",
      w, h, sheet.index, sheet.thickness_mm, sheet.pieces.size(), 100.0 * sheet.utilisation);
  auto path_of = [](const geom2d::Ring& ring) {
    std::string d;
    for (std::size_t i = 0; i < ring.size(); ++i) d += fmt::format("{}{:.3f},{:.3f} ", i == 0 ? "M" : "L", geom2d::to_mm(ring[i].x), geom2d::to_mm(ring[i].y));
    return d + "Z";
  };
  std::string labels;
  for (const auto& sp : sheet.pieces) {
    const Layer& layer = lam.layers[sp.layer];
    const Piece& piece = layer.pieces[sp.piece];
    out += fmt::format("<path d=\"{}\" fill=\"none\" stroke=\"#7f8c8d\" stroke-width=\"0.3\" stroke-dasharray=\"1 1\"/>\n",
                       path_of(place(sp.placement, footprint(layer, piece, process.kerf_mm))));
    auto loop_path = [&](const EdgeLoop& loop, const char* colour) {
      geom2d::Ring ring;
      for (const auto& s : loop.samples) ring.push_back({geom2d::to_units(s.p.x), geom2d::to_units(s.p.y)});
      out += fmt::format("<path d=\"{}\" fill=\"{}\" fill-rule=\"evenodd\" stroke=\"#2c3e50\" stroke-width=\"0.3\"/>\n", path_of(place(sp.placement, ring)), colour);
      if (loop.samples.size() < 2) return;
      // The lead-in (from outside the loop) and the cut's direction at the start.
      const auto& s0 = loop.samples[0];
      const auto& s1 = loop.samples[std::min<std::size_t>(3, loop.samples.size() - 1)];
      double x0 = 0, y0 = 0, xl = 0, yl = 0, x1 = 0, y1 = 0;
      place(sp.placement, s0.p.x, s0.p.y, x0, y0);
      place(sp.placement, s0.p.x + s0.n.x * process.lead_in_mm, s0.p.y + s0.n.y * process.lead_in_mm, xl, yl);
      place(sp.placement, s1.p.x, s1.p.y, x1, y1);
      out += fmt::format("<line x1=\"{:.3f}\" y1=\"{:.3f}\" x2=\"{:.3f}\" y2=\"{:.3f}\" stroke=\"#c0392b\" stroke-width=\"0.4\" marker-end=\"url(#arrow)\"/>\n", xl, yl, x0, y0);
      out += fmt::format("<line x1=\"{:.3f}\" y1=\"{:.3f}\" x2=\"{:.3f}\" y2=\"{:.3f}\" stroke=\"#c0392b\" stroke-width=\"0.4\" marker-end=\"url(#arrow)\"/>\n", x0, y0, x1, y1);
    };
    loop_path(piece.outer, "#d6eaf8");
    for (const auto& hole : piece.holes) loop_path(hole, "#eef1f4");
    // Number and orientation: the piece's +X from its first sample's place.
    double cx = 0, cy = 0, n = 0;
    for (const auto& s : piece.outer.samples) cx += s.p.x, cy += s.p.y, n += 1;
    cx /= std::max(n, 1.0), cy /= std::max(n, 1.0);
    double px = 0, py = 0, qx = 0, qy = 0;
    place(sp.placement, cx, cy, px, py);
    place(sp.placement, cx + 5.0, cy, qx, qy);
    out += fmt::format("<line x1=\"{:.3f}\" y1=\"{:.3f}\" x2=\"{:.3f}\" y2=\"{:.3f}\" stroke=\"#27ae60\" stroke-width=\"0.5\" marker-end=\"url(#arrow)\"/>\n", px, py, qx, qy);
    labels += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" font-size=\"4\" font-family=\"sans-serif\" fill=\"#111\">L{}.P{}</text>\n", px + 1.0, h - py - 1.0,
                          sp.layer, sp.piece);
  }
  out += "</g>\n" + labels + "</svg>\n";
  return out;
}

namespace {

// The stack as JSON for the page's 3-D view: per piece, the kept edge at the bottom and the top.
json stack_json(const Lamination& lam) {
  json layers = json::array();
  for (const auto& l : lam.layers) {
    json rings = json::array();
    for (const auto& piece : l.pieces) {
      auto add_loop = [&](const EdgeLoop& loop) {
        const std::size_t n = loop.samples.size();
        if (n == 0) return;
        const std::size_t step = std::max<std::size_t>(1, n / kMaxRingPointsInPage);
        json lo = json::array(), hi = json::array();
        for (std::size_t i = 0; i < n; i += step) {
          const auto& s = loop.samples[i];
          const double rb = s.kept_mm(l.z_bottom_mm, l.z_ref_mm), rt = s.kept_mm(l.z_top(), l.z_ref_mm);
          lo.push_back({round_to(s.p.x + s.n.x * rb, 1e-3), round_to(s.p.y + s.n.y * rb, 1e-3)});
          hi.push_back({round_to(s.p.x + s.n.x * rt, 1e-3), round_to(s.p.y + s.n.y * rt, 1e-3)});
        }
        rings.push_back({{"bottom", lo}, {"top", hi}, {"ruled_every", std::max<std::size_t>(1, lo.size() / kRuledLinesPerRing)}});
      };
      add_loop(piece.outer);
      for (const auto& hole : piece.holes) add_loop(hole);
    }
    layers.push_back({{"z0", l.z_bottom_mm}, {"z1", l.z_top()}, {"rings", rings}});
  }
  return layers;
}

constexpr const char* kPageScript = R"JS(
const stack = JSON.parse(document.getElementById('stack').textContent);
const canvas = document.getElementById('view'), ctx = canvas.getContext('2d');
let yaw = -0.6, pitch = 0.45, drag = null;
let lo = [1e9, 1e9, 1e9], hi = [-1e9, -1e9, -1e9];
for (const l of stack) for (const r of l.rings) for (const [k, z] of [['bottom', l.z0], ['top', l.z1]]) for (const p of r[k]) {
  const q = [p[0], p[1], z];
  for (let i = 0; i < 3; ++i) { lo[i] = Math.min(lo[i], q[i]); hi[i] = Math.max(hi[i], q[i]); }
}
const centre = lo.map((v, i) => (v + hi[i]) / 2), size = Math.max(...hi.map((v, i) => v - lo[i]), 1);
function project(x, y, z) {
  x -= centre[0]; y -= centre[1]; z -= centre[2];
  const cx = Math.cos(yaw) * x - Math.sin(yaw) * y, cy = Math.sin(yaw) * x + Math.cos(yaw) * y;
  const sy = Math.cos(pitch) * z - Math.sin(pitch) * cy;
  const s = 0.8 * Math.min(canvas.width, canvas.height) / size;
  return [canvas.width / 2 + s * cx, canvas.height / 2 - s * sy];
}
function line(a, b) { ctx.moveTo(a[0], a[1]); ctx.lineTo(b[0], b[1]); }
function draw() {
  ctx.fillStyle = '#fff'; ctx.fillRect(0, 0, canvas.width, canvas.height);
  stack.forEach((l, i) => {
    ctx.strokeStyle = i % 2 ? '#2e86c1' : '#ca6f1e'; ctx.lineWidth = 1; ctx.beginPath();
    for (const r of l.rings) {
      for (const [k, z] of [['bottom', l.z0], ['top', l.z1]]) {
        const pts = r[k].map(p => project(p[0], p[1], z));
        pts.forEach((p, j) => line(p, pts[(j + 1) % pts.length]));
      }
      for (let j = 0; j < r.bottom.length; j += r.ruled_every) {
        line(project(r.bottom[j][0], r.bottom[j][1], l.z0), project(r.top[j][0], r.top[j][1], l.z1));
      }
    }
    ctx.stroke();
  });
}
canvas.addEventListener('pointerdown', e => { drag = [e.clientX, e.clientY]; });
window.addEventListener('pointerup', () => { drag = null; });
window.addEventListener('pointermove', e => {
  if (!drag) return;
  yaw += (e.clientX - drag[0]) * 0.01; pitch = Math.max(-1.5, Math.min(1.5, pitch + (e.clientY - drag[1]) * 0.01));
  drag = [e.clientX, e.clientY]; draw();
});
draw();
)JS";

std::string escape(std::string s) {
  std::string out;
  for (char c : s) out += c == '<' ? std::string("&lt;") : c == '&' ? std::string("&amp;") : std::string(1, c);
  return out;
}

}  // namespace

std::string lamination_html(const Lamination& lam, const std::vector<Sheet>& sheets, const WaterjetProcess& process, const LaminateMeta& meta) {
  std::string rows;
  for (const auto& l : lam.layers) {
    rows += fmt::format("<tr><td>{}</td><td>{:.3f}</td><td>{:g}</td><td>{}</td><td>{:.4f}</td><td>{:.3f}</td><td>{}/{}/{}</td><td>{}</td></tr>\n", l.index,
                        l.z_bottom_mm, l.thickness_mm, l.subslices, l.area_deviation, l.max_gap_mm, l.convex_samples, l.concave_samples,
                        l.straight_samples, l.at_jet_limit);
  }
  std::string sheet_blocks;
  for (const auto& s : sheets) {
    sheet_blocks += fmt::format("<figure><figcaption>sheet {} — {:g} mm, {} pieces, {:.1f} % used, {}</figcaption>{}</figure>\n", s.index, s.thickness_mm,
                                s.pieces.size(), 100.0 * s.utilisation, escape(s.index < meta.programs.size() ? meta.programs[s.index] : ""),
                                sheet_svg(lam, s, process));
  }
  std::string stack = stack_json(lam).dump();
  std::string safe_stack;
  for (char c : stack) safe_stack += c == '<' ? std::string("\\u003c") : std::string(1, c);
  return fmt::format(R"(<!doctype html>
<html><head><meta charset="utf-8"><title>polyaxis laminate — {part}</title>
<style>body{{font-family:sans-serif;margin:1.5em;color:#222}} table{{border-collapse:collapse}} td,th{{border:1px solid #ccc;padding:2px 6px;text-align:right}}
figure{{display:inline-block;margin:0.5em;vertical-align:top}} figure svg{{width:360px;height:auto;border:1px solid #ccc}} canvas{{border:1px solid #ccc;cursor:grab}}</style></head>
<body>
<h1>Lamination of {part}</h1>
<p>{layers} layers from the stock {stock} mm (area deviation ≤ {dev:g}, jet within {jet:g}°), on {sheets} sheets; machine {machine}, process {process}.</p>
<p>Symmetric difference with the part: sloped edges <b id="sloped">{sloped:.1f} mm³</b>, vertical edges at the same layers <b id="stepped">{stepped:.1f} mm³</b>,
vertical edges that keep all the material (no gouge, as the sloped edges) <b id="covering">{covering:.1f} mm³</b> (part {volume:.1f} mm³).</p>
<h2>The stack (drag to turn)</h2>
<canvas id="view" width="720" height="520"></canvas>
<h2>Sheets</h2>
{sheet_blocks}
<h2>Layers</h2>
<table><tr><th>layer</th><th>bottom mm</th><th>thickness mm</th><th>sub-slices</th><th>area deviation</th><th>largest gap mm</th><th>convex/concave/straight samples</th><th>at jet limit</th></tr>
{rows}</table>
<script type="application/json" id="stack">{stack}</script>
<script>{script}</script>
</body></html>
)",
                     fmt::arg("part", escape(meta.part)), fmt::arg("layers", lam.layers.size()), fmt::arg("stock", fmt::join(meta.sheets_mm, ", ")),
                     fmt::arg("dev", meta.area_deviation), fmt::arg("jet", meta.max_jet_angle_deg), fmt::arg("sheets", sheets.size()),
                     fmt::arg("machine", escape(meta.machine)), fmt::arg("process", escape(meta.process)), fmt::arg("sloped", lam.sloped_deviation_mm3),
                     fmt::arg("stepped", lam.stepped_deviation_mm3), fmt::arg("covering", lam.covering_deviation_mm3), fmt::arg("volume", lam.part_volume_mm3), fmt::arg("sheet_blocks", sheet_blocks),
                     fmt::arg("rows", rows), fmt::arg("stack", safe_stack), fmt::arg("script", kPageScript));
}

}  // namespace polyaxis::lamination
