#include "branches.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <set>

#include "polyaxis/analysis/skeleton.h"
#include "polyaxis/core/tolerances.h"
#include "polyaxis/mesh/distance.h"
#include "polyaxis/mesh/plane_cut.h"
#include "polyaxis/mesh/properties.h"
#include "polyaxis/mesh/self_intersections.h"
#include "polyaxis/mesh/tube.h"

namespace polyaxis::planner::detail {

namespace {

using analysis::SkeletonEdge;
using core::Vec3;
using analysis::SkeletonGraph;

// POLY resampled every STEP_MM of its length (its ends kept).
std::vector<Vec3> resampled(const std::vector<Vec3>& poly, double step_mm) {
  double length = 0.0;
  for (std::size_t i = 1; i < poly.size(); ++i) length += core::norm(poly[i] - poly[i - 1]);
  const int n = std::max(1, static_cast<int>(std::ceil(length / step_mm)));
  std::vector<Vec3> out{poly.front()};
  std::size_t seg = 1;
  double done = 0.0;  // length of poly up to poly[seg - 1]
  for (int k = 1; k < n; ++k) {
    const double at = length * k / n;
    while (seg + 1 < poly.size() && done + core::norm(poly[seg] - poly[seg - 1]) < at) done += core::norm(poly[seg] - poly[seg - 1]), ++seg;
    const double l = core::norm(poly[seg] - poly[seg - 1]);
    const double u = l > 0.0 ? std::clamp((at - done) / l, 0.0, 1.0) : 0.0;
    out.push_back(poly[seg - 1] + (poly[seg] - poly[seg - 1]) * u);
  }
  out.push_back(poly.back());
  return out;
}

// POLY's inner points averaged over WINDOW points either side (a voxel chain's steps smoothed).
std::vector<Vec3> smoothed(const std::vector<Vec3>& poly, int window) {
  std::vector<Vec3> out = poly;
  const int n = static_cast<int>(poly.size());
  for (int i = 1; i + 1 < n; ++i) {
    const int w = std::min({window, i, n - 1 - i});
    Vec3 sum{0, 0, 0};
    for (int j = i - w; j <= i + w; ++j) sum = sum + poly[static_cast<std::size_t>(j)];
    out[static_cast<std::size_t>(i)] = sum / static_cast<double>(2 * w + 1);
  }
  return out;
}

// P moved, in the plane through it normal to T, to the deepest point of the part near it (the
// centre of a round limb's section); its depth (distance to SURFACE, > 0 inside) in DEPTH.
Vec3 centred(const mesh::SurfaceDistance& surface, Vec3 p, Vec3 t, double& depth, bool& across) {
  mesh::Nearest n = surface.nearest(p);
  across = std::fabs(core::dot(n.normal, t)) < kAcrossCos;
  depth = -n.signed_mm;
  double step = std::max(0.25 * std::fabs(depth), 0.05);
  for (int it = 0; it < 60 && step > 1e-3; ++it) {
    Vec3 away = p - n.point;
    away = away - t * core::dot(away, t);
    if (core::norm(away) < 1e-12 || depth <= 0.0) break;
    const Vec3 q = p + core::normalized(away) * step;
    const mesh::Nearest m = surface.nearest(q, n);
    if (-m.signed_mm > depth) {
      p = q, n = m, depth = -m.signed_mm, across = std::fabs(core::dot(n.normal, t)) < kAcrossCos;
    } else {
      step *= 0.5;
    }
  }
  return p;
}

// The unit direction along POLY from its start (FROM_START) or into its end, over about SPAN_MM.
Vec3 end_tangent(const std::vector<Vec3>& poly, bool from_start, double span_mm) {
  const std::size_t n = poly.size();
  Vec3 a = from_start ? poly.front() : poly.back(), b = a;
  double walked = 0.0;
  for (std::size_t k = 1; k < n && walked < span_mm; ++k) {
    const Vec3 next = from_start ? poly[k] : poly[n - 1 - k];
    walked += core::norm(next - b);
    b = next;
  }
  return from_start ? core::normalized(b - a) : core::normalized(a - b);
}

// A chain of skeleton edges that the trunk runs along: the edges' polylines end to end, and
// whether each end is free (a skeleton end: the limb's end face lies about a radius beyond it).
struct Chain {
  std::vector<Vec3> polyline;
  bool free_start = false, free_end = false;
};

// The tube of CHAIN: its voxel chain smoothed and resampled, each point centred in the part
// (SURFACE) in the plane across the chain; through the inscribed ball of a branch node (JOINTS,
// centre and radius), where the junction's bulge would pull the points off the limb's axis, a cubic
// from the centred point before to the one after (ended before it where the chain ends there); near
// a free end, where the end face is the nearest surface, the points left out and the tube run on
// past the end. Each ball grown to hold the tessellated limb (kTubeSides, kTubeMarginBeads).
// kInfeasible where the chain leaves the part, the limb is not round or the tube crosses itself.
core::Result<mesh::Mesh> chain_tube(const SkeletonGraph& g, const Chain& chain, const std::vector<std::pair<Vec3, double>>& joints,
                                     const mesh::SurfaceDistance& surface, double bead_mm) {
  const double voxel = g.voxel_mm;
  std::vector<Vec3> axis = resampled(smoothed(chain.polyline, kSmoothVoxels), kStepVoxels * voxel);
  if (axis.size() < 2) return core::make_error(core::ErrorCode::kInfeasible, "a skeleton chain shorter than a voxel");
  const std::vector<Vec3> raw = axis;
  std::vector<char> in_joint(axis.size()), across(axis.size());
  for (std::size_t i = 0; i < axis.size(); ++i) {
    in_joint[i] = std::any_of(joints.begin(), joints.end(), [&](const auto& j) { return core::norm(raw[i] - j.first) < j.second; });
  }
  std::vector<double> depth(axis.size(), 0.0);
  for (std::size_t i = 0; i < axis.size(); ++i) {
    const Vec3 t = core::normalized(raw[std::min(i + 1, raw.size() - 1)] - raw[i > 0 ? i - 1 : 0]);
    bool side = true;
    if (in_joint[i]) {
      depth[i] = -surface.nearest(raw[i]).signed_mm;
    } else {
      axis[i] = centred(surface, raw[i], t, depth[i], side);
    }
    across[i] = side;
    if (!(depth[i] > 0.0)) return core::make_error(core::ErrorCode::kInfeasible, "the skeleton leaves the part");
  }
  // Through a joint the axis is the cubic (Hermite) from the centred point before it to the one
  // after, along their tangents: an arm's arc carried on through the bulge.
  for (std::size_t i = 0; i < axis.size();) {
    if (!in_joint[i]) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < axis.size() && in_joint[j]) ++j;
    if (i >= 2 && j + 1 < axis.size()) {
      const Vec3 p0 = axis[i - 1], p1 = axis[j], span = p1 - p0;
      const double l = core::norm(span);
      const Vec3 t0 = core::normalized(axis[i - 1] - axis[i - 2]) * l, t1 = core::normalized(axis[j + 1] - axis[j]) * l;
      for (std::size_t k = i; k < j; ++k) {
        const double u = static_cast<double>(k - i + 1) / static_cast<double>(j - i + 1), u2 = u * u, u3 = u2 * u;
        axis[k] = p0 * (2 * u3 - 3 * u2 + 1) + t0 * (u3 - 2 * u2 + u) + p1 * (-2 * u3 + 3 * u2) + t1 * (u3 - u2);
        depth[k] = depth[i - 1] + (depth[j] - depth[i - 1]) * u;
        in_joint[k] = false;
      }
    }
    i = j;
  }
  // A joint at an end of the chain (the trunk ends at a branch point): the chain ends at the last
  // centred point before it, capped round there.
  std::size_t from = 0, to = axis.size();
  while (from < to && in_joint[from]) ++from;
  while (to > from && in_joint[to - 1]) --to;
  if (to - from < 2 || std::any_of(in_joint.begin() + static_cast<std::ptrdiff_t>(from), in_joint.begin() + static_cast<std::ptrdiff_t>(to),
                                   [](char c) { return c != 0; })) {
    return core::make_error(core::ErrorCode::kInfeasible, "a joint the trunk's axis cannot be carried through");
  }
  axis = std::vector<Vec3>(axis.begin() + static_cast<std::ptrdiff_t>(from), axis.begin() + static_cast<std::ptrdiff_t>(to));
  depth = std::vector<double>(depth.begin() + static_cast<std::ptrdiff_t>(from), depth.begin() + static_cast<std::ptrdiff_t>(to));
  across = std::vector<char>(across.begin() + static_cast<std::ptrdiff_t>(from), across.begin() + static_cast<std::ptrdiff_t>(to));
  const std::vector<Vec3> kept_raw(raw.begin() + static_cast<std::ptrdiff_t>(from), raw.begin() + static_cast<std::ptrdiff_t>(to));
  // Near a free end the nearest surface is the end face, which says nothing of where the axis runs:
  // those points are left out, and the tube runs on from the last that the limb's side centred.
  std::size_t first = 0, last = axis.size() - 1;
  while (chain.free_start && first < last && !across[first]) ++first;
  while (chain.free_end && last > first && !across[last]) --last;
  if (last <= first) return core::make_error(core::ErrorCode::kInfeasible, "a chain with no point centred by the limb's side");
  const double start_gap = core::norm(kept_raw.front() - kept_raw[first]), end_gap = core::norm(kept_raw.back() - kept_raw[last]);
  axis = std::vector<Vec3>(axis.begin() + static_cast<std::ptrdiff_t>(first), axis.begin() + static_cast<std::ptrdiff_t>(last) + 1);
  depth = std::vector<double>(depth.begin() + static_cast<std::ptrdiff_t>(first), depth.begin() + static_cast<std::ptrdiff_t>(last) + 1);
  std::vector<double> radii(axis.size());
  for (std::size_t i = 0; i < axis.size(); ++i) radii[i] = depth[i] / std::cos(std::numbers::pi / kTubeSides) + kTubeMarginBeads * bead_mm;
  // Runs on past a free end bending as the axis bends over its last two steps (an arm's arc goes
  // on to its end face), in steps of the last one.
  // A round limb's side lies all round within the margin of the tube; a wall's or a rib's does not
  // (the ball inscribed in a wall is as thick as the wall, and the tube pokes out of it).
  std::size_t hugging = 0, rings = 0;
  for (std::size_t i = 0; i < axis.size(); ++i) {
    if (depth[i] <= 0.0) continue;  // bridged through a joint
    const Vec3 t = core::normalized(axis[std::min(i + 1, axis.size() - 1)] - axis[i > 0 ? i - 1 : 0]);
    const Vec3 u = core::normalized(core::cross(t, std::fabs(t.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0})), v = core::cross(t, u);
    for (int k = 0; k < kRoundSamples; ++k) {
      const double a = 2.0 * std::numbers::pi * k / kRoundSamples;
      const Vec3 q = axis[i] + (u * std::cos(a) + v * std::sin(a)) * radii[i];
      ++rings;
      if (std::fabs(surface.nearest(q).signed_mm) <= kRoundShare * radii[i] + kTubeMarginBeads * bead_mm) ++hugging;
    }
  }
  if (rings == 0 || static_cast<double>(hugging) < kRoundHugShare * static_cast<double>(rings)) {
    return core::make_error(core::ErrorCode::kInfeasible, fmt::format("the trunk's limbs are not round ({:.0f} % of the tube's side lies on the part's)",
                                                                      rings == 0 ? 0.0 : 100.0 * static_cast<double>(hugging) / static_cast<double>(rings)));
  }
  auto extend = [&](bool at_start) {
    if (at_start) std::reverse(axis.begin(), axis.end()), std::reverse(radii.begin(), radii.end());
    const std::size_t n = axis.size();
    const double r = radii.back(), run = (at_start ? start_gap : end_gap) + kTubeEndRadii * r;
    Vec3 t = core::normalized(axis[n - 1] - axis[n - 2]);
    const double step = std::max(core::norm(axis[n - 1] - axis[n - 2]), 0.25 * r);
    Vec3 k{0, 0, 0};  // the turn per step: axis times sine
    double turn = 0.0;
    if (n >= 3) {
      const Vec3 before = core::normalized(axis[n - 2] - axis[n - 3]);
      k = core::cross(before, t);
      turn = std::asin(std::min(1.0, core::norm(k))) * step / std::max(core::norm(axis[n - 2] - axis[n - 3]), 1e-9);
      turn = std::min(turn, step / (kLeastBendRadii * r));  // no tighter than the tube can bend without crossing itself
      k = core::norm(k) > 1e-9 ? core::normalized(k) : Vec3{0, 0, 0};
    }
    for (double done = 0.0; done < run;) {
      t = core::normalized(t * std::cos(turn) + core::cross(k, t) * std::sin(turn) + k * (core::dot(k, t) * (1.0 - std::cos(turn))));
      const double l = std::min(step, run - done);
      axis.push_back(axis.back() + t * l), radii.push_back(r);
      done += l;
    }
    if (at_start) std::reverse(axis.begin(), axis.end()), std::reverse(radii.begin(), radii.end());
  };
  if (chain.free_start) extend(true);
  if (chain.free_end) extend(false);
  // Consecutive points that centring brought together would leave no tangent.
  std::vector<Vec3> a{axis.front()};
  std::vector<double> r{radii.front()};
  for (std::size_t i = 1; i < axis.size(); ++i) {
    if (core::norm(axis[i] - a.back()) < 0.1 * voxel) continue;
    a.push_back(axis[i]), r.push_back(radii[i]);
  }
  if (a.size() < 2) return core::make_error(core::ErrorCode::kInfeasible, "a skeleton chain shorter than a voxel");
  mesh::Mesh m = mesh::tube(a, r, kTubeSides);
  if (!mesh::self_intersecting_faces(m).empty()) {
    return core::make_error(core::ErrorCode::kInfeasible, "the tube around the trunk crosses itself (its axis bends more sharply than its radius)");
  }
  return m;
}

std::string label_of(const SkeletonGraph& g, std::uint32_t node, std::size_t branches) {
  const Vec3 p = g.nodes[node].position;
  return branches == 1 ? fmt::format("the branch leaving ({:.1f}, {:.1f}, {:.1f})", p.x, p.y, p.z)
                       : fmt::format("the {} branches leaving ({:.1f}, {:.1f}, {:.1f})", branches, p.x, p.y, p.z);
}

// The trunk's chains for BRANCH (the edges that grow from the side children): each edge not in the
// branch, carried on through branch nodes by the child that continues it (CARRIED), with the nodes
// it passes through.
struct TrunkChain {
  Chain chain;
  std::set<std::uint32_t> nodes;
};

std::vector<TrunkChain> trunk_chains(const SkeletonGraph& g, const std::vector<std::optional<std::size_t>>& carried,
                                     const std::set<std::size_t>& branch) {
  auto continues = [&](std::size_t k) { return carried[g.edges[k].from] == k; };
  std::vector<TrunkChain> out;
  for (std::size_t k = 0; k < g.edges.size(); ++k) {
    if (branch.count(k) || g.edges[k].from == g.edges[k].to || continues(k)) continue;
    TrunkChain c;
    c.chain.free_start = g.nodes[g.edges[k].from].degree == 1;
    c.nodes.insert(g.edges[k].from);
    for (std::optional<std::size_t> e = k; e && !branch.count(*e); e = carried[g.edges[*e].to]) {
      const auto& poly = g.edges[*e].polyline;
      c.chain.polyline.insert(c.chain.polyline.end(), poly.begin() + (c.chain.polyline.empty() ? 0 : 1), poly.end());
      c.chain.free_end = g.nodes[g.edges[*e].to].degree == 1;
      c.nodes.insert(g.edges[*e].to);
    }
    out.push_back(std::move(c));
  }
  return out;
}

// The side edges SIDES and all that grows from them.
std::set<std::size_t> grown_from(const SkeletonGraph& g, const std::vector<std::size_t>& sides) {
  std::set<std::uint32_t> beyond;
  std::set<std::size_t> branch(sides.begin(), sides.end());
  for (const std::size_t c : sides) beyond.insert(g.edges[c].to);
  for (bool grew = true; grew;) {
    grew = false;
    for (std::size_t k = 0; k < g.edges.size(); ++k) {
      if (!branch.count(k) && beyond.count(g.edges[k].from)) branch.insert(k), beyond.insert(g.edges[k].to), grew = true;
    }
  }
  return branch;
}

// TRUNK and REST (the part within and outside the tubes) with the pieces of REST that hold no
// point of BRANCH's skeleton edges (the foot, a cap: parts of the trunk the tubes left out) united
// with TRUNK; REST keeps the others. kInfeasible when no piece holds a branch, or the union fails.
core::Result<std::pair<mesh::Mesh, mesh::Mesh>> branches_only(const SkeletonGraph& g, const std::set<std::size_t>& branch, mesh::Mesh trunk,
                                                             const mesh::Mesh& rest) {
  std::vector<Vec3> points;
  for (const std::size_t k : branch) points.insert(points.end(), g.edges[k].polyline.begin(), g.edges[k].polyline.end());
  std::vector<mesh::Mesh> kept{std::move(trunk)};
  mesh::Mesh branches;
  for (mesh::Mesh& piece : mesh::connected_solids(rest)) {
    const core::Box3 box = mesh::bounding_box(piece);
    const bool holds = std::any_of(points.begin(), points.end(), [&](Vec3 p) {
      return p.x >= box.min.x && p.x <= box.max.x && p.y >= box.min.y && p.y <= box.max.y && p.z >= box.min.z && p.z <= box.max.z &&
             mesh::winding_number(piece, p) > core::kInsideWindingNumber;
    });
    if (!holds) {
      kept.push_back(std::move(piece));
      continue;
    }
    const auto base = static_cast<std::uint32_t>(branches.vertices.size());
    branches.vertices.insert(branches.vertices.end(), piece.vertices.begin(), piece.vertices.end());
    for (const auto& t : piece.triangles) branches.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  }
  if (branches.triangles.empty()) return core::make_error(core::ErrorCode::kInfeasible, "no piece outside the trunk's tubes holds a branch");
  if (kept.size() == 1) return std::pair{std::move(kept.front()), std::move(branches)};
  auto united = mesh::unite(kept);
  if (!united) return core::make_error(core::ErrorCode::kInfeasible, fmt::format("the trunk and its pieces the tubes left out: {}", united.error().message));
  return std::pair{std::move(united.value()), std::move(branches)};
}

// The split of PART at NODE with the side edges SIDES as branches (and all that grows from them).
// Every trunk chain is tubed (chain_tube); a chain that cannot be (a foot's flat disc, a rib: not
// round) is left out, and only the sides leaving a tubed chain stay branches, so long as one does.
// Where chains were left out, the pieces of the part outside the tubes that hold none of the
// branches' skeleton (the foot, a cap) go back to the trunk.
TrunkSplit split_at(const mesh::RepairedMesh& part, const SkeletonGraph& g, const std::vector<std::optional<std::size_t>>& carried,
                    const std::vector<std::pair<Vec3, double>>& joints, const mesh::SurfaceDistance& surface, double bead_mm,
                    std::uint32_t node, std::vector<std::size_t> sides) {
  TrunkSplit split;
  split.label = label_of(g, node, sides.size());
  std::vector<mesh::Mesh> tubes;
  std::set<std::uint32_t> tubed_nodes;
  std::string left_out;
  for (TrunkChain& c : trunk_chains(g, carried, grown_from(g, sides))) {
    auto t = chain_tube(g, c.chain, joints, surface, bead_mm);
    if (!t) {
      if (left_out.empty()) left_out = t.error().message;
      continue;
    }
    tubes.push_back(std::move(t.value()));
    tubed_nodes.insert(c.nodes.begin(), c.nodes.end());
  }
  std::erase_if(sides, [&](std::size_t k) { return !tubed_nodes.count(g.edges[k].from); });
  if (!sides.empty()) split.label = label_of(g, node, sides.size());
  if (tubes.empty() || sides.empty()) {
    split.refused = !left_out.empty() ? left_out : tubes.empty() ? "no trunk: every edge is a branch" : "no branch leaves a round limb";
    return split;
  }
  auto tubes_united = tubes.size() == 1 ? core::Result<mesh::Mesh>(std::move(tubes.front())) : mesh::unite(tubes);
  auto rest = tubes_united ? mesh::difference(part.mesh, tubes_united.value()) : core::Result<mesh::Mesh>(tubes_united.error());
  auto trunk = tubes_united ? mesh::intersection(part.mesh, tubes_united.value()) : core::Result<mesh::Mesh>(tubes_united.error());
  if (!rest || !trunk) {
    split.refused = !rest ? rest.error().message : trunk.error().message;
    return split;
  }
  if (rest.value().triangles.empty() || trunk.value().triangles.empty()) {
    split.refused = rest.value().triangles.empty() ? "the trunk's tubes hold the whole part" : "the tubes miss the part";
    return split;
  }
  if (!left_out.empty()) {
    auto kept = branches_only(g, grown_from(g, sides), std::move(trunk.value()), rest.value());
    if (!kept) {
      split.refused = kept.error().message;
      return split;
    }
    trunk = std::move(kept.value().first), rest = std::move(kept.value().second);
  }
  split.trunk = std::move(trunk.value()), split.rest = std::move(rest.value()), split.tubes = std::move(tubes_united.value());
  return split;
}

}  // namespace

