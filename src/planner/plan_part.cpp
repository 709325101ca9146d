#include "polyaxis/planner/plan_part.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>

#include "polyaxis/mesh/distance.h"
#include "polyaxis/mesh/plane_cut.h"
#include "polyaxis/mesh/properties.h"
#include "polyaxis/mesh/self_intersections.h"
#include "polyaxis/mesh/topology.h"
#include "polyaxis/post/traori.h"
#include "core/arena.h"
#include "branches.h"
#include "reach.h"
#include "read_backs.h"

namespace polyaxis::planner {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// A region below the root's base that the substrate plate itself can supply: it lies within the
// plate's thickness under the base and holds at most this share of the part's volume (a corner
// of a leaning feature poking under a base plate, not a feature of its own).
constexpr double kPlateSuppliedShare = 0.01;

bool supplied_by_plate(const analysis::Region& r, const analysis::Region& root, const process::ProcessConfig& process,
                       double part_volume) {
  if (r.rule != "below the plate" || !r.parent || *r.parent != root.id) return false;
  if (r.volume_mm3 > kPlateSuppliedShare * part_volume) return false;
  const Vec3 up = core::normalized(root.build_direction);
  const double base = core::dot(root.base_point, up);
  double depth = 0.0;
  for (const Vec3& v : r.mesh.vertices) depth = std::max(depth, base - core::dot(v, up));
  return depth <= process.substrate.thickness_mm;
}

// Rounds of turning the torch where the program read back strikes earlier deposit.
constexpr int kReliefRounds = 3;
// Collisions named in a message, at most.
constexpr std::size_t kNamedCollisions = 3;
// Regions tried along other directions, one after the other, at most (redirected).
constexpr std::size_t kRedirectRegions = 2;

// A unit direction for messages, "(x, y, z)" to 3 decimals, with no "-0.000".
std::string direction_text(Vec3 d) {
  auto tidy = [](double v) { return std::abs(v) < 5e-4 ? 0.0 : v; };
  return fmt::format("({:.3f}, {:.3f}, {:.3f})", tidy(d.x), tidy(d.y), tidy(d.z));
}

std::string describe(const verify::Collision& c) {
  return fmt::format("line {} (layer {} region {}) at ({:.2f}, {:.2f}, {:.2f}), the {} ({:.2f} mm)", c.line, c.layer, c.region, c.tip.x, c.tip.y,
                     c.tip.z, c.body, c.depth_mm);
}

// A root base within this of the part's lowest point (along the root's direction) is that point.
constexpr double kSameBaseMm = 1e-6;
// Restarts where the rotary axes stall (post::GcodeStats::stall_splits) are warned of when their
// dwells take at least this share of the build time.
constexpr double kStallRestartWarnShare = 0.05;

struct Candidate {
  Plan plan;
  std::optional<analysis::CentroidalAxis> axis;
  Strategy strategy = Strategy::kSingle;
  std::vector<std::string> warnings;
  // A decomposition's regions and options as make_plan took them (part frame, no stop flag): its
  // regions can be planned again along other directions (redirected).
  std::vector<PlanRegion> regions;
  PlanOptions plan_options;
  bool root_at_lowest = false;  // a decomposition's root stands on the part's lowest point
  // Its key in PartMemo (candidate_key: which candidate of the choice, how the part stands); empty
  // for the plans made outside the choice (trunk splits, substrate pieces, redirected regions).
  std::vector<double> memo_key;
};

// The layers of PLAN that turn with the part rather than stay parallel: "tilted", "conformal",
// "tilted and conformal", or empty when every region is planar.
std::string turned_layers(const Plan& plan) {
  auto uses = [&](slicing::LayerStrategy s) {
    return std::any_of(plan.placed_regions.begin(), plan.placed_regions.end(), [&](const PlanRegion& r) { return !r.prebuilt && r.layers == s; });
  };
  const bool tilted = uses(slicing::LayerStrategy::kTilted), conformal = uses(slicing::LayerStrategy::kConformal);
  return tilted && conformal ? "tilted and conformal" : tilted ? "tilted" : conformal ? "conformal" : "";
}

// What every decomposition of one part computes alike, computed once: the count of faces that cross
// another and the centroidal axis from each start direction. Candidates may ask side by side; each
// value is computed by the first that asks, the others wait for it.
class PartMemo {
 public:
  explicit PartMemo(const mesh::RepairedMesh& part) : part_(part) {}

  // The part as one solid for the decomposition's cuts (analysis::cuttable_solid: the part, or its
  // overlapping bodies united), or why there is none.
  const core::Result<const mesh::RepairedMesh*>& solid() {
    std::call_once(solid_once_, [&] { solid_.emplace(analysis::cuttable_solid(part_, united_, crossing_)); });
    return *solid_;
  }

  const core::Result<analysis::CentroidalAxis>& axis(const analysis::CentroidalAxisOptions& options) {
    std::shared_ptr<AxisEntry> entry;
    {
      const std::lock_guard lock(mutex_);
      const Vec3 s = options.start_direction;
      auto& slot = axes_[{s.x, s.y, s.z}];
      if (!slot) slot = std::make_shared<AxisEntry>();
      entry = slot;
    }
    const mesh::RepairedMesh& part = solid() ? *solid().value() : part_;
    std::call_once(entry->once, [&] { entry->axis.emplace(analysis::centroidal_axis(part.mesh, part.topology, options)); });
    return *entry->axis;
  }

  // The decomposition of the solid (analysis::decompose) under AXIS and OPTIONS, made once for each
  // root (every option but `stop` and `least_height_mm` keys it: the machine and process, which fix
  // the latter, are the same for one part). The choice on planar layers asks for the same trees as
  // the choice on automatic ones. A run that was stopped is not kept; two lanes asking for one root
  // at once may both make it (the same tree).
  core::Result<analysis::RegionTree> decomposition(const mesh::Mesh& solid, const analysis::CentroidalAxis& axis,
                                                   const analysis::DecomposeOptions& options) {
    const analysis::RootBase& b = options.root_base;
    const std::vector<double> key{options.root_direction.x, options.root_direction.y, options.root_direction.z,
                                  static_cast<double>(b.kind), static_cast<double>(b.face), b.point.x, b.point.y, b.point.z,
                                  b.normal.x, b.normal.y, b.normal.z, options.self_supporting_deg, options.face_normal_tolerance_deg,
                                  options.work_budget_facet_visits, options.reach_deg, options.min_region_mm};
    {
      const std::lock_guard lock(mutex_);
      if (auto it = trees_.find(key); it != trees_.end()) return it->second;
    }
    auto tree = analysis::decompose(solid, axis, options);
    if (options.stop != nullptr && options.stop->load()) return tree;
    const std::lock_guard lock(mutex_);
    trees_.emplace(key, tree);
    return tree;
  }

  // An automatic choice's candidate that took planar layers in every region, under KEY (the
  // candidate and how the part stands): the choice again on planar layers would make the same plan
  // (auto slices planar layers first and keeps them), so it is taken from here. Null when none.
  std::shared_ptr<const Candidate> planar_candidate(const std::vector<double>& key) {
    const std::lock_guard lock(mutex_);
    auto it = planar_.find(key);
    return it == planar_.end() ? nullptr : it->second;
  }
  void keep_planar_candidate(const std::vector<double>& key, const Candidate& c) {
    const std::lock_guard lock(mutex_);
    planar_.emplace(key, std::make_shared<const Candidate>(c));
  }

  // The outcome of redirected() for the planar candidate under KEY, kept where every plan it made
  // took planar layers in every region: the choice again on planar layers would make the same
  // plans, programs and outcome. Null when none is kept.
  std::shared_ptr<const std::optional<PlanPartResult>> redirected(const std::vector<double>& key) {
    const std::lock_guard lock(mutex_);
    auto it = redirected_.find(key);
    return it == redirected_.end() ? nullptr : it->second;
  }
  void keep_redirected(const std::vector<double>& key, const std::optional<PlanPartResult>& outcome) {
    const std::lock_guard lock(mutex_);
    redirected_.emplace(key, std::make_shared<const std::optional<PlanPartResult>>(outcome));
  }

  // plan_on_trunk of trunk_splits()[I] along DIRECTION with its trunk's reasons, made by MAKE on the
  // first call: the choice (with_trunk_splits) and the fallback after a failed decomposition
  // (clean_on_trunk) plan the same splits, both on automatic layers only.
  struct OnTrunk {
    core::Result<Candidate> candidate;
    std::string why;
  };
  std::shared_ptr<const OnTrunk> on_trunk(std::size_t i, Vec3 direction, const std::function<OnTrunk()>& make) {
    const std::array<double, 4> key{static_cast<double>(i), direction.x, direction.y, direction.z};
    {
      const std::lock_guard lock(mutex_);
      if (auto it = on_trunk_.find(key); it != on_trunk_.end()) return it->second;
    }
    auto made = std::make_shared<const OnTrunk>(make());
    const std::lock_guard lock(mutex_);
    return on_trunk_.emplace(key, std::move(made)).first->second;
  }

  // The programs read back so far (program_of).
  detail::ReadBacks& read_backs() { return read_backs_; }

  // The part's trunk splits (detail::trunk_splits) for beads of BEAD_MM, the first call's bead.
  const std::vector<detail::TrunkSplit>& trunk_splits(double bead_mm) {
    std::call_once(splits_once_, [&] { splits_ = detail::trunk_splits(part_, bead_mm); });
    return splits_;
  }

