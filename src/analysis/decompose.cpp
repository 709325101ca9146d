// Decomposition into support-free regions: Ruan, Eiamsa-ard, Liou 2006, §4.1 (splitting planar
// faces found from the centroidal axis's break links), with every split checked by the overhang it
// leaves (SPEC §2.3) and the build direction of each region chosen by that overhang.
#include "polyaxis/analysis/decompose.h"

#include <fmt/format.h>

#include <algorithm>
#include <numbers>
#include <cmath>
#include <memory>
#include <span>
#include <tbb/parallel_for.h>

#include "polyaxis/core/progress.h"
#include "polyaxis/mesh/plane_cut.h"
#include "polyaxis/mesh/properties.h"
#include "polyaxis/mesh/topology.h"
#include "polyaxis/mesh/self_intersections.h"
#include "build_order.h"
#include "patch_split.h"
#include "region_geometry.h"
#include "split_screen.h"

namespace polyaxis::analysis {
namespace {

using detail::angle_deg;
using detail::kOnBaseMm;
using detail::kUnsupportedNoiseMm2;
using detail::PlanarFace;

// A splitting face is a real planar face of the part, not one facet of a tessellated curve: it
// has at least this many facets and this much area. At most kMaxFaceCandidates faces, the nearest
// to the link, are tried per link.
constexpr std::uint32_t kMinSplitFaceFacets = 2;
constexpr double kMinSplitFaceMm2 = 1.0;
constexpr std::size_t kMaxFaceCandidates = 12;
// Planes across the axis: at most this many per direction, stepped back from the branch's first
// node towards the link's start by the axis increment.
constexpr int kMaxAxisPlanes = 16;
// A face within this angle of facing straight down, and at least this large, is a candidate for
// the plate (the root's base).
constexpr double kPlateFaceDeg = 1.0;
constexpr double kMinPlateFaceMm2 = 1.0;
// A splitting face within this of a link's extent still overlaps it (Ruan Eq. 5), mm.
constexpr double kLinkOverlapMm = 1e-6;
// At most this many nodes of a branch stand for it (where its material is), evenly spread.
constexpr std::size_t kMaxTargets = 8;
// A split must remove at least this much overhang, mm², and at most this many of a link's best
// screened candidates are cut exactly.
constexpr double kMinGainMm2 = 2.0 * kUnsupportedNoiseMm2;
constexpr std::size_t kExactTries = 3;
// Overhang left by the links: at most this many patch regions in all, and the largest this many
// patches of a region tried.
constexpr int kMaxPatchSplits = 12;
constexpr std::size_t kMaxPatchesPerRegion = 4;
// Cosines closer than this are a tie (about 0.1° near 0°, 1e-6 in general).
constexpr double kSameCos = 1e-6;
// Of two children, one whose surface is smaller by more than this share is the smaller.
constexpr double kClearlySmallerShare = 0.1;
using detail::kFaceCutOffsetMm;
// A piece of a cut whose mean thickness (twice its volume over its surface: a slab's thickness) is
// below this share of the least region thickness is a film: a plane moved kFaceCutOffsetMm off a
// face the child stands on leaves the face's whole skin with the parent, which then seems to hold
// up the child while nothing can be deposited that thin.
constexpr double kFilmShare = 1.0;

struct Candidate {
  Vec3 point, normal;  // the plane; normal towards the child
  std::string rule;
  detail::Screened screened;
};

// Whether the split removing GAIN_A mm² of overhang with candidate A (of link DIR_A) beats B: more
// overhang removed (beyond the noise), then Ruan's splitting faces before planes across the axis,
// then the child that takes clearly less of the part's surface (a plane that cuts the branch off
// where it leaves its father, not one that also takes a slab of the father: a link's direction
// bends towards the father's axis, and the plane across it can run down through the father to the
// plate), then the plane most nearly across its link (Ruan's criterion 1), then the child built
// closest to its base's normal (flat first layers).
bool preferred(double gain_a, const Candidate& a, Vec3 dir_a, double gain_b, const Candidate& b, Vec3 dir_b) {
  if (std::fabs(gain_a - gain_b) > kUnsupportedNoiseMm2) return gain_a > gain_b;
  const bool face_a = a.rule == "planar face", face_b = b.rule == "planar face";
  if (face_a != face_b) return face_a;
  const double area_a = a.screened.child_area_mm2, area_b = b.screened.child_area_mm2;
  if (area_a < (1.0 - kClearlySmallerShare) * area_b) return true;
  if (area_b < (1.0 - kClearlySmallerShare) * area_a) return false;
  const double across_a = std::fabs(core::dot(a.normal, dir_a)), across_b = std::fabs(core::dot(b.normal, dir_b));
  if (std::fabs(across_a - across_b) > kSameCos) return across_a > across_b;
  return core::dot(a.screened.child_direction, a.normal) > core::dot(b.screened.child_direction, b.normal) + kSameCos;
}

struct SplitLink {
  std::size_t link = 0;
  Vec3 from, to, dir, father_dir, branch_dir;
  std::vector<Vec3> targets;  // nodes beyond the link
  bool done = false;
};

// The links that may start a region: C¹ breaks (Ruan) and the first link of every child branch
// (its junction with its father), each with the nodes reached beyond it.
std::vector<SplitLink> split_links(const CentroidalAxis& axis) {
  std::vector<std::vector<std::uint32_t>> next(axis.nodes.size());
  for (const AxisLink& l : axis.links) next[l.from].push_back(l.to);
  std::vector<SplitLink> out;
  for (std::size_t li = 0; li < axis.links.size(); ++li) {
    const AxisLink& link = axis.links[li];
    const bool junction = axis.nodes[link.from].branch != axis.nodes[link.to].branch;
    if (!link.is_break && !junction) continue;
    SplitLink s;
    s.link = li;
    s.from = axis.nodes[link.from].position;
    s.to = axis.nodes[link.to].position;
    s.dir = core::normalized(s.to - s.from);
    s.father_dir = s.dir;
    for (const AxisLink& l : axis.links) {
      if (l.to == link.from) s.father_dir = core::normalized(axis.nodes[l.to].position - axis.nodes[l.from].position);
    }
    std::vector<std::uint32_t> reach{link.to};
    std::vector<char> seen(axis.nodes.size(), 0);
    seen[link.to] = 1;
    for (std::size_t i = 0; i < reach.size(); ++i) {
      for (std::uint32_t n : next[reach[i]]) {
        if (!seen[n]) seen[n] = 1, reach.push_back(n);
      }
    }
    const std::size_t step = (reach.size() + kMaxTargets - 1) / kMaxTargets;
    for (std::size_t i = 0; i < reach.size(); i += step) s.targets.push_back(axis.nodes[reach[i]].position);
    if (reach.size() > 1) s.targets.push_back(axis.nodes[reach.back()].position);
    // The direction the branch grows in: from the link's end to the node beyond it.
    s.branch_dir = s.dir;
    if (!next[link.to].empty()) s.branch_dir = core::normalized(axis.nodes[next[link.to][0]].position - s.to);
    out.push_back(std::move(s));
  }
  return out;
}

// Sum of the distances from TARGETS to the solid M (0 for a target inside).
double distance_sum(const mesh::Mesh& m, const std::vector<Vec3>& targets) {
  double sum = 0.0;
  for (const Vec3& t : targets) sum += detail::distance_to_solid(m, t);
  return sum;
}

std::pair<double, double> extent_along(const mesh::Mesh& m, const PlanarFace& f, Vec3 d) {
  double lo = INFINITY, hi = -INFINITY;
  for (std::uint32_t id : f.facet_ids) {
    for (int k = 0; k < 3; ++k) {
      const double c = core::dot(m.corner(id, k), d);
      lo = std::min(lo, c), hi = std::max(hi, c);
    }
  }
  return {lo, hi};
}

// Candidate splitting planes for link S, best-first by their origin: Ruan's splitting faces (concave
// boundary edge, normal within the tolerance of the link or its father link, projection overlapping
// the link: Eq. 5), then planar faces with a concave edge within max_base_tilt_deg of the link (the
// child then grows along the link from a tilted base), then planes across the link and across the
// branch's first link, from the branch's first node back towards the link's start.
std::vector<Candidate> candidates_for(const SplitLink& s, const mesh::Mesh& part, const std::vector<PlanarFace>& faces,
                                      double increment_mm, double tolerance_deg, double alpha_deg) {
  std::vector<Candidate> out;
  Vec3 centre{};
  for (const Vec3& t : s.targets) centre = centre + t;
  centre = centre / static_cast<double>(s.targets.size());
  auto add = [&](Vec3 point, Vec3 normal, const char* rule, double offset_mm) {
    normal = core::normalized(normal);
    if (core::dot(centre - point, normal) < 0.0) normal = normal * -1.0;
    out.push_back({point + normal * offset_mm, normal, rule, {}});
  };
  auto overlaps = [&](const PlanarFace& f, Vec3 d) {
    const auto [flo, fhi] = extent_along(part, f, d);
    const double a = core::dot(s.from, d), b = core::dot(s.to, d);
    return fhi >= std::min(a, b) - kLinkOverlapMm && flo <= std::max(a, b) + kLinkOverlapMm;
  };
  std::vector<const PlanarFace*> ruan, tilted;
  for (const PlanarFace& f : faces) {
    if (!f.concave_edge || f.facets < kMinSplitFaceFacets || f.area_mm2 < kMinSplitFaceMm2) continue;
    bool is_ruan = false;
    for (const Vec3 d : {s.dir, s.father_dir}) {
      if (std::min(angle_deg(f.normal, d), angle_deg(f.normal * -1.0, d)) <= tolerance_deg && overlaps(f, d)) is_ruan = true;
    }
    if (is_ruan) {
      ruan.push_back(&f);
    } else if (angle_deg(f.normal, s.dir) < detail::max_base_tilt_deg(alpha_deg) && overlaps(f, s.dir)) {
      tilted.push_back(&f);
    }
  }
  // Nearest first to where the branch leaves its father (the link's end).
  for (auto* list : {&ruan, &tilted}) {
    std::stable_sort(list->begin(), list->end(), [&](const PlanarFace* a, const PlanarFace* b) {
      return std::fabs(core::dot(a->point - s.to, a->normal)) < std::fabs(core::dot(b->point - s.to, b->normal));
    });
    if (list->size() > kMaxFaceCandidates) list->resize(kMaxFaceCandidates);
    for (const PlanarFace* f : *list) add(f->point, f->normal, "planar face", kFaceCutOffsetMm);
  }
  const double length = core::norm(s.to - s.from);
  const double step = std::max(increment_mm, length / kMaxAxisPlanes);
  for (const Vec3 d : {s.dir, core::normalized(s.dir + s.branch_dir), s.branch_dir}) {
    for (int k = 0; k <= kMaxAxisPlanes && k * step <= length + kLinkOverlapMm; ++k) add(s.to - s.dir * (k * step), d, "fallback plane", 0.0);
  }
  return out;
}

struct ExactSplit {
  mesh::Mesh parent, child;
  Vec3 direction;
  double unsupported_mm2 = INFINITY;  // parent + child
  double child_mm2 = INFINITY;
  std::size_t child_mid_air = 0;  // corners where the child's first layer starts on nothing (mid_air_starts)
};

struct ExactRules {
  bool child_must_stand = false;  // a child left with overhang ends the split before the parent is built
  bool keep_base = false;         // a child with facets on the host's base is refused
  detail::DirectionCone reach;    // the child's build direction stays inside it
  double min_thickness_mm = 0.0;  // a piece thinner than this on average is refused (is_film)
  // DecomposeOptions::least_height_mm (null or empty: not checked), over the plane (PLATE_POINT, UP):
  // a child reaching below the height its direction needs is refused.
  const std::function<double(double)>* least_height = nullptr;
  Vec3 plate_point, up{0, 0, 1};
};

// Whether the head can lay CHILD, built along unit DIRECTION, with RULES' plate under it: every
// vertex at least the height the direction needs above the plate (kOnBaseMm spared).
bool head_clears_plate(const mesh::Mesh& child, Vec3 direction, const ExactRules& rules) {
  if (rules.least_height == nullptr || !*rules.least_height) return true;
  const Vec3 up = core::normalized(rules.up);
  const double need = (*rules.least_height)(std::acos(std::clamp(core::dot(direction, up), -1.0, 1.0)));
  if (need <= kOnBaseMm) return true;
  return std::all_of(child.vertices.begin(), child.vertices.end(),
                     [&](const Vec3& v) { return core::dot(v - rules.plate_point, up) >= need - kOnBaseMm; });
}

// Whether PIECE is thinner on average than kFilmShare · MIN_THICKNESS_MM: twice its volume over its
// surface, which is a slab's thickness and less for any other shape of that volume and surface.
bool is_film(const mesh::Mesh& piece, double min_thickness_mm) {
  const double area = mesh::surface_area(piece);
  return area > 0.0 && 2.0 * mesh::signed_volume(piece) < kFilmShare * min_thickness_mm * area;
}

// Cuts HOST by the plane (POINT, NORMAL towards the child; capped); the child is the piece on the
// normal side nearest TARGETS, every other piece stays with the parent, put back onto it as one
// solid (mesh::cut_off). The child's direction is the best of STARTS and the search from them. RULES
// refuse some children (before the parent is built, where they can).
std::optional<ExactSplit> exact_split(const Region& host, Vec3 point, Vec3 normal, const std::vector<Vec3>& targets,
                                      std::span<const Vec3> starts, double alpha_deg, const ExactRules& rules = {}) {
  ExactSplit out;
  const Vec3 hb = core::normalized(host.base_normal);
  auto cut = mesh::cut_off(host.mesh, point, normal, [&](const std::vector<mesh::Mesh>& pieces) -> std::optional<std::size_t> {
    std::size_t pick = 0;
    double best = INFINITY;
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      const double d = distance_sum(pieces[i], targets);
      if (d < best) best = d, pick = i;
    }
    const mesh::Mesh& child = pieces[pick];
    if (rules.keep_base) {
      for (std::size_t f = 0; f < child.triangles.size(); ++f) {
        bool on_base = true;
        for (int k = 0; k < 3; ++k) on_base = on_base && std::fabs(core::dot(child.corner(f, k) - host.base_point, hb)) <= kOnBaseMm;
        if (on_base) return std::nullopt;
      }
    }
    const std::vector<detail::FacetSample> facets = detail::facet_samples(child, point, normal);
    out.direction = detail::best_direction(facets, normal, starts, alpha_deg, 0.25, rules.reach);
    if (!head_clears_plate(child, out.direction, rules)) return std::nullopt;
    if (rules.child_must_stand && detail::unsupported(child, out.direction, alpha_deg, point, normal) > 0.0) return std::nullopt;
    return pick;
  });
  if (!cut) return std::nullopt;
  out.child = std::move(cut.value().child);
  out.parent = std::move(cut.value().parent);
  if (is_film(out.child, rules.min_thickness_mm) || is_film(out.parent, rules.min_thickness_mm)) return std::nullopt;
  // Counted on the child as cut, with any cavity it encloses.
  out.child_mm2 = detail::unsupported(out.child, out.direction, alpha_deg, point, normal);
  // Its own underside where it lies in the cut: nothing holds it but a film of the parent.
  if (const double on_cut = detail::underside_in_cut_mm2(host.mesh, point, normal, rules.min_thickness_mm); on_cut >= kUnsupportedNoiseMm2) out.child_mm2 += on_cut;
  if (rules.child_must_stand && out.child_mm2 > 0.0) return std::nullopt;
  out.unsupported_mm2 = detail::unsupported(out.parent, host.build_direction, alpha_deg, host.base_point, host.base_normal) + out.child_mm2;
  // Only a child that stands is looked at for starts in mid-air (one that overhangs is no patch
  // child, and the probes cost O(F) each).
  if (out.child_mm2 == 0.0) out.child_mid_air = detail::mid_air_starts(out.child, out.direction, point, normal, rules.min_thickness_mm).size();
  return out;
}

// The plate: the downward planar face where the centroidal axis's root branch starts (Ruan: the
// root branch is the body the part grows from; a part on feet starts above them), else the lowest
// such face (the larger on a tie).
const PlanarFace* plate_face(const std::vector<PlanarFace>& faces, const CentroidalAxis& axis, Vec3 up) {
  std::optional<double> start;
  for (const AxisBranch& b : axis.branches) {
    if (!b.father && !b.nodes.empty()) start = core::dot(axis.nodes[b.nodes.front()].position, up);
  }
  const double reach = std::max(axis.increment_mm, 1.0);
  const PlanarFace* lowest = nullptr;
  const PlanarFace* at_start = nullptr;
  for (const PlanarFace& f : faces) {
    if (f.area_mm2 < kMinPlateFaceMm2 || angle_deg(f.normal, up * -1.0) > kPlateFaceDeg) continue;
    const double h = core::dot(f.point, up);
    if (!lowest || h < core::dot(lowest->point, up) - kOnBaseMm ||
        (std::fabs(h - core::dot(lowest->point, up)) <= kOnBaseMm && f.area_mm2 > lowest->area_mm2)) {
      lowest = &f;
    }
    if (start && std::fabs(h - *start) <= reach &&
        (!at_start || std::fabs(h - *start) < std::fabs(core::dot(at_start->point, up) - *start) - kOnBaseMm ||
         (std::fabs(h - core::dot(at_start->point, up)) <= kOnBaseMm && f.area_mm2 > at_start->area_mm2))) {
      at_start = &f;
    }
  }
  return at_start ? at_start : lowest;
}

}  // namespace