std::vector<TrunkSplit> trunk_splits(const mesh::RepairedMesh& part, double bead_mm) {
  std::vector<TrunkSplit> out;
  auto graph = analysis::skeleton(part.mesh);
  if (!graph || graph.value().roots.size() != 1) return out;
  const SkeletonGraph& g = graph.value();
  const mesh::SurfaceDistance surface(part.mesh);
  // At each branch point the child edge turning least from the edge into it carries that edge on.
  std::vector<std::optional<std::size_t>> carried(g.nodes.size());
  std::vector<std::pair<Vec3, double>> joints;  // the branch points' balls, their bulge
  for (std::uint32_t node = 0; node < g.nodes.size(); ++node) {
    std::vector<std::size_t> in, children;
    for (std::size_t k = 0; k < g.edges.size(); ++k) {
      if (g.edges[k].from == g.edges[k].to) continue;
      if (g.edges[k].to == node) in.push_back(k);
      if (g.edges[k].from == node) children.push_back(k);
    }
    if (g.nodes[node].degree >= 3) joints.emplace_back(g.nodes[node].position, kJointRadii * g.nodes[node].radius_mm + g.voxel_mm);
    if (in.size() != 1 || children.size() < 2) continue;
    const double span = 2.0 * std::max(g.nodes[node].radius_mm, g.voxel_mm);
    const Vec3 into = end_tangent(g.edges[in.front()].polyline, false, span);
    carried[node] = *std::max_element(children.begin(), children.end(), [&](std::size_t a, std::size_t b) {
      return core::dot(into, end_tangent(g.edges[a].polyline, true, span)) < core::dot(into, end_tangent(g.edges[b].polyline, true, span));
    });
  }
  auto children_of = [&](std::uint32_t node) {
    std::vector<std::size_t> children;
    for (std::size_t k = 0; k < g.edges.size(); ++k) {
      if (g.edges[k].from == node && g.edges[k].to != node) children.push_back(k);
    }
    return children;
  };
  // Branch points in order from the root (edges run away from it, breadth-first).
  std::size_t points_tried = 0;
  for (std::uint32_t node = 0; node < g.nodes.size() && points_tried < kMaxTrunkSplits; ++node) {
    if (!carried[node]) continue;
    const std::vector<std::size_t> children = children_of(node);
    // A branch point none of whose side children is a round limb (a spur of the skeleton in a flat
    // foot or flange) is passed over.
    const bool round_side = std::any_of(children.begin(), children.end(), [&](std::size_t c) {
      if (c == *carried[node]) return false;
      Chain side;
      side.polyline = g.edges[c].polyline;
      side.free_end = g.nodes[g.edges[c].to].degree == 1;
      return chain_tube(g, side, joints, surface, bead_mm).ok();
    });
    if (!round_side) continue;
    ++points_tried;
    // The branches tried: every child but the one carrying the trunk on; then every child, the
    // trunk ending at the node (a column with arms all round; a Y fork, whose arms both leave the
    // column at an angle and stand close: grown one on the other, the head building the second
    // strikes the first).
    std::vector<std::size_t> sides;
    for (const std::size_t c : children) {
      if (c != *carried[node]) sides.push_back(c);
    }
    out.push_back(split_at(part, g, carried, joints, surface, bead_mm, node, sides));
    out.push_back(split_at(part, g, carried, joints, surface, bead_mm, node, children));
  }
  return out;
}

}  // namespace polyaxis::planner::detail