 private:
  struct AxisEntry {
    std::once_flag once;
    std::optional<core::Result<analysis::CentroidalAxis>> axis;
  };
  const mesh::RepairedMesh& part_;
  std::once_flag solid_once_;
  std::optional<mesh::RepairedMesh> united_;
  std::size_t crossing_ = 0;
  std::optional<core::Result<const mesh::RepairedMesh*>> solid_;
  std::mutex mutex_;
  std::map<std::array<double, 3>, std::shared_ptr<AxisEntry>> axes_;
  std::map<std::vector<double>, core::Result<analysis::RegionTree>> trees_;
  std::map<std::vector<double>, std::shared_ptr<const Candidate>> planar_;
  std::map<std::vector<double>, std::shared_ptr<const std::optional<PlanPartResult>>> redirected_;
  std::once_flag splits_once_;
  std::vector<detail::TrunkSplit> splits_;
  detail::ReadBacks read_backs_;
  std::map<std::array<double, 4>, std::shared_ptr<const OnTrunk>> on_trunk_;
};

// STOP as plan_decomposed's.
core::Result<Candidate> plan_single(const mesh::RepairedMesh& part, const machine::MachineConfig& machine,
                                    const process::ProcessConfig& process, const PlanPartOptions& o, const std::atomic<bool>* stop = nullptr) {
  PlanOptions po = o.plan;
  po.direction = o.direction;
  po.stop = stop;
  auto plan = make_plan(part, machine, process, po);
  if (!plan) return plan.error();
  Candidate c;
  c.plan = std::move(plan.value());
  return c;
}

// The vertex of MESH lowest along D.
Vec3 lowest_along(const mesh::Mesh& m, Vec3 d) {
  Vec3 low = m.vertices.front();
  for (const Vec3& v : m.vertices) {
    if (core::dot(v, d) < core::dot(low, d)) low = v;
  }
  return low;
}

// The unit vector A turned towards B by DEG degrees (B itself when nearer).
Vec3 turned_towards(Vec3 a, Vec3 b, double deg) {
  a = core::normalized(a), b = core::normalized(b);
  const double angle = std::acos(std::clamp(core::dot(a, b), -1.0, 1.0)), t = deg * std::numbers::pi / 180.0;
  if (angle <= t || angle < 1e-9) return b;
  const Vec3 ortho = core::normalized(b - a * core::dot(a, b));
  return core::normalized(a * std::cos(t) + ortho * std::sin(t));
}

// The part within this of the substrate's surface is the substrate's (--substrate): two
// tessellations of one surface differ by about this (STEP at the default chordal deviation, 0.01
// mm; the rounding of STL's floats, 1e-5 mm), and no layer is this thin.
constexpr double kSubstrateSkinMm = 0.02;

// Faces of a piece within this of the substrate's surface, facing into it, are the piece's base.
constexpr double kOnSubstrateMm = 1e-6;
constexpr double kFacingCos = 0.999;

// The outward normal of the substrate where PIECE stands on it: the area-weighted mean of the
// substrate faces PIECE's base lies on (none: the piece does not touch the substrate). A face of
// PIECE is on the substrate when its centroid is within kOnSubstrateMm of the substrate face nearest
// to it and faces into that face. Cost: O((F_piece + F_substrate) log F_substrate).
std::optional<Vec3> base_normal(const mesh::Mesh& piece, const mesh::Mesh& substrate) {
  const mesh::SurfaceDistance surface(substrate);
  if (surface.empty()) return std::nullopt;
  Vec3 sum;
  for (std::size_t f = 0; f < piece.triangles.size(); ++f) {
    const Vec3 area = mesh::face_area_vector(piece, f);
    const double a2 = core::norm(area);
    if (!(a2 > 0.0)) continue;
    const Vec3 c = (piece.corner(f, 0) + piece.corner(f, 1) + piece.corner(f, 2)) / 3.0;
    const mesh::Nearest near = surface.nearest(c);
    if (std::abs(near.signed_mm) > kOnSubstrateMm) continue;
    const Vec3 sa = mesh::face_area_vector(substrate, near.face);
    const double s2 = core::norm(sa);
    if (!(s2 > 0.0) || core::dot(sa / s2, area / a2) > -kFacingCos) continue;
    sum = sum + sa * (0.5 * a2 / s2);  // the piece face's area along the substrate's normal
  }
  if (!(core::norm(sum) > 0.0)) return std::nullopt;
  return core::normalized(sum);
}

// The substrate as region 0: prebuilt, along UP.
PlanRegion substrate_region(const mesh::Mesh& substrate, Vec3 up) {
  PlanRegion base;
  base.id = 0;
  base.mesh = substrate;
  base.direction = up;
  base.prebuilt = true;
  base.rule = kRegionSubstrate;
  base.volume_mm3 = std::abs(mesh::signed_volume(base.mesh));
  base.base_point = lowest_along(base.mesh, up);
  return base;
}

// A piece of the deposit as region ID, grown from the substrate along D.
PlanRegion on_substrate_region(std::uint32_t id, mesh::Mesh piece, Vec3 d) {
  PlanRegion r;
  r.id = id;
  r.direction = d;
  r.parent = 0;
  r.rests_on = {0};
  r.rule = kRegionOnSubstrate;
  r.mesh = std::move(piece);
  r.volume_mm3 = std::abs(mesh::signed_volume(r.mesh));
  r.base_point = lowest_along(r.mesh, d);
  return r;
}

// The part less the substrate (--substrate), and the surface its pieces stand on.
struct OnSubstrate {
  mesh::Mesh rest;  // what is deposited
  mesh::Mesh skin;  // the substrate grown by kSubstrateSkinMm, its outer surface where that folds
};

// True when SKIN, made from SUBSTRATE grown by kSubstrateSkinMm and rid of its crossings, is what
// it should be: closed, crossing nothing, and holding the substrate and at most the skin more
// (CGAL's autorefinement of shells that only touch gave 4 faces).
bool holds_substrate(const mesh::Mesh& skin, const mesh::Mesh& substrate) {
  if (!mesh::build_topology(skin).closed() || !mesh::self_intersecting_faces(skin).empty()) return false;
  const double v = mesh::signed_volume(skin), least = mesh::signed_volume(substrate);
  return v >= least && v <= least + kSubstrateSkinMm * mesh::surface_area(substrate) * 1.01;
}

// The part less O.substrate. The substrate grown by a skin: where the part's surface and the
// substrate's are two tessellations of one surface (a hub exported apart from its impeller), a
// sliver of the part would be left over the substrate and join every piece into one. A substrate
// with a gap or a feature thinner than twice the skin, or slivers along a union's seam, folds when
// grown (its faces cross, and the difference would be garbage): then the skin's outer surface
// (mesh::without_crossings), and only when that fails the substrate as given. Its faces lie on the
// part's, which CGAL's corefinement may never finish with: two_branches less its trunk and one
// arm, the skin folded along the seam of the two, ran for 16 minutes before the outer surface.
core::Result<OnSubstrate> part_less_substrate(const mesh::RepairedMesh& part, const PlanPartOptions& o) {
  OnSubstrate out;
  out.skin = mesh::grown(*o.substrate, kSubstrateSkinMm);
  if (!mesh::self_intersecting_faces(out.skin).empty()) {
    auto outer = mesh::without_crossings(out.skin);
    out.skin = outer && holds_substrate(outer.value(), *o.substrate) ? std::move(outer.value()) : *o.substrate;
  }
  auto rest = mesh::difference(part.mesh, out.skin);
  if (!rest) return core::make_error(rest.error().code, "--substrate: the part less the substrate: " + rest.error().message);
  if (rest.value().triangles.empty()) {
    return core::make_error(core::ErrorCode::kInfeasible, "--substrate: nothing to build: the substrate holds the whole part");
  }
  out.rest = std::move(rest.value());
  return out;
}

// ON.rest, the part less the substrate, deposited onto it (--substrate): along O.direction as one region,
// or (PER_PIECE) each connected piece as a region of its own along the substrate's normal under
// its base, turned towards O.direction into the tilt's reach (kInfeasible under kAuto when that
// turns none: the one direction again).
core::Result<Candidate> plan_on_substrate(const mesh::RepairedMesh& part, const machine::MachineConfig& machine,
                                          const process::ProcessConfig& process, const PlanPartOptions& o, const OnSubstrate& on,
                                          bool per_piece) {
  const Vec3 up = core::normalized(o.direction);
  std::vector<PlanRegion> regions{substrate_region(*o.substrate, up)};
  if (!per_piece) {
    regions.push_back(on_substrate_region(1, on.rest, up));
  } else {
    const double reach = detail::direction_reach_rad(machine, process);
    bool turned = false;
    for (mesh::Mesh& piece : mesh::connected_solids(on.rest)) {
      Vec3 d = base_normal(piece, on.skin).value_or(up);
      const double angle = std::acos(std::clamp(core::dot(d, up), -1.0, 1.0));
      if (angle > reach) d = turned_towards(d, up, (angle - reach) * 180.0 / std::numbers::pi);
      turned = turned || core::norm(d - up) > 1e-9;
      regions.push_back(on_substrate_region(static_cast<std::uint32_t>(regions.size()), std::move(piece), d));
    }
    if (regions.size() < 2 || (!turned && o.strategy == Strategy::kAuto)) {
      return core::make_error(core::ErrorCode::kInfeasible, "every piece on the substrate grows along the given direction: nothing to turn");
    }
  }
  PlanOptions po = o.plan;
  po.direction = up;
  auto plan = make_plan(part, machine, process, po, regions);
  if (!plan) return plan.error();
  Candidate c;
  c.plan = std::move(plan.value());
  c.strategy = per_piece ? Strategy::kDecompose : Strategy::kSingle;
  return c;
}

// Marks the regions O.prebuilt names as prebuilt; kUsage for an id that is not a region.
core::Status mark_prebuilt(std::vector<PlanRegion>& regions, const PlanPartOptions& o) {
  for (const std::uint32_t id : o.prebuilt) {
    auto it = std::find_if(regions.begin(), regions.end(), [&](const PlanRegion& r) { return r.id == id; });
    if (it == regions.end()) {
      std::vector<std::uint32_t> ids;
      for (const PlanRegion& r : regions) ids.push_back(r.id);
      return core::make_error(core::ErrorCode::kUsage,
                              fmt::format("--prebuilt {}: the decomposition has no such region (its regions: {}; polyaxis analyze lists them)", id,
                                          fmt::join(ids, ", ")));
    }
    it->prebuilt = true;
  }
  return {};
}

// STOP: set by another thread when the candidate is no longer wanted (it then ends early with an
// error that nobody reads); null when it always is. ROOT_AT_LOWEST (when given) is set once the tree
// is made, whether a plan follows or not: true when its root stands on the part's lowest point along
// its direction, so that rooting it there explicitly (RootBase::kLowest) would give the same tree.
core::Result<Candidate> plan_decomposed(const mesh::RepairedMesh& part, const machine::MachineConfig& machine,
                                        const process::ProcessConfig& process, const PlanPartOptions& o,
                                        const analysis::RootBase& root_base, PartMemo& memo, const std::atomic<bool>* stop = nullptr,
                                        bool* root_at_lowest = nullptr) {
  // A solid the cuts can take: the part, or its overlapping bodies united (analysis::cuttable_solid).
  const auto& cuttable = memo.solid();
  if (!cuttable) return cuttable.error();
  const mesh::RepairedMesh& solid = *cuttable.value();
  auto root_dir = analysis::root_direction(part.mesh, root_base, o.direction);
  if (!root_dir) return root_dir.error();
  analysis::CentroidalAxisOptions axis_options;
  axis_options.start_direction = analysis::nearest_major_direction(root_dir.value());
  const auto& axis = memo.axis(axis_options);
  if (!axis) return axis.error();
  if (stop != nullptr && stop->load()) return core::make_error(core::ErrorCode::kInfeasible, "not wanted any more");
  analysis::DecomposeOptions dopt;
  dopt.root_direction = root_dir.value();
  dopt.root_base = root_base;
  dopt.self_supporting_deg = process.self_supporting_deg;
  dopt.work_budget_facet_visits = o.decompose_budget_facet_visits;
  dopt.reach_deg = detail::direction_reach_rad(machine, process) * 180.0 / std::numbers::pi;
  dopt.min_region_mm = process.layer_min_mm;
  dopt.least_height_mm = [&machine, &process, clearance = o.plan.head_clearance_mm](double tilt_rad) {
    return detail::least_layable_height_mm(machine, process, tilt_rad, clearance);
  };
  dopt.stop = stop;
  auto tree = memo.decomposition(solid.mesh, axis.value(), dopt);
  if (!tree) return tree.error();
  if (stop != nullptr && stop->load()) return core::make_error(core::ErrorCode::kInfeasible, "not wanted any more");
  if (root_at_lowest != nullptr) {
    const analysis::Region& root = tree.value().regions.front();
    const Vec3 up = core::normalized(root.build_direction);
    double lowest = INFINITY;
    for (const Vec3& v : part.mesh.vertices) lowest = std::min(lowest, core::dot(v, up));
    *root_at_lowest = core::dot(root.base_point, up) - lowest <= kSameBaseMm;
  }
  const bool at_lowest = root_at_lowest != nullptr && *root_at_lowest;
  if (o.strategy == Strategy::kAuto && tree.value().regions.size() < 2) {
    return core::make_error(core::ErrorCode::kInfeasible, "it finds the part one region: nothing to split");
  }
  Candidate c;
  c.strategy = Strategy::kDecompose;
  c.root_at_lowest = at_lowest;
  if (dopt.reach_deg < 180.0) {
    double left = 0.0;
    for (const analysis::Region& r : tree.value().regions) left += r.support_free ? 0.0 : r.unsupported_area_mm2;
    if (left > 0.0 && machine::tilts_head(machine.kind) && dopt.reach_deg < detail::reach_rad(machine) * 180.0 / std::numbers::pi) {
      c.warnings.push_back(fmt::format("the decomposition kept every build direction within {:.0f} deg of vertical (the head-head machine "
                                       "'{}' leaves the part fixed; process off_vertical_max_deg) and leaves {:.1f} mm2 of overhang: a "
                                       "process that deposits further off vertical may remove it",
                                       dopt.reach_deg, machine.name, left));
    } else if (left > 0.0) {
      const char tilt = machine::tilt_axis_letter(machine.kind);
      c.warnings.push_back(fmt::format("the decomposition kept every build direction within the tilt reach of {:.0f} deg "
                                       "(machine '{}', limits.{}) and leaves {:.1f} mm2 of overhang: a wider tilt range may remove it",
                                       dopt.reach_deg, machine.name, tilt == '\0' ? 'z' : static_cast<char>(tilt - 'A' + 'a'), left));
    }
  }
  if (tree.value().budget_exhausted) {
    c.warnings.push_back(fmt::format("the decomposition stopped at its work budget ({:.0e} facet visits) with {} regions; "
                                     "--decompose-budget 0 lets it run to the end",
                                     o.decompose_budget_facet_visits, tree.value().regions.size()));
  }
  std::vector<PlanRegion> regions;
  const double part_volume = std::abs(mesh::signed_volume(solid.mesh));
  for (const analysis::Region& r : tree.value().regions) {  // parents come before children
    if (supplied_by_plate(r, tree.value().regions.front(), process, part_volume)) {
      c.warnings.push_back(fmt::format("region {} ({:.3g} mm3) lies in the substrate plate under the root's base: the plate supplies it "
                                       "(machine it from the plate), it is not deposited",
                                       r.id, r.volume_mm3));
      continue;
    }
    PlanRegion pr;
    pr.id = r.id;
    pr.mesh = r.mesh;
    pr.direction = r.build_direction;
    pr.parent = r.parent;
    pr.base_point = r.base_point;
    pr.base_normal = r.base_normal;
    pr.support_free = r.support_free;
    pr.rule = r.rule;
    pr.rests_on = r.rests_on;
    pr.volume_mm3 = r.volume_mm3;
    pr.overhang_mm2 = r.unsupported_area_mm2;
    regions.push_back(std::move(pr));
    if (!r.support_free) {
      const std::string starts =
          r.mid_air_starts.empty() ? std::string{}
                                   : fmt::format(", its first layer starts on nothing at {} corner(s), the first at ({:.2f}, {:.2f}, {:.2f})",
                                                 r.mid_air_starts.size(), r.mid_air_starts[0].x, r.mid_air_starts[0].y, r.mid_air_starts[0].z);
      c.warnings.push_back(fmt::format("region {} is not support-free along its direction ({:.1f} mm2 overhang{})", r.id,
                                       r.unsupported_area_mm2, starts));
    }
  }
  if (auto st = mark_prebuilt(regions, o); !st) return st.error();
  PlanOptions po = o.plan;
  po.direction = root_dir.value();
  po.stop = stop;
  auto plan = make_plan(part, machine, process, po, regions);
  if (!plan) return plan.error();
  c.plan = std::move(plan.value());
  c.axis = axis.value();
  c.regions = std::move(regions);
  c.plan_options = po;
  c.plan_options.stop = nullptr;
  return c;
}

// A plan's figures as better() ranks them.
struct Figures {
  double unsupported_area_mm2 = 0.0;
  std::size_t regions = 0, reorientations = 0;
  static Figures of(const Plan& p) { return {p.unsupported_area_mm2, p.regions, p.reorientations}; }
};

// True when A is the better plan: less unsupported area, then fewer regions, then fewer reorientations.
bool better(const Figures& a, const Figures& b) {
  if (std::abs(a.unsupported_area_mm2 - b.unsupported_area_mm2) > kUnsupportedNoiseMm2) return a.unsupported_area_mm2 < b.unsupported_area_mm2;
  if (a.regions != b.regions) return a.regions < b.regions;
  return a.reorientations < b.reorientations;
}
bool better(const Plan& a, const Plan& b) { return better(Figures::of(a), Figures::of(b)); }

// --substrate: the part less the substrate along one direction (kSingle), each of its pieces along
// the substrate's normal under it (kDecompose), or both and the better (kAuto, as choose()).
core::Result<Candidate> choose_on_substrate(const mesh::RepairedMesh& part, const machine::MachineConfig& machine,
                                            const process::ProcessConfig& process, const PlanPartOptions& o, std::string& why) {
  const std::string one = "the part less the substrate, along the given direction, onto the substrate (--substrate)";
  const std::string pieces = "the part less the substrate, each piece along the substrate's normal under it (--substrate)";
  const auto on = part_less_substrate(part, o);
  if (!on) return on.error();
  if (o.strategy != Strategy::kAuto) {
    why = o.strategy == Strategy::kSingle ? one : pieces;
    return plan_on_substrate(part, machine, process, o, on.value(), o.strategy == Strategy::kDecompose);
  }
  auto single = plan_on_substrate(part, machine, process, o, on.value(), false);
  if (single && single.value().plan.unsupported_area_mm2 == 0.0) {
    why = one;
    return single;
  }
  auto turned = plan_on_substrate(part, machine, process, o, on.value(), true);
  if (!turned || (single && !better(turned.value().plan, single.value().plan))) {
    why = single ? fmt::format("{}{}", one, turned ? "; the pieces along the substrate's normal do no better" : "") : one;
    return single;
  }
  why = fmt::format("{} ({} mm2 unsupported along the given direction)", pieces,
                    single ? area_text(single.value().plan.unsupported_area_mm2) : std::string("nothing planned"));
  return turned;
}

// The candidates of an automatic choice, in the order they are taken: the first support-free one
// ends the choice, and of the others the better one (better()) is kept, the earlier on a tie.
enum AutoCandidate : std::size_t {
  kOneDirection,
  kDecomposition,
  kFromLowest,
  kOneTurnedOver,
  kDecompositionTurnedOver,
  kOneOnASide,
  kAutoCandidates
};
constexpr std::array<const char*, kAutoCandidates> kAutoLabels = {
    "one build direction",           "the decomposition", "the decomposition from the lowest point", "one build direction turned over",
    "the decomposition turned over", "one build direction on a side face"};

// PartMemo's key for candidate I of the choice under O: which candidate and how the part stands.
std::vector<double> candidate_key(std::size_t i, const PlanPartOptions& o) {
  const analysis::RootBase& rb = o.root_base;
  return std::vector<double>{static_cast<double>(i), o.direction.x, o.direction.y, o.direction.z, static_cast<double>(rb.kind),
                             static_cast<double>(rb.face), rb.point.x, rb.point.y, rb.point.z, rb.normal.x, rb.normal.y, rb.normal.z};
}

// The candidate under KEY, made by PLAN(STOP); or, when O asks for planar layers, the one the choice
// on automatic layers made under KEY and kept because it took planar layers in every region (the
// same plan). A candidate made on automatic layers, not stopped, is kept so when it is.
template <typename MakeFn>
core::Result<Candidate> memoized(PartMemo& memo, const std::vector<double>& key, const PlanPartOptions& o, const std::atomic<bool>* stop,
                                 MakeFn&& plan) {
  if (o.plan.layers == LayerChoice::kPlanar) {
    if (const auto kept = memo.planar_candidate(key)) {
      Candidate c = *kept;
      // As this choice would have planned it: regions it plans again (redirected) take planar layers too.
      c.plan_options.layers = o.plan.layers;
      return c;
    }
  }
  core::Result<Candidate> made = plan(stop);
  if (!made) return made;
  made.value().memo_key = key;
  const bool stopped = stop != nullptr && stop->load();
  if (o.plan.layers == LayerChoice::kAuto && !stopped && turned_layers(made.value().plan).empty()) memo.keep_planar_candidate(key, made.value());
  return made;
}

// A side face to stand the part on: at least this many bead widths squared, and leaving at most
// this share of the overhang (mesh::overhang_area) that the part upright or turned over leaves.
constexpr double kSideFaceMinBeads2 = 25.0;
constexpr double kSideGainShare = 0.5;
// Directions within this of the given one or its reverse are those already tried, degrees.
constexpr double kSameDirectionDeg = 1.0;

// The build direction that stands the part on one of its planar faces (the reverse of its outward
// normal) and leaves the least overhang by the facets (the larger face on a tie), when that is at
// most kSideGainShare of what UP and its reverse leave: a block with a hole across it, built
// lying on its side, has the hole upright. None when no face does. O(F) per planar face.
std::optional<Vec3> side_direction(const mesh::Mesh& m, Vec3 up, const process::ProcessConfig& process) {
  const double alpha = process.self_supporting_deg * std::numbers::pi / 180.0;
  const Vec3 u = core::normalized(up);
  const double upright = std::min(mesh::overhang_area(m, u, alpha), mesh::overhang_area(m, u * -1.0, alpha));
  if (upright == 0.0) return std::nullopt;
  const double min_area = kSideFaceMinBeads2 * process.bead_width_mm * process.bead_width_mm;
  const double same_cos = std::cos(kSameDirectionDeg * std::numbers::pi / 180.0);
  std::optional<Vec3> best;
  double best_mm2 = kSideGainShare * upright, best_face = 0.0;
  for (const analysis::BaseFace& f : analysis::base_faces(m)) {
    const Vec3 d = core::normalized(f.normal) * -1.0;
    if (f.area_mm2 < min_area || std::abs(core::dot(d, u)) >= same_cos) continue;
    const double mm2 = mesh::overhang_area(m, d, alpha);
    if (mm2 < best_mm2 || (best && mm2 == best_mm2 && f.area_mm2 > best_face)) best = d, best_mm2 = mm2, best_face = f.area_mm2;
  }
  return best;
}

// The automatic choice. The candidates are made in two lanes side by side (the directions in one,
// the decompositions in the other, the part turned over in the one free first), and a candidate
// is stopped once one before it is support-free: the choice is the one made taking them one after
// the other, in less time.
core::Result<Candidate> choose_auto(const mesh::RepairedMesh& part, const machine::MachineConfig& machine,
                                    const process::ProcessConfig& process, const PlanPartOptions& o, PartMemo& memo, std::string& why) {
  PlanPartOptions over = o;  // the part turned over
  over.direction = o.direction * -1.0;
  analysis::RootBase lowest;
  lowest.kind = analysis::RootBase::Kind::kLowest;
  const bool may_turn_over = o.root_base.kind == analysis::RootBase::Kind::kAuto;
  std::array<std::optional<core::Result<Candidate>>, kAutoCandidates> made;
  std::array<std::atomic<bool>, kAutoCandidates> unwanted{};
  Vec3 side{0, 0, 1};  // kOneOnASide's direction, when made
  auto label = [&](std::size_t i) {
    if (i != kOneOnASide) return std::string(kAutoLabels[i]);
    return fmt::format("{} (along {})", kAutoLabels[i], direction_text(side));
  };
  auto make = [&](std::size_t i, auto&& plan) {
    if (unwanted[i].load()) return;
    made[i].emplace(memoized(memo, candidate_key(i, o), o, &unwanted[i], plan));
    if (made[i]->ok() && made[i]->value().plan.unsupported_area_mm2 == 0.0) {
      for (std::size_t j = i + 1; j < kAutoCandidates; ++j) unwanted[j] = true;
    }
  };
  const auto progress = core::ProgressScope::current();  // each lane may run on a worker thread
  // The part turned over, one direction: made by the lane that is free first.
  std::atomic<bool> turned_over_taken{false};
  auto turned_over = [&] {
    if (may_turn_over && !turned_over_taken.exchange(true)) {
      make(kOneTurnedOver, [&](auto stop) { return plan_single(part, machine, process, over, stop); });
    }
  };
  tbb::parallel_invoke(
      [&] {
        const core::ProgressScope scope(progress);
        make(kOneDirection, [&](auto stop) { return plan_single(part, machine, process, o, stop); });
        if (!may_turn_over) return;
        turned_over();
        if (unwanted[kOneOnASide].load()) return;
        if (const auto lying_along = side_direction(part.mesh, o.direction, process)) {
          PlanPartOptions lying = o;
          lying.direction = side = *lying_along;
          make(kOneOnASide, [&](auto stop) { return plan_single(part, machine, process, lying, stop); });
        }
      },
      [&] {
        const core::ProgressScope scope(progress);
        bool at_lowest = false;
        make(kDecomposition, [&](auto stop) { return plan_decomposed(part, machine, process, o, o.root_base, memo, stop, &at_lowest); });
        if (made[kDecomposition] && made[kDecomposition]->ok()) at_lowest = at_lowest || made[kDecomposition]->value().root_at_lowest;
        if (!may_turn_over) return;
        // Rooted at the lowest point it would give the same tree, and the same plan or refusal, as the
        // decomposition rooted there.
        if (!at_lowest) make(kFromLowest, [&](auto stop) { return plan_decomposed(part, machine, process, o, lowest, memo, stop); });
        make(kDecompositionTurnedOver, [&](auto stop) { return plan_decomposed(part, machine, process, over, o.root_base, memo, stop); });
        turned_over();
      });
  std::vector<std::string> refused;
  std::optional<std::size_t> best;
  std::optional<core::ErrorCode> first_code;
  auto plan_of = [&](std::size_t i) -> const Plan& { return made[i]->value().plan; };
  std::size_t taken = 0;  // candidates taken into the choice: [0, taken)
  for (; taken < kAutoCandidates && !(best && plan_of(*best).unsupported_area_mm2 == 0.0); ++taken) {
    if (!made[taken]) continue;
    const core::Result<Candidate>& c = *made[taken];
    if (!c) {
      if (!first_code) first_code = c.error().code;
      refused.push_back(fmt::format("{}: {}", label(taken), c.error().message));
      continue;
    }
    if (!best || better(c.value().plan, plan_of(*best))) best = taken;
  }
  if (!best) {
    why = fmt::format("nothing could be planned: {}", fmt::join(refused, "; "));
    return core::make_error(first_code.value_or(core::ErrorCode::kInfeasible), why);
  }
  // Where a candidate ties with the best on area and regions, better() ranked them on
  // reorientations: both then say how many.
  auto ties = [&](std::size_t i) {
    const Figures a = Figures::of(plan_of(i)), b = Figures::of(plan_of(*best));
    return std::abs(a.unsupported_area_mm2 - b.unsupported_area_mm2) <= kUnsupportedNoiseMm2 && a.regions == b.regions;
  };
  bool any_tie = false;
  for (std::size_t i = 0; i < taken; ++i) any_tie = any_tie || (i != *best && made[i] && made[i]->ok() && ties(i));
  auto summary = [](const Plan& p, bool with_turns) {
    return fmt::format("{} region{}, {}{}", p.regions, p.regions == 1 ? "" : "s",
                       p.unsupported_area_mm2 == 0.0 ? std::string("support-free") : fmt::format("{} mm2 unsupported", area_text(p.unsupported_area_mm2)),
                       with_turns ? fmt::format(", {} reorientations", p.reorientations) : std::string());
  };
  // The candidates it did better than, with what they would have left.
  std::vector<std::string> outdone;
  for (std::size_t i = 0; i < taken; ++i) {
    if (i != *best && made[i] && made[i]->ok()) outdone.push_back(fmt::format("{}: {}", label(i), summary(plan_of(i), ties(i))));
  }
  why = fmt::format("{} ({}{}{})", label(*best), summary(plan_of(*best), any_tie),
                    outdone.empty() ? "" : fmt::format("; also tried: {}", fmt::join(outdone, "; ")),
                    refused.empty() ? "" : fmt::format("; refused: {}", fmt::join(refused, "; ")));
  return std::move(made[*best]->value());
}

// The regions of CANDIDATE (a plan of TRUNK) in the part's frame: a decomposition's as it took
// them, or the whole trunk along the candidate's one direction.
std::vector<PlanRegion> trunk_regions(const Candidate& candidate, const mesh::Mesh& trunk) {
  if (!candidate.regions.empty()) return candidate.regions;
  const Placement& placed = candidate.plan.placement;
  PlanRegion whole;
  whole.mesh = trunk;
  whole.direction = placed.unrotate({0, 0, 1});
  whole.base_point = lowest_along(trunk, whole.direction);
  whole.rule = kRegionTrunk;
  whole.volume_mm3 = std::abs(mesh::signed_volume(trunk));
  return {whole};
}

// SPLIT's trunk planned as a part of its own (the automatic choice, its label in TRUNK_WHY), then
// with its regions the branches, SPLIT.rest's pieces, each along the trunk's outward normal under
// its base turned into the tilt's reach, built after the whole trunk with the surface of the
// trunk's tubes (SPLIT.tubes, where they cut the part: the branches' base) as the base of their
// conformal layers (auto layers take those where they leave less overhang).
core::Result<Candidate> plan_on_trunk(const mesh::RepairedMesh& part, const machine::MachineConfig& machine,
                                      const process::ProcessConfig& process, const PlanPartOptions& o, const detail::TrunkSplit& split,
                                      std::string& trunk_why) {
  auto trunk = mesh::repair(io::RawMesh{split.trunk.vertices, split.trunk.triangles});
  if (!trunk) return trunk.error();
  if (trunk.value().shells.size() != 1) return core::make_error(core::ErrorCode::kInfeasible, "the trunk is not one solid");
  PartMemo memo(trunk.value());
  auto built = choose_auto(trunk.value(), machine, process, o, memo, trunk_why);
  if (!built) return built.error();
  std::vector<PlanRegion> regions = trunk_regions(built.value(), trunk.value().mesh);
  std::vector<std::uint32_t> below;
  std::uint32_t root = regions.front().id, next = 0;
  for (const PlanRegion& r : regions) {
    below.push_back(r.id), next = std::max(next, r.id + 1);
    if (!r.parent) root = r.id;
  }
  const Vec3 up = core::normalized(o.direction);
  const double reach = detail::direction_reach_rad(machine, process);
  for (mesh::Mesh& piece : mesh::connected_solids(split.rest)) {
    Vec3 d = base_normal(piece, split.trunk).value_or(up);
    const double angle = std::acos(std::clamp(core::dot(d, up), -1.0, 1.0));
    if (angle > reach) d = turned_towards(d, up, (angle - reach) * 180.0 / std::numbers::pi);
    PlanRegion r = on_substrate_region(next++, std::move(piece), d);
    r.parent = root, r.rests_on = below, r.rule = kRegionOnTrunk, r.on_trunk = true;
    regions.push_back(std::move(r));
  }
  PlanOptions po = o.plan;
  po.direction = regions.front().direction;
  po.trunk = std::make_shared<const mesh::Mesh>(split.tubes);
  auto plan = make_plan(part, machine, process, po, regions);
  if (!plan) return plan.error();
  Candidate c;
  c.plan = std::move(plan.value());
  c.strategy = Strategy::kDecompose;
  c.regions = std::move(regions);
  c.plan_options = po;
  return c;
}

// plan_on_trunk of the part's trunk split I (PartMemo::trunk_splits), made once per MEMO.
std::shared_ptr<const PartMemo::OnTrunk> planned_on_trunk(const mesh::RepairedMesh& part, const machine::MachineConfig& machine,
                                                          const process::ProcessConfig& process, const PlanPartOptions& o, PartMemo& memo,
                                                          std::size_t i) {
  return memo.on_trunk(i, o.direction, [&] {
    PartMemo::OnTrunk t{core::make_error(core::ErrorCode::kInfeasible, "not made"), {}};
    t.candidate = plan_on_trunk(part, machine, process, o, memo.trunk_splits(process.bead_width_mm)[i], t.why);
    return t;
  });
}

// CHOSEN (auto's choice, WHY its reasons) or, when it is not support-free and the layers are
// automatic, the part split into a trunk and branches (detail::trunk_splits) when that does better.
core::Result<Candidate> with_trunk_splits(core::Result<Candidate> chosen, const mesh::RepairedMesh& part, const machine::MachineConfig& machine,
                                          const process::ProcessConfig& process, const PlanPartOptions& o, PartMemo& memo, std::string& why) {
  if (!chosen || chosen.value().plan.unsupported_area_mm2 == 0.0 || o.plan.layers != LayerChoice::kAuto ||
      !machine::has_rotary_axes(machine.kind)) {
    return chosen;
  }
  std::vector<std::string> tried;
  const auto& splits = memo.trunk_splits(process.bead_width_mm);
  for (std::size_t i = 0; i < splits.size(); ++i) {
    const detail::TrunkSplit& split = splits[i];
    if (!split.refused.empty()) {
      tried.push_back(fmt::format("{} on the trunk: {}", split.label, split.refused));
      continue;
    }
    const auto made = planned_on_trunk(part, machine, process, o, memo, i);
    const std::string& trunk_why = made->why;
    core::Result<Candidate> on_trunk = made->candidate;
    if (!on_trunk) {
      tried.push_back(fmt::format("{} on the trunk: {}", split.label, on_trunk.error().message));
      continue;
    }
    const Plan& p = on_trunk.value().plan;
    if (!better(p, chosen.value().plan)) {
      tried.push_back(fmt::format("{} on the trunk: {} mm2 unsupported", split.label, area_text(p.unsupported_area_mm2)));
      continue;
    }
    why = fmt::format("{} grown on the trunk ({} region{}, {}; the trunk: {}; before: {})", split.label, p.regions, p.regions == 1 ? "" : "s",
                      p.unsupported_area_mm2 == 0.0 ? std::string("support-free") : area_text(p.unsupported_area_mm2) + " mm2 unsupported",
                      trunk_why, why);
    chosen = std::move(on_trunk);
    if (p.unsupported_area_mm2 == 0.0) return chosen;
  }
  if (!tried.empty()) why += fmt::format("; also tried: {}", fmt::join(tried, "; "));
  return chosen;
}

// MEMO: the part's analyses, kept across the calls for one part (the layers do not change them).
core::Result<Candidate> choose(const mesh::RepairedMesh& part, const machine::MachineConfig& machine, const process::ProcessConfig& process,
                               const PlanPartOptions& o, PartMemo& memo, std::string& why) {
  if (o.substrate) return choose_on_substrate(part, machine, process, o, why);
  if (!o.prebuilt.empty()) {
    if (o.strategy == Strategy::kSingle) {
      return core::make_error(core::ErrorCode::kUsage, "--prebuilt names regions of the decomposition; it contradicts --strategy single");
    }
    why = fmt::format("the part's regions, each along its own direction, region{} {} prebuilt (--prebuilt)", o.prebuilt.size() == 1 ? "" : "s",
                      fmt::join(o.prebuilt, ", "));
    return plan_decomposed(part, machine, process, o, o.root_base, memo);
  }
  // The plan on planar layers is kept from the one on automatic layers where that one took them
  // everywhere: as auto's first candidates, under their keys.
  if (o.strategy == Strategy::kSingle) {
    why = "one region along the given direction (--strategy single)";
    return memoized(memo, candidate_key(kOneDirection, o), o, nullptr, [&](auto stop) { return plan_single(part, machine, process, o, stop); });
  }
  if (o.strategy == Strategy::kDecompose) {
    why = "the part's regions, each along its own direction (--strategy decompose)";
    return memoized(memo, candidate_key(kDecomposition, o), o, nullptr,
                    [&](auto stop) { return plan_decomposed(part, machine, process, o, o.root_base, memo, stop); });
  }
  // Auto: one direction; then the decomposition rooted as asked, at the lowest point; then with the
  // part turned over, one direction and the decomposition; the best that succeeds, taken in that
  // order up to the first that is support-free.
  return with_trunk_splits(choose_auto(part, machine, process, o, memo, why), part, machine, process, o, memo, why);
}

// GCODE, PLAN's program, read back: its simulation against the plan and its verification against
// the build model, side by side (they read the same text independently).
detail::ReadBack read_back(const machine::MachineConfig& machine, const process::ProcessConfig& process, const PlanPartOptions& options,
                           const Plan& plan, const std::string& gcode) {
  std::optional<core::Result<verify::SimulationReport>> sim;
  std::optional<core::Result<verify::BuildCheck>> check;
  double simulate_s = 0.0, verify_s = 0.0;
  const auto progress = core::ProgressScope::current();  // each side may run on a worker thread
  tbb::parallel_invoke(
      [&] {
        const core::ProgressScope scope(progress);
        const auto t = Clock::now();
        sim.emplace(verify::simulate(machine, gcode, plan.program, &process, options.gcode.chordal_mm));
        simulate_s = since(t);
      },
      [&] {
        const core::ProgressScope scope(progress);
        const auto t = Clock::now();
        check.emplace(verify::verify_build(machine, process, plan.build_model, gcode));
        verify_s = since(t);
      });
  return detail::ReadBack{std::move(*sim), std::move(*check), simulate_s, verify_s};
}

// The program of a chosen plan: G-code, its simulation against the plan and its verification
// against the build model; OUT.plan is set. A program read back before in this call (MEMO's
// read_backs: the same G-code, program and build model) is not read again: its figures and the
// times first measured are taken.
core::Status program_of(const machine::MachineConfig& machine, const process::ProcessConfig& process, const PlanPartOptions& options,
                        PartMemo& memo, PlanPartResult& out) {
  const Plan& plan = out.plan;
  auto t0 = Clock::now();
  post::GcodeOptions gcode_options = options.gcode;
  gcode_options.stats = &out.gcode_stats;
  auto gcode = post::write_program(machine, process, plan.program, gcode_options);
  if (!gcode) return gcode.error();
  out.gcode = std::move(gcode.value());
  out.gcode_s = since(t0);
  const detail::ReadBackKey key = detail::read_back_key(out.gcode, plan.program, plan.build_model);
  std::optional<detail::ReadBack> read = memo.read_backs().find(key);
  if (!read) {
    read.emplace(read_back(machine, process, options, plan, out.gcode));
    memo.read_backs().keep(key, *read);
  }
  out.simulate_s = read->simulate_s, out.verify_s = read->verify_s;
  if (!read->simulation) return read->simulation.error();
  out.simulation = std::move(read->simulation.value());
  if (out.simulation.limit_violations > 0) {
    return core::make_error(core::ErrorCode::kMachineLimit,
                            fmt::format("the program breaks a machine limit: {}",
                                        out.simulation.violations.empty() ? "" : out.simulation.violations.front()));
  }
  if (!read->check) return read->check.error();
  out.check = std::move(read->check.value());
  return {};
}

// Where the program read back still strikes earlier deposit, or the plate or the table near a
// layer's path, the torch turns further there and the program is made and read back again, at most
// kReliefRounds times, and only while each round strikes less often than the one before.
core::Status relieve(const machine::MachineConfig& machine, const process::ProcessConfig& process, const PlanPartOptions& options,
                     PartMemo& memo, PlanPartResult& out) {
  for (int round = 0; round < kReliefRounds && !out.check.collision_places.empty(); ++round) {
    if (relieve_collisions(out.plan, machine, process, options.plan, out.check.collision_places) == 0) break;
    const std::size_t before = out.check.collisions;
    if (auto s = program_of(machine, process, options, memo, out); !s) return s;
    // A round that struck as often as the one before (the head buried in a feature the torch turns
    // cannot clear) is not followed by another: each costs a whole program and its read-back.
    if (out.check.collisions >= before) break;
  }
  return {};
}

}  // namespace