namespace {

std::vector<BaseFace> base_faces_of(const std::vector<PlanarFace>& faces) {
  std::vector<BaseFace> out;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const PlanarFace& f = faces[i];
    if (f.area_mm2 >= kMinBaseFaceMm2) out.push_back({static_cast<std::uint32_t>(i), f.normal, f.point, f.area_mm2, f.facets});
  }
  return out;
}

}  // namespace

std::vector<BaseFace> base_faces(const mesh::Mesh& mesh) { return base_faces_of(detail::planar_faces(mesh)); }

namespace {

core::Result<BaseFace> listed_face(const std::vector<BaseFace>& faces, std::uint32_t id) {
  for (const BaseFace& f : faces) {
    if (f.id == id) return f;
  }
  return core::make_error(core::ErrorCode::kUsage,
                          fmt::format("--root-base: {} is not a planar face of at least {} mm2 (analysis.json lists them under "
                                      "\"faces\")",
                                      id, kMinBaseFaceMm2));
}

}  // namespace

core::Result<Vec3> root_direction(const mesh::Mesh& mesh, const RootBase& base, Vec3 default_up) {
  switch (base.kind) {
    case RootBase::Kind::kAuto:
    case RootBase::Kind::kLowest:
      return core::normalized(default_up);
    case RootBase::Kind::kFace: {
      auto f = listed_face(base_faces(mesh), base.face);
      if (!f) return f.error();
      return f.value().normal * -1.0;
    }
    case RootBase::Kind::kPlane:
      if (!core::is_finite(base.point) || !core::is_finite(base.normal) || core::norm(base.normal) < 1e-12) {
        return core::make_error(core::ErrorCode::kUsage, "--root-base: the plane needs a finite point and a non-zero normal");
      }
      return core::normalized(base.normal);
  }
  return core::normalized(default_up);
}