std::string area_text(double mm2) {
  if (mm2 == 0.0 || std::abs(mm2) >= 0.1) return fmt::format("{:.1f}", mm2);
  return fmt::format("{:.2g}", mm2);
}

const char* strategy_name(Strategy s) {
  switch (s) {
    case Strategy::kSingle: return "single";
    case Strategy::kDecompose: return "decompose";
    case Strategy::kAuto: return "auto";
  }
  return "?";
}

namespace {

// CANDIDATE's program (with its relief rounds) when it can be written and reads back clean: no
// collision, no region starting in mid-air.
std::optional<PlanPartResult> clean_program(core::Result<Candidate> candidate, Strategy strategy, const machine::MachineConfig& machine,
                                            const process::ProcessConfig& process, const PlanPartOptions& options, PartMemo& memo) {
  if (!candidate) return std::nullopt;
  PlanPartResult out;
  out.plan = std::move(candidate.value().plan);
  out.strategy_used = strategy;
  if (!program_of(machine, process, options, memo, out) || !relieve(machine, process, options, memo, out)) return std::nullopt;
  if (out.check.collisions > 0 || !out.check.mid_air_regions.empty()) return std::nullopt;
  return out;
}

// The part split into a trunk and branches (detail::trunk_splits, plan_on_trunk) whose program
// reads back clean, the first support-free one or else the one with the least unsupported area,
// with its label; for a decomposition that failed read-back where one direction overhangs. With
// TO_BEAT (that direction's plan), a split whose plan as chosen is not better() is not programmed:
// the caller would not take it. None unless the layers are automatic.
std::optional<std::pair<PlanPartResult, std::string>> clean_on_trunk(const mesh::RepairedMesh& part, const machine::MachineConfig& machine,
                                                                     const process::ProcessConfig& process, const PlanPartOptions& options,
                                                                     PartMemo& memo, const Plan* to_beat) {
  if (options.plan.layers != LayerChoice::kAuto || !machine::has_rotary_axes(machine.kind)) return std::nullopt;
  std::optional<std::pair<PlanPartResult, std::string>> best;
  const auto& splits = memo.trunk_splits(process.bead_width_mm);
  for (std::size_t i = 0; i < splits.size(); ++i) {
    const detail::TrunkSplit& split = splits[i];
    if (!split.refused.empty()) continue;
    const auto made = planned_on_trunk(part, machine, process, options, memo, i);
    const std::string& trunk_why = made->why;
    // Not programmed where, as chosen, it cannot win.
    if (!made->candidate || (to_beat != nullptr && !better(made->candidate.value().plan, *to_beat))) continue;
    auto clean = clean_program(made->candidate, Strategy::kDecompose, machine, process, options, memo);
    if (!clean || (best && !better(clean->plan, best->first.plan))) continue;
    best.emplace(std::move(*clean), fmt::format("{} grown on the trunk (the trunk: {})", split.label, trunk_why));
    if (best->first.plan.unsupported_area_mm2 == 0.0) break;
  }
  return best;
}

// Directions to build REGIONS[I] along in place of its own: its base's normal, half-way to it, its
// parent's direction and half-way to that, each with its name, at least kRedirectMinDeg from its own
// direction and from those before it.
std::vector<std::pair<Vec3, std::string>> other_directions(const std::vector<PlanRegion>& regions, std::size_t i) {
  const PlanRegion& r = regions[i];
  const Vec3 own = core::normalized(r.direction);
  std::vector<std::pair<Vec3, std::string>> tries;
  auto add = [&](Vec3 d, std::string name) {
    if (!(core::norm(d) > 0.0)) return;
    d = core::normalized(d);
    const double min_cos = std::cos(kRedirectMinDeg * std::numbers::pi / 180.0);
    if (core::dot(d, own) > min_cos) return;
    for (const auto& t : tries) {
      if (core::dot(d, t.first) > min_cos) return;
    }
    tries.emplace_back(d, std::move(name));
  };
  const Vec3 base = core::normalized(r.base_normal);
  add(base, "its base's normal");
  add(own + base, "half-way to its base's normal");
  for (const PlanRegion& p : regions) {
    if (!r.parent || p.id != *r.parent) continue;
    const Vec3 up = core::normalized(p.direction);
    add(up, fmt::format("its parent's direction (region {})", p.id));
    add(own + up, fmt::format("half-way to its parent's direction (region {})", p.id));
  }
  return tries;
}

// The first region (index into REGIONS) struck while being built in RESULT's program that is not the
// root, not prebuilt and not in DONE; none: SIZE_MAX.
std::size_t first_struck(const std::vector<PlanRegion>& regions, const PlanPartResult& result, const std::vector<std::size_t>& done) {
  for (const verify::Collision& c : result.check.collision_list) {
    for (std::size_t i = 0; i < regions.size(); ++i) {
      const PlanRegion& r = regions[i];
      if (static_cast<std::int64_t>(r.id) == c.region && r.parent && !r.prebuilt && std::find(done.begin(), done.end(), i) == done.end()) return i;
    }
  }
  return SIZE_MAX;
}

// REGIONS with region I built along DIRECTION (other_directions: the direction and its name) in
// place of the direction along which the head struck something in CURRENT: its regions, whether
// its plan took planar layers in every region (false when none could be made), and its program,
// relieved and read back, where it could be written and no region starts in mid-air.
struct Redirection {
  std::vector<PlanRegion> regions;
  bool planar = false;
  std::optional<PlanPartResult> read;
};

Redirection redirection(const mesh::RepairedMesh& part, const machine::MachineConfig& machine, const process::ProcessConfig& process,
                        const PlanPartOptions& options, PartMemo& memo, const PlanOptions& plan_options, const std::vector<PlanRegion>& regions,
                        std::size_t i, const PlanPartResult& current, const std::pair<Vec3, std::string>& direction) {
  Redirection t;
  t.regions = regions;
  PlanRegion& r = t.regions[i];
  const Vec3 was = core::normalized(r.direction);
  r.direction_rule = kDirectionRedirected;
  r.direction_why = fmt::format("along {} the head struck something at {} samples (the first: {}); built along {} instead", direction_text(was),
                                current.check.collisions, describe(current.check.collision_list.front()), direction.second);
  r.direction = direction.first;
  auto plan = make_plan(part, machine, process, plan_options, t.regions);
  t.planar = plan && turned_layers(plan.value()).empty();
  if (!plan) return t;
  PlanPartResult out;
  out.plan = std::move(plan.value());
  out.strategy_used = Strategy::kDecompose;
  if (!program_of(machine, process, options, memo, out) || !relieve(machine, process, options, memo, out) || !out.check.mid_air_regions.empty()) return t;
  t.read = std::move(out);
  return t;
}

// SOURCE's decomposition, whose program (STRUCK) strikes something no build order or torch tilt
// cleared, with the region first struck while being built along other directions
// (other_directions), one at a time; one the support check finds support-free must read back with
// no more beads over nothing than STRUCK. Where none reads back clean, the one that clears that region
// itself with the least overhang is kept and the next region it struck (a region built on it, say)
// is tried in turn, kRedirectRegions regions at most. Each redirected region is marked
// kDirectionRedirected. The best (better()) of the programs that read back clean; the first
// support-free one ends the search.
// ALL_PLANAR is cleared where a plan it made took other than planar layers somewhere, or could not
// be made.
std::optional<PlanPartResult> redirected_search(const mesh::RepairedMesh& part, const machine::MachineConfig& machine,
                                                const process::ProcessConfig& process, const PlanPartOptions& options, PartMemo& memo,
                                                const Candidate& source, const PlanPartResult& struck, bool& all_planar) {
  std::vector<PlanRegion> regions = source.regions;
  std::vector<std::size_t> done;
  std::optional<PlanPartResult> best, next;
  const PlanPartResult* current = &struck;
  const auto progress = core::ProgressScope::current();  // each try may run on a worker thread
  while (done.size() < kRedirectRegions) {
    const std::size_t i = first_struck(regions, *current, done);
    if (i == SIZE_MAX) break;
    done.push_back(i);
    // The directions are planned, programmed and read back side by side, then taken in their order
    // as one after the other would: the same outcome, and the plans past the first support-free one
    // made for nothing.
    const auto directions = other_directions(regions, i);
    std::vector<Redirection> tries(directions.size());
    tbb::parallel_for(std::size_t{0}, directions.size(), [&](std::size_t k) {
      const core::ProgressScope scope(progress);
      tries[k] = redirection(part, machine, process, options, memo, source.plan_options, regions, i, *current, directions[k]);
    });
    std::optional<std::pair<PlanPartResult, std::vector<PlanRegion>>> carry;  // clears region I, least overhang
    for (Redirection& t : tries) {
      all_planar = all_planar && t.planar;
      if (!t.read) continue;
      PlanPartResult& out = *t.read;
      // Support-free by the support check yet, read back, more beads over nothing than as
      // decomposed: a direction at the very limit of the check, which the read-back's grounding
      // rule does not let through (a bar leaning 60° built along a 30° lean, α = 30°).
      if (out.plan.unsupported_area_mm2 == 0.0 && out.check.ungrounded_samples > struck.check.ungrounded_samples) continue;
      if (out.check.collisions == 0) {
        if (!best || better(out.plan, best->plan)) best = std::move(out);
        if (best->plan.unsupported_area_mm2 == 0.0) return best;
        continue;
      }
      const bool clears = std::none_of(out.check.collision_list.begin(), out.check.collision_list.end(),
                                       [&](const verify::Collision& c) { return c.region == static_cast<std::int64_t>(t.regions[i].id); });
      if (clears && (!carry || out.plan.unsupported_area_mm2 < carry->first.plan.unsupported_area_mm2)) carry.emplace(std::move(out), std::move(t.regions));
    }
    if (best || !carry) break;
    next = std::move(carry->first);
    regions = std::move(carry->second);
    current = &*next;
  }
  return best;
}

// redirected_search, made once for a planar candidate of choose_auto (PartMemo::redirected).
std::optional<PlanPartResult> redirected(const mesh::RepairedMesh& part, const machine::MachineConfig& machine,
                                         const process::ProcessConfig& process, const PlanPartOptions& options, PartMemo& memo,
                                         const Candidate& source, const PlanPartResult& struck) {
  const bool keyed = !source.memo_key.empty() && turned_layers(source.plan).empty();
  if (keyed) {
    if (auto kept = memo.redirected(source.memo_key)) return *kept;
  }
  bool all_planar = true;
  auto outcome = redirected_search(part, machine, process, options, memo, source, struck, all_planar);
  if (keyed && all_planar) memo.keep_redirected(source.memo_key, outcome);
  return outcome;
}

// One direction in place of a decomposition whose program failed: upright and, where auto may turn
// the part over, turned over and stood on a side face (side_direction) too, the better first (as
// choose_auto takes them); the first that reads back clean, with its label.
std::optional<std::pair<PlanPartResult, std::string>> clean_single(const mesh::RepairedMesh& part, const machine::MachineConfig& machine,
                                                                   const process::ProcessConfig& process, const PlanPartOptions& options,
                                                                   PartMemo& memo) {
  std::vector<std::pair<core::Result<Candidate>, const char*>> tries;
  tries.emplace_back(plan_single(part, machine, process, options), kAutoLabels[kOneDirection]);
  if (options.root_base.kind == analysis::RootBase::Kind::kAuto) {
    PlanPartOptions over = options;
    over.direction = options.direction * -1.0;
    tries.emplace_back(plan_single(part, machine, process, over), kAutoLabels[kOneTurnedOver]);
    if (const auto side = side_direction(part.mesh, options.direction, process)) {
      PlanPartOptions lying = options;
      lying.direction = *side;
      tries.emplace_back(plan_single(part, machine, process, lying), kAutoLabels[kOneOnASide]);
    }
    // The better first (as choose_auto takes them), the earlier on a tie.
    std::stable_sort(tries.begin(), tries.end(), [](const auto& a, const auto& b) {
      return a.first && (!b.first || better(a.first.value().plan, b.first.value().plan));
    });
  }
  for (auto& [candidate, label] : tries) {
    if (auto clean = clean_program(std::move(candidate), Strategy::kSingle, machine, process, options, memo)) return std::pair{std::move(*clean), std::string(label)};
  }
  return std::nullopt;
}

// auto's one direction in place of a failed decomposition (clean_single), made on first use.
class SingleFallback {
 public:
  SingleFallback(const mesh::RepairedMesh& part, const machine::MachineConfig& machine, const process::ProcessConfig& process,
                 const PlanPartOptions& options, PartMemo& memo)
      : part_(part), machine_(machine), process_(process), options_(options), memo_(memo) {}
  std::optional<std::pair<PlanPartResult, std::string>>& get() {
    if (!made_) made_.emplace(clean_single(part_, machine_, process_, options_, memo_));
    return *made_;
  }

 private:
  const mesh::RepairedMesh& part_;
  const machine::MachineConfig& machine_;
  const process::ProcessConfig& process_;
  const PlanPartOptions& options_;
  PartMemo& memo_;
  std::optional<std::optional<std::pair<PlanPartResult, std::string>>> made_;
};

// No build order or torch tilt cleared the head in OUT, CHOSEN's decomposition (relieve): the
// regions it struck in, along other directions (redirected; Dwivedi's rule base: the region's
// direction before giving up). With auto, one direction (SINGLE: upright, turned over or on a side
// face) that leaves less overhang, or as little in one region, wins (and is taken by the caller).
// True when OUT was replaced by the redirected plan, with its choice and a warning naming why.
bool take_redirected(const mesh::RepairedMesh& part, const machine::MachineConfig& machine, const process::ProcessConfig& process,
                     const PlanPartOptions& options, PartMemo& memo, const Candidate& chosen, SingleFallback& single, PlanPartResult& out) {
  auto alt = redirected(part, machine, process, options, memo, chosen, out);
  if (!alt) return false;
  if (options.strategy == Strategy::kAuto) {
    if (auto& one = single.get(); one && better(one->first.plan, alt->plan)) return false;
  }
  std::string why;
  for (const PlanRegion& r : alt->plan.placed_regions) {
    if (r.direction_rule == kDirectionRedirected) why += fmt::format("{}region {}: {}", why.empty() ? "" : "; ", r.id, r.direction_why);
  }
  why += fmt::format(" ({} mm2 unsupported)", area_text(alt->plan.unsupported_area_mm2));
  alt->choice = out.choice + "; " + why;
  alt->warnings = out.warnings;
  alt->warnings.push_back(why);
  alt->axis = std::move(out.axis);
  out = std::move(*alt);
  return true;
}

// OUT as plan_part returns it: its warnings (feeds the machine slows, robot wrist and
// configuration, thin regions, overhang, collisions kept, a region in mid-air), or kInfeasible
// naming the first collisions unless OPTIONS allow them.
core::Result<PlanPartResult> finished(PlanPartResult out, const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                      const PlanPartOptions& options) {
  if (!out.plan.fidelity.measured) measure_plan_fidelity(out.plan, process);
  const Plan& plan = out.plan;
  // Catalogue O3: a linear maximum below the process's feeds slows moves below the planned feed
  // (F100 on every move): a warning with the count. Slowing where the rotary axes turn (and the
  // linear axes with them) is ordinary on a 5-axis machine and not warned of.
  const bool slow_machine = machine.feed.linear_max_mm_min < 60.0 * std::max(process.deposit_feed_mm_s, process.travel_feed_mm_s);
  if (const post::GcodeStats& g = out.gcode_stats; slow_machine && g.linear_limited > 0) {
    out.warnings.push_back(fmt::format("{} of {} feed blocks run slower than planned: the machine's linear maximum "
                                       "(feed.linear_max_mm_min {} mm/min) is below the process's feed there",
                                       g.linear_limited, g.feed_blocks, machine.feed.linear_max_mm_min));
  }
  if (const post::GcodeStats& g = out.gcode_stats; machine.robot && g.robot_near_singular > 0) {
    out.warnings.push_back(fmt::format("{} of {} robot targets hold the wrist within robot.wrist_margin_deg ({}°) of its singularity "
                                       "(smallest |axis 5| {:.2f}°): the controller may slow down or turn axes 4 and 6 fast there",
                                       g.robot_near_singular, g.robot_targets, machine.robot->wrist_margin_deg, g.robot_min_wrist_deg));
  }
  if (const post::GcodeStats& g = out.gcode_stats; machine.robot && g.robot_config_changes > 0) {
    out.warnings.push_back(fmt::format("the robot changes its configuration {} times, each on a joint move (MoveJ) with the process off",
                                       g.robot_config_changes));
  }
  if (const std::uint64_t restarts = out.gcode_stats.stall_splits; restarts > 0 && process.dwell_on_s > 0.0) {
    // Each turn in place is a bead stopped and started again (a seam, and metal where it restarts)
    // with the process's dwell: worth knowing where they take a noticeable share of the build.
    const double dwell_s = static_cast<double>(restarts) * process.dwell_on_s, total_s = out.simulation.build_time.total_s;
    if (total_s > 0.0 && dwell_s >= kStallRestartWarnShare * total_s) {
      out.warnings.push_back(fmt::format("the process is switched off and on again {} times where the rotary axes cannot turn the torch as "
                                         "fast as the tip moves (a turn in place each; {:.0f} s of dwell, {:.0f} % of the build time): "
                                         "layers whose normal turns less along a contour (planar ones) or faster rotary axes "
                                         "(machine feed.rotary_max_deg_min) avoid them",
                                         restarts, dwell_s, 100.0 * dwell_s / total_s));
    }
  }
  if (plan.thin_regions > 0) {
    out.warnings.push_back(fmt::format("{} regions thinner than a bead ({:.1f} mm2) get no path; see plan.json", plan.thin_regions,
                                       plan.thin_area_mm2));
  }
  if (plan.unsupported_area_mm2 > 0.0) {
    out.warnings.push_back(fmt::format("the plan is not support-free: {} mm2 unsupported (report.html shows the pieces in red)",
                                       area_text(plan.unsupported_area_mm2)));
  }
  if (out.check.collisions > 0 && !out.check.collision_list.empty()) {
    std::string first;
    for (std::size_t i = 0; i < out.check.collision_list.size() && i < kNamedCollisions; ++i) {
      first += (i ? "; " : "") + describe(out.check.collision_list[i]);
    }
    const std::uint64_t prebuilt = out.check.prebuilt_collisions;
    const std::string what = fmt::format("read back, the head strikes something at {} samples (the plate or table at {}, earlier deposit "
                                         "at {}{}); the first: {}",
                                         out.check.collisions, out.check.head_collisions, out.check.material_collisions - prebuilt,
                                         prebuilt > 0 ? fmt::format(", the prebuilt part at {}", prebuilt) : std::string(), first);
    if (!options.allow_collisions) {
      return core::make_error(core::ErrorCode::kInfeasible,
                              fmt::format("{}: no build order or torch tilt removed them; a slimmer head (machine nozzle), another "
                                          "strategy, or --allow-collisions to write the plan for inspection",
                                          what));
    }
    out.warnings.push_back(what + "; report.html shows them in red");
  }
  if (!out.check.mid_air_regions.empty()) {
    out.warnings.push_back(fmt::format("read back, region {} starts in mid-air: its first bead rests on nothing", out.check.mid_air_regions.front()));
  }
  if (out.check.ungrounded_samples > 0) {
    // Beads over the overhang reported above, or over a gap between the beads of the layer below
    // that the layers' own check, made on their sections, does not see.
    const auto first = std::find_if(out.check.first_problems.begin(), out.check.first_problems.end(),
                                    [](const std::string& p) { return p.find(verify::kUngroundedProblem) != std::string::npos; });
    out.warnings.push_back(fmt::format("read back, {} of {} deposit samples rest on no earlier deposit within {:.3f} mm under them and {:.3f} mm "
                                       "across{}",
                                       out.check.ungrounded_samples, out.check.deposit_samples, out.check.ground_mm, out.check.ground_lateral_mm,
                                       first == out.check.first_problems.end() ? std::string() : "; the first: " + *first));
  }
  return out;
}

// plan_part with the layers OPTIONS.plan.layers asks for (plan_part adds the comparison of auto
// layers with planar ones). With TO_BEAT (the figures of the choice behind a program that reads
// back clean, MADE_FROM of that call), a choice that is not better (better()) is not programmed:
// what follows the choice (relief, the regions turned elsewhere, the fallbacks to one direction)
// is made to clear collisions, not overhang, and each of its alternatives was ranked below the
// choice, so it cannot win. Its figures go to OUTDONE and the result is an error. MADE_FROM: the
// figures of the plan the result's program was made from, as chosen (before relief, which turns
// the torch and may add reorientations: choices are compared as chosen, or the same choice made
// again would seem the better and be programmed twice).
core::Result<PlanPartResult> plan_part_as_asked(const mesh::RepairedMesh& part, const machine::MachineConfig& machine,
                                                const process::ProcessConfig& process, const PlanPartOptions& options, PartMemo& memo,
                                                const Figures* to_beat = nullptr, std::optional<Figures>* outdone = nullptr,
                                                Figures* made_from = nullptr) {
  PlanPartResult out;
  auto chosen = choose(part, machine, process, options, memo, out.choice);
  if (chosen && to_beat != nullptr && !better(Figures::of(chosen.value().plan), *to_beat)) {
    if (outdone != nullptr) outdone->emplace(Figures::of(chosen.value().plan));
    return core::make_error(core::ErrorCode::kInfeasible, "outdone before its program");
  }
  if (chosen && made_from != nullptr) *made_from = Figures::of(chosen.value().plan);
  if (!chosen) {
    if (options.plan.layers != LayerChoice::kAuto) return chosen.error();
    // Layers auto chose that cannot be planned (no torch axis keeps the head off the plate along
    // tilted layers, say): the whole choice again on planar layers, when that reads back clean.
    PlanPartOptions planar = options;
    planar.plan.layers = LayerChoice::kPlanar;
    auto alt = plan_part_as_asked(part, machine, process, planar, memo, nullptr, nullptr, made_from);
    if (!alt || alt.value().check.collisions > 0 || !alt.value().check.mid_air_regions.empty()) return chosen.error();
    const std::string why = fmt::format("the layers auto chose cannot be planned: {}", chosen.error().message);
    alt.value().choice += fmt::format("; planar layers: {}", why);
    for (PlanRegion& r : alt.value().plan.placed_regions) r.layers_rule = kLayersPlanar, r.layers_why = "auto layers were refused: " + why;
    alt.value().warnings.push_back(fmt::format("planar layers were chosen because {}", why));
    return alt;
  }
  out.plan = std::move(chosen.value().plan);
  out.axis = std::move(chosen.value().axis);
  out.strategy_used = chosen.value().strategy;
  out.warnings = std::move(chosen.value().warnings);
  core::Status made = program_of(machine, process, options, memo, out);
  if (made) made = relieve(machine, process, options, memo, out);
  bool mid_air = made && !out.check.mid_air_regions.empty(), collides = made && out.check.collisions > 0;
  const std::string turned = turned_layers(out.plan);
  if (options.plan.layers == LayerChoice::kAuto && !turned.empty() && (!made || mid_air || collides)) {
    // Tilted or conformal layers whose program cannot be written or, read back, starts in mid-air or strikes
    // something (the torch turned with the layers brings the head down to the plate): the whole
    // choice again on planar layers, when that reads back clean.
    PlanPartOptions planar = options;
    planar.plan.layers = LayerChoice::kPlanar;
    Figures planar_made;
    auto alt = plan_part_as_asked(part, machine, process, planar, memo, nullptr, nullptr, &planar_made);
    if (alt && alt.value().check.collisions == 0 && alt.value().check.mid_air_regions.empty()) {
      if (made_from != nullptr) *made_from = planar_made;
      const std::string why = !made     ? fmt::format("the {} layers' program cannot be written: {}", turned, made.error().message)
                              : mid_air ? fmt::format("read back, the {} layers' region {} starts in mid-air", turned, out.check.mid_air_regions.front())
                                        : fmt::format("read back, the {} layers' program strikes something at {} samples (the first: {})", turned,
                                                      out.check.collisions, describe(out.check.collision_list.front()));
      alt.value().choice += fmt::format("; planar layers: {}", why);
      for (PlanRegion& r : alt.value().plan.placed_regions) r.layers_rule = kLayersPlanar, r.layers_why = turned + " layers were refused: " + why;
      alt.value().warnings.push_back(fmt::format("planar layers were chosen because {}", why));
      return alt;
    }
  }
  if (options.strategy == Strategy::kAuto && options.substrate && out.strategy_used == Strategy::kSingle && (!made || mid_air || collides)) {
    // On a substrate, one direction whose program cannot be written, or read back starts in
    // mid-air or strikes something: each piece along the substrate's normal under it, when that
    // reads back clean.
    const auto on = part_less_substrate(part, options);
    auto pieces = on ? plan_on_substrate(part, machine, process, options, on.value(), true) : core::Result<Candidate>(on.error());
    if (auto clean = clean_program(std::move(pieces), Strategy::kDecompose, machine, process, options, memo)) {
      PlanPartResult& alt = *clean;
      const std::string why = !made     ? fmt::format("along the given direction the program cannot be written: {}", made.error().message)
                              : mid_air ? std::string("along the given direction the deposit starts in mid-air")
                                        : fmt::format("along the given direction the program read back strikes something at {} samples "
                                                      "(the first: {})",
                                                      out.check.collisions, describe(out.check.collision_list.front()));
      alt.choice = fmt::format("the part less the substrate, each piece along the substrate's normal under it (--substrate): {}", why);
      alt.warnings = {fmt::format("each piece on the substrate is built along the substrate's normal under it because {}", why)};
      out = std::move(alt);
      if (made_from != nullptr) *made_from = Figures::of(out.plan);
      made = {}, mid_air = false, collides = false;
    }
  }
  // auto's one direction in place of a failed decomposition (clean_single), made once when asked.
  SingleFallback single(part, machine, process, options, memo);
  if (options.redirect_regions && made && collides && !mid_air && out.strategy_used == Strategy::kDecompose && options.prebuilt.empty() &&
      !options.substrate) {
    collides = !take_redirected(part, machine, process, options, memo, chosen.value(), single, out);
    if (!collides && made_from != nullptr) *made_from = Figures::of(out.plan);
  }
  if (options.strategy == Strategy::kAuto && options.prebuilt.empty() && !options.substrate && out.strategy_used == Strategy::kDecompose && (!made || mid_air || collides)) {
    // The decomposition's program cannot be written (a limit of the machine that only shows in
    // the program, such as C winding past its end stops on a tilted region), or, read back, a
    // region starts in mid-air, or the head strikes something no order or tilt could avoid: one
    // direction instead (upright, turned over or on a side face), when that one reads back clean.
    auto& clean = single.get();
    if (!clean || clean->first.plan.unsupported_area_mm2 > 0.0) {
      // Where one direction overhangs, the trunk and its branches may not.
      if (auto trunk = clean_on_trunk(part, machine, process, options, memo, clean ? &clean->first.plan : nullptr); trunk && (!clean || better(trunk->first.plan, clean->first.plan))) {
        clean.emplace(std::move(trunk->first), std::move(trunk->second));
      }
    }
    if (clean) {
      auto& [alt, label] = *clean;
      const std::string why =
          !made     ? fmt::format("the decomposition's program cannot be written: {}", made.error().message)
          : mid_air ? fmt::format("read back, the decomposition's region {} starts in mid-air", out.check.mid_air_regions.front())
                    : fmt::format("read back, the decomposition's program strikes something at {} samples (the first: {})", out.check.collisions,
                                  describe(out.check.collision_list.front()));
      alt.choice = fmt::format("{} ({} mm2 unsupported): {}", label, area_text(alt.plan.unsupported_area_mm2), why);
      alt.warnings = {fmt::format("{} was chosen because {}", label, why)};
      out = std::move(alt);
      if (made_from != nullptr) *made_from = Figures::of(out.plan);
      made = {};
    }
  }
  if (!made) return made.error();
  return finished(std::move(out), machine, process, options);
}

}  // namespace