core::Result<RegionTree> decompose(const mesh::Mesh& mesh, const CentroidalAxis& axis, const DecomposeOptions& options) {
  const double alpha = options.self_supporting_deg;
  RegionTree tree;
  const std::vector<PlanarFace> faces = detail::planar_faces(mesh);
  tree.faces = base_faces_of(faces);
  auto root_dir = root_direction(mesh, options.root_base, options.root_direction);
  if (!root_dir) return root_dir.error();
  Region root;
  root.id = 0;
  root.build_direction = root_dir.value();
  root.base_normal = root.build_direction;
  root.mesh = mesh;
  const Vec3 up = root.build_direction;
  const detail::DirectionCone reach{up, std::cos(std::clamp(options.reach_deg, 0.0, 180.0) * std::numbers::pi / 180.0)};
  double lowest = INFINITY;
  for (const Vec3& v : mesh.vertices) lowest = std::min(lowest, core::dot(v, up));
  root.base_point = up * lowest;
  root.rule = "plate";
  // The base plane: the plate found from the axis, or the one pinned by options.root_base. What
  // lies on its far side (knuckles under a body, a corner poking through a base plate) becomes
  // regions built the opposite way from it.
  std::optional<Vec3> base_point;
  switch (options.root_base.kind) {
    case RootBase::Kind::kAuto:
      if (const PlanarFace* plate = plate_face(faces, axis, up)) base_point = plate->point;
      break;
    case RootBase::Kind::kLowest:
      break;
    case RootBase::Kind::kFace:
      base_point = faces[options.root_base.face].point;  // listed: root_direction checked the id
      root.rule = "root base (face)";
      break;
    case RootBase::Kind::kPlane:
      base_point = options.root_base.point;
      root.rule = "root base (plane)";
      break;
  }
  std::vector<mesh::Mesh> hanging;
  if (base_point && core::dot(*base_point, up) > lowest + kOnBaseMm) {
    auto cut = mesh::cut_by_plane(mesh, *base_point, up);
    if (!cut || cut.value().above.triangles.empty()) {
      if (options.root_base.kind == RootBase::Kind::kPlane || options.root_base.kind == RootBase::Kind::kFace) {
        return core::make_error(core::ErrorCode::kUsage, "--root-base: nothing of the part lies on the root's side of that base");
      }
    } else {
      root.mesh = std::move(cut.value().above);
      root.base_point = *base_point;
      hanging = detail::shells_of(cut.value().below);
    }
  } else if (base_point) {
    root.base_point = up * lowest;
  }
  tree.regions.push_back(std::move(root));
  // The plate the root stands on, which the head must keep clear of (DecomposeOptions::least_height_mm).
  const Vec3 plate_point = tree.regions.front().base_point, plate_up = up;
  for (mesh::Mesh& h : hanging) {
    Region r;
    r.id = static_cast<std::uint32_t>(tree.regions.size());
    r.parent = 0;
    r.build_direction = up * -1.0;
    r.base_normal = r.build_direction;
    r.base_point = tree.regions[0].base_point;
    r.mesh = std::move(h);
    r.rule = "below the plate";
    tree.regions.push_back(std::move(r));
  }

  // Per region: its overhang in its own direction and its adjacency, refreshed when it is cut.
  std::vector<double> overhang;
  std::vector<mesh::EdgeTopology> topology;
  // Bumped whenever a region is cut: what was worked out on the region before stays valid until then.
  std::vector<std::uint64_t> version;
  std::uint64_t next_version = 0;
  auto refresh = [&](std::size_t r) {
    overhang.resize(tree.regions.size());
    topology.resize(tree.regions.size());
    version.resize(tree.regions.size());
    version[r] = ++next_version;
    const Region& g = tree.regions[r];
    overhang[r] = detail::unsupported(g.mesh, g.build_direction, alpha, g.base_point, g.base_normal);
    topology[r] = mesh::build_topology(g.mesh);
  };
  for (std::size_t r = 0; r < tree.regions.size(); ++r) refresh(r);

  // Cuts CHILD off HOST (its parent, which keeps what remains).
  auto add_child = [&](std::size_t host, ExactSplit&& split, Vec3 point, Vec3 normal, std::string rule) {
    Region child;
    child.id = static_cast<std::uint32_t>(tree.regions.size());
    child.parent = tree.regions[host].id;
    child.build_direction = split.direction;
    child.base_point = point;
    child.base_normal = normal;
    child.mesh = std::move(split.child);
    child.rule = std::move(rule);
    tree.regions[host].mesh = std::move(split.parent);
    tree.regions.push_back(std::move(child));
    refresh(host);
    refresh(tree.regions.size() - 1);
  };

  // Greedy, best first: every round screens every open link's candidates in the region holding the
  // link's branch, cuts the link whose best candidate removes the most overhang, and stops when no
  // split removes any.
  // The work budget (DecomposeOptions::work_budget_facet_visits): false once it is spent.
  auto spend = [&](double visits) {
    if (tree.budget_exhausted) return false;
    if (options.stop != nullptr && options.stop->load(std::memory_order_relaxed)) return !(tree.budget_exhausted = true);
    tree.work_facet_visits += visits;
    if (options.work_budget_facet_visits > 0.0 && tree.work_facet_visits > options.work_budget_facet_visits) tree.budget_exhausted = true;
    return !tree.budget_exhausted;
  };
  // Link S's candidates screened in region HOST, best first (none once the budget is spent).
  auto screen_link = [&](const SplitLink& s, std::size_t host) {
    const Region& h = tree.regions[host];
    detail::HostRegion hr{&h.mesh, &topology[host], h.build_direction, h.base_point, h.base_normal, false, reach, nullptr, options.min_region_mm};
    std::vector<Candidate> cands = candidates_for(s, mesh, faces, axis.increment_mm, options.face_normal_tolerance_deg, alpha);
    if (!spend(static_cast<double>(cands.size() + s.targets.size()) * static_cast<double>(h.mesh.triangles.size()))) return std::vector<Candidate>{};
    const detail::HostFaces host_faces = detail::host_faces(h.mesh, h.build_direction, h.base_point, h.base_normal, alpha);
    hr.faces = &host_faces;
    const std::vector<std::uint32_t> seeds = detail::nearest_facets(h.mesh, s.targets);
    // Candidates are screened in parallel; each writes only its own result.
    tbb::parallel_for(std::size_t{0}, cands.size(), [&](std::size_t k) {
      Candidate& c = cands[k];
      const Vec3 starts[] = {c.normal, s.dir, s.branch_dir};
      c.screened = detail::screen_split(hr, c.point, c.normal, seeds, starts, alpha);
    });
    std::erase_if(cands, [](const Candidate& c) { return !c.screened.valid; });
    std::stable_sort(cands.begin(), cands.end(), [&](const Candidate& a, const Candidate& b) {
      return preferred(overhang[host] - a.screened.total(), a, s.dir, overhang[host] - b.screened.total(), b, s.dir);
    });
    return cands;
  };
  std::vector<SplitLink> links = split_links(axis);
  // Per link, what a round works out from regions that a later round may find uncut: the
  // distance from its targets to each region, and its screened candidates in its host.
  struct LinkMemo {
    std::vector<std::pair<std::uint64_t, double>> distance;  // per region: (version, distance sum)
    std::uint64_t host_version = 0;                          // of the host the candidates were screened in (0: none)
    std::vector<Candidate> screened;                         // best first
  };
  std::vector<LinkMemo> memo(links.size());
  auto progress = std::make_unique<core::Progress>("decompose", links.size());  // links decided
  while (!tree.budget_exhausted) {  // once it is spent, no cut can be paid for
    progress->update(static_cast<std::uint64_t>(std::count_if(links.begin(), links.end(), [](const SplitLink& l) { return l.done; })));
    std::size_t best_link = links.size(), best_host = 0;
    double best_gain = 0.0;
    for (std::size_t i = 0; i < links.size(); ++i) {
      SplitLink& s = links[i];
      if (s.done || s.targets.empty()) continue;
      LinkMemo& m = memo[i];
      m.distance.resize(tree.regions.size());
      std::size_t host = 0;
      double nearest = INFINITY;
      for (std::size_t r = 0; r < tree.regions.size() && tree.regions.size() > 1; ++r) {  // one region is the host
        if (m.distance[r].first != version[r]) m.distance[r] = {version[r], distance_sum(tree.regions[r].mesh, s.targets)};
        if (m.distance[r].second < nearest) nearest = m.distance[r].second, host = r;
      }
      if (overhang[host] <= 0.0) continue;  // nothing to gain in a support-free region
      if (m.host_version != version[host]) {
        m.host_version = version[host];
        m.screened = screen_link(s, host);
        if (tree.budget_exhausted) break;
      }
      const std::vector<Candidate>& cands = m.screened;
      if (cands.empty()) continue;
      const double gain = overhang[host] - cands[0].screened.total();
      if (gain > kMinGainMm2 &&
          (best_link == links.size() || preferred(gain, cands[0], s.dir, best_gain, memo[best_link].screened[0], links[best_link].dir))) {
        best_gain = gain, best_link = i, best_host = host;
      }
    }
    if (best_link == links.size()) break;
    SplitLink& s = links[best_link];
    s.done = true;
    const std::vector<Candidate> best_candidates = std::move(memo[best_link].screened);
    const std::size_t host = best_host;
    std::optional<ExactSplit> chosen;
    const Candidate* used = nullptr;
    for (std::size_t k = 0; k < best_candidates.size() && k < kExactTries; ++k) {
      const Candidate& c = best_candidates[k];
      if (!spend(kExactCutVisitsPerFacet * static_cast<double>(tree.regions[host].mesh.triangles.size()))) break;
      const Vec3 starts[] = {c.normal, s.dir, s.branch_dir, c.screened.child_direction};
      auto e = exact_split(tree.regions[host], c.point, c.normal, s.targets, starts, alpha, ExactRules{false, false, reach, options.min_region_mm, &options.least_height_mm, plate_point, plate_up});
      if (e && e->unsupported_mm2 < overhang[host] - kMinGainMm2 && (!chosen || e->unsupported_mm2 < chosen->unsupported_mm2)) {
        chosen = std::move(e), used = &best_candidates[k];
        // The cut confirms the estimate: the later candidates were estimated no better.
        if (chosen->unsupported_mm2 <= c.screened.total() + kUnsupportedNoiseMm2) break;
      }
    }
    if (!chosen) continue;  // the exact cut did not confirm the estimate: leave this link
    add_child(host, std::move(*chosen), used->point, used->normal, used->rule);
  }

  // What the links leave: each overhang patch, largest first, may be cut off into a region of its
  // own, built along a direction in which it stands (patch_split.h), when that removes overhang.
  progress->update(links.size());
  progress.reset();  // the links' stage ends here
  core::Progress patch_progress("overhang patches", 0);  // patches tried
  std::uint64_t patches_tried = 0;
  for (int splits = 0; splits < kMaxPatchSplits && !tree.budget_exhausted;) {
    bool split = false;
    for (std::size_t host = 0; host < tree.regions.size() && !split; ++host) {
      if (overhang[host] <= 0.0) continue;
      const Region& h = tree.regions[host];
      detail::HostRegion hr{&h.mesh, &topology[host], h.build_direction, h.base_point, h.base_normal, false, reach, nullptr, options.min_region_mm};
      // The plate stays under the regions that stand on it; a cut base may go with the child, whose
      // facets on it are then checked like any other.
      hr.keep_base = !h.parent || h.rule == "below the plate";
      const detail::HostFaces host_faces = detail::host_faces(h.mesh, h.build_direction, h.base_point, h.base_normal, alpha);
      hr.faces = &host_faces;
      const auto patches = detail::overhang_patches(h.mesh, topology[host], h.build_direction, alpha, h.base_point, h.base_normal);
      for (std::size_t p = 0; p < patches.size() && p < kMaxPatchesPerRegion && !split; ++p) {
        patch_progress.update(++patches_tried);
        if (!spend(detail::kPatchScreenBudget)) break;
        const std::vector<detail::PatchCandidate> cands = detail::patch_candidates(hr, patches[p], axis.increment_mm, alpha);
        const std::vector<Vec3> targets = detail::patch_targets(h.mesh, patches[p]);
        std::optional<ExactSplit> chosen;
        const detail::PatchCandidate* used = nullptr;
        for (std::size_t k = 0; k < cands.size() && k < kExactTries; ++k) {
          const detail::PatchCandidate& c = cands[k];
          if (c.screened.total() >= overhang[host] - kMinGainMm2) break;
          if (!spend(kExactCutVisitsPerFacet * static_cast<double>(h.mesh.triangles.size()))) break;
          const Vec3 starts[] = {c.normal, c.screened.child_direction};
          auto e = exact_split(h, c.point, c.normal, targets, starts, alpha, ExactRules{true, hr.keep_base, reach, options.min_region_mm, &options.least_height_mm, plate_point, plate_up});
          // A child that starts nowhere in mid-air first, then the least overhang left.
          auto better = [&](const ExactSplit& x, const ExactSplit& y) {
            return (x.child_mid_air == 0) != (y.child_mid_air == 0) ? x.child_mid_air == 0 : x.unsupported_mm2 < y.unsupported_mm2;
          };
          if (e && e->child_mm2 == 0.0 && e->unsupported_mm2 < overhang[host] - kMinGainMm2 && (!chosen || better(*e, *chosen))) {
            chosen = std::move(e), used = &c;
            if (chosen->child_mid_air == 0 && chosen->unsupported_mm2 <= c.screened.total() + kUnsupportedNoiseMm2) break;
          }
        }
        if (!chosen) continue;
        add_child(host, std::move(*chosen), used->point, used->normal, "overhang patch");
        split = true;
        ++splits;
      }
    }
    if (!split) break;
  }
  for (std::size_t r = 0; r < tree.regions.size(); ++r) {
    Region& g = tree.regions[r];
    g.volume_mm3 = mesh::signed_volume(g.mesh);
    g.unsupported_area_mm2 = overhang[r];
    // Looked for only where no facet overhangs: a region with overhang is not support-free anyway,
    // and an underside's bumps would each be probed.
    if (g.unsupported_area_mm2 == 0.0) g.mid_air_starts = detail::mid_air_starts(g.mesh, g.build_direction, g.base_point, g.base_normal, options.min_region_mm);
    g.support_free = g.unsupported_area_mm2 == 0.0 && g.mid_air_starts.empty();
  }
  detail::order_by_support(tree.regions);
  return tree;
}

core::Result<const mesh::RepairedMesh*> cuttable_solid(const mesh::RepairedMesh& part, std::optional<mesh::RepairedMesh>& united,
                                                       std::size_t& crossing) {
  crossing = part.self_intersecting.empty() ? mesh::self_intersecting_faces(part.mesh).size() : part.self_intersecting.size();
  const mesh::RepairedMesh* solid = &part;
  if (crossing > 0) {
    united = mesh::unite_overlapping_shells(part);
    if (united && united->self_intersecting.size() < crossing) {
      solid = &*united, crossing = united->self_intersecting.size();
    } else {
      united.reset();
    }
  }
  if (static_cast<double>(crossing) > kMaxCrossingShare * static_cast<double>(solid->mesh.triangles.size())) {
    return core::make_error(core::ErrorCode::kInfeasible,
                            fmt::format("the part's surface crosses itself ({} faces): the cuts between regions need a clean solid", crossing));
  }
  return solid;
}

}  // namespace polyaxis::analysis