namespace {

core::Result<PlanPartResult> plan_part_chosen(const mesh::RepairedMesh& part, const machine::MachineConfig& machine,
                                              const process::ProcessConfig& process, const PlanPartOptions& asked) {
  PlanPartOptions options = asked;
  if (options.gcode.part == nullptr) options.gcode.part = &part.mesh;  // the posts that carry the part (3MF toolpath)
  // Of the many plans a choice makes, only the one it returns is measured (finished()).
  options.plan.measure_fidelity = false;
  PartMemo memo(part);
  Figures first_made;
  auto first = plan_part_as_asked(part, machine, process, options, memo, nullptr, nullptr, &first_made);
  if (options.plan.layers != LayerChoice::kAuto || !first) return first;
  const std::string turned_or_none = turned_layers(first.value().plan);
  if (turned_or_none.empty() && first.value().plan.unsupported_area_mm2 == 0.0) return first;
  // Auto layers took tilted or conformal ones somewhere, judged region by region on the slices alone,
  // or the plan still overhangs (its choice passed over candidates whose regions took such layers: a
  // decomposition on planar layers may be support-free where the same regions on tilted ones are
  // not): the whole choice on planar layers too, and the better plan as built (read back clean first,
  // then less unsupported area, fewer regions, fewer reorientations).
  const std::string turned = turned_or_none.empty() ? std::string("automatic") : turned_or_none;
  PlanPartOptions planar_options = options;
  planar_options.plan.layers = LayerChoice::kPlanar;
  auto clean = [](const PlanPartResult& r) { return r.check.collisions == 0 && r.check.mid_air_regions.empty(); };
  std::optional<Figures> outdone;
  auto planar = plan_part_as_asked(part, machine, process, planar_options, memo, clean(first.value()) ? &first_made : nullptr, &outdone);
  if (outdone) {
    // Both as chosen, as they were compared (relief may have added reorientations since).
    const Figures& kept = first_made;
    first.value().choice += fmt::format("; {} layers: {} mm2 unsupported, {} region{}, {} reorientations as chosen against {}, {}, {} on planar layers (chosen, not programmed)",
                                        turned, area_text(kept.unsupported_area_mm2), kept.regions, kept.regions == 1 ? "" : "s", kept.reorientations,
                                        area_text(outdone->unsupported_area_mm2), outdone->regions, outdone->reorientations);
    return first;
  }
  if (!planar) return first;
  const bool take_planar = clean(planar.value()) != clean(first.value()) ? clean(planar.value()) : better(planar.value().plan, first.value().plan);
  PlanPartResult& kept = take_planar ? planar.value() : first.value();
  const PlanPartResult& other = take_planar ? first.value() : planar.value();
  const std::string versus = fmt::format("{} mm2 unsupported, {} region{}, {} reorientations against {}, {}, {} on {} layers",
                                         area_text(kept.plan.unsupported_area_mm2), kept.plan.regions, kept.plan.regions == 1 ? "" : "s", kept.plan.reorientations,
                                         area_text(other.plan.unsupported_area_mm2), other.plan.regions, other.plan.reorientations,
                                         take_planar ? turned : "planar");
  kept.choice += fmt::format("; {} layers: {}", take_planar ? "planar" : turned, versus);
  if (take_planar) {
    for (PlanRegion& r : kept.plan.placed_regions) r.layers_rule = kLayersPlanar, r.layers_why = "the plan on planar layers is the better: " + versus;
  }
  return std::move(kept);
}

// plan_part_chosen, with PlanPartResult::choose_s: all of it but the kept program's G-code,
// simulation and verification (the choices dropped, programs made and read back, relief rounds).
core::Result<PlanPartResult> plan_part_in_arena(const mesh::RepairedMesh& part, const machine::MachineConfig& machine,
                                                const process::ProcessConfig& process, const PlanPartOptions& asked) {
  const auto t0 = Clock::now();
  auto result = plan_part_chosen(part, machine, process, asked);
  if (result) {
    PlanPartResult& r = result.value();
    r.choose_s = std::max(0.0, since(t0) - (r.gcode_s + r.simulate_s + r.verify_s));
  }
  return result;
}

}  // namespace

core::Result<PlanPartResult> plan_part(const mesh::RepairedMesh& part, const machine::MachineConfig& machine,
                                       const process::ProcessConfig& process, const PlanPartOptions& options) {
  core::ProgressScope scope(options.progress);
  return core::with_threads(options.plan.threads, [&] { return plan_part_in_arena(part, machine, process, options); });
}

}  // namespace polyaxis::planner
