#include "polyaxis/verify/verify.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <array>
#include <optional>
#include <unordered_map>
#include <map>
#include <functional>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "gcode_walk.h"
#include "head_material.h"
#include "polyaxis/machine/kinematics.h"

namespace polyaxis::verify {
namespace {

using core::Vec3;
using machine::MachinePose;

constexpr std::size_t kMaxProblems = 10;
// Samples along a move: at most this far apart (share of the bead) and this much rotation apart.
constexpr double kSampleBeadShare = 0.25;
constexpr double kSampleDeg = 1.0;
// The head is checked against the material at most this far apart (share of the bead, and degrees
// of axis turn); between checks the margin grows by half the gap.
constexpr double kQueryBeads = 1.5;
constexpr double kQueryDeg = 1.5;
// The deposit is kept for the head check as samples at most this far apart (share of the bead).
constexpr double kMaterialBeads = 0.5;
// A check that comes within its margin only is done again this many times finer along the motion.
constexpr int kRefinePieces = 16;


// Earlier deposit, bucketed in cubes of the grounding distance.
class DepositGrid {
 public:
  explicit DepositGrid(double cell_mm) : cell_(cell_mm) {}
  DepositGrid(const DepositGrid&) = delete;
  DepositGrid& operator=(const DepositGrid&) = delete;
  void add(Vec3 p) {
    // Consecutive deposit samples mostly share a cell: the last one's list is kept at hand.
    const std::uint64_t k = key(cell(p.x), cell(p.y), cell(p.z));
    if (last_ == nullptr || k != last_key_) last_ = &cells_[k], last_key_ = k;
    last_->push_back({static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)});
  }
  // A stored point in the cells around P for which PRED holds, none when there is none; the cell
  // holding HINT (where a match is most likely) is searched first.
  template <typename Pred>
  std::optional<Vec3> find(Vec3 p, Vec3 hint, Pred pred) const {
    std::optional<Vec3> found;
    auto visit = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
      const auto it = cells_.find(key(x, y, z));
      if (it == cells_.end()) return false;
      for (const auto& q : it->second) {
        if (const Vec3 v{q[0], q[1], q[2]}; pred(v)) return found = v, true;
      }
      return false;
    };
    const std::int64_t hx = cell(hint.x), hy = cell(hint.y), hz = cell(hint.z);
    if (visit(hx, hy, hz)) return found;
    const std::int64_t cx = cell(p.x), cy = cell(p.y), cz = cell(p.z);
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          if (cx + dx == hx && cy + dy == hy && cz + dz == hz) continue;
          if (visit(cx + dx, cy + dy, cz + dz)) return found;
        }
      }
    }
    return found;
  }

 private:
  std::int64_t cell(double v) const { return static_cast<std::int64_t>(std::floor(v / cell_)); }
  static std::uint64_t key(std::int64_t x, std::int64_t y, std::int64_t z) {
    // 21 bits a coordinate: cells of ~1 mm cover ±1 km.
    auto b = [](std::int64_t v) { return static_cast<std::uint64_t>(v + (1 << 20)) & 0x1FFFFF; };
    return b(x) << 42 | b(y) << 21 | b(z);
  }
  double cell_;
  // Node-based: a list's address stays valid while others are added.
  std::unordered_map<std::uint64_t, std::vector<std::array<float, 3>>> cells_;
  std::vector<std::array<float, 3>>* last_ = nullptr;
  std::uint64_t last_key_ = 0;
};

// A layer's deposit samples, held until the layer ends: its plane is fitted to all of them.
struct Pending {
  Vec3 tip, axis;
  std::uint64_t line;
  std::int64_t layer, region;
  bool first_of_region;
};

// The unit eigenvector of the smallest eigenvalue of the symmetric 3×3 matrix C (Jacobi), and
// the middle eigenvalue (to tell a plane from a line).
Vec3 smallest_eigenvector(double c[3][3], double& middle) {
  double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int sweep = 0; sweep < 50; ++sweep) {
    const double off = c[0][1] * c[0][1] + c[0][2] * c[0][2] + c[1][2] * c[1][2];
    if (off < 1e-30) break;
    for (int p = 0; p < 2; ++p) {
      for (int q = p + 1; q < 3; ++q) {
        if (std::abs(c[p][q]) < 1e-300) continue;
        const double theta = (c[q][q] - c[p][p]) / (2.0 * c[p][q]);
        const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
        const double cs = 1.0 / std::sqrt(t * t + 1.0), sn = t * cs;
        for (int k = 0; k < 3; ++k) {  // C ← Jᵀ C J, V ← V J
          const double ckp = c[k][p], ckq = c[k][q];
          c[k][p] = cs * ckp - sn * ckq;
          c[k][q] = sn * ckp + cs * ckq;
        }
        for (int k = 0; k < 3; ++k) {
          const double cpk = c[p][k], cqk = c[q][k];
          c[p][k] = cs * cpk - sn * cqk;
          c[q][k] = sn * cpk + cs * cqk;
        }
        for (int k = 0; k < 3; ++k) {
          const double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = cs * vkp - sn * vkq;
          v[k][q] = sn * vkp + cs * vkq;
        }
      }
    }
  }
  int order[3] = {0, 1, 2};
  std::sort(order, order + 3, [&](int a, int b) { return c[a][a] < c[b][b]; });
  middle = c[order[1]][order[1]];
  return core::normalized(Vec3{v[0][order[0]], v[1][order[0]], v[2][order[0]]});
}

// The normal of the plane a layer's samples lie on, turned to the side of their mean tool axis;
// for samples along one line (or fewer than three), the mean axis made square to that line. CURVED
// (when given) is set when the samples stand off that plane by more than SPREAD_MM (root mean
// square): a curved (conformal) layer, whose normal at each sample is its tool axis.
Vec3 layer_normal(const std::vector<Pending>& samples, double spread_mm, bool* curved = nullptr) {
  Vec3 mean, axis;
  for (const Pending& s : samples) mean = mean + s.tip, axis = axis + s.axis;
  mean = mean / static_cast<double>(samples.size());
  axis = core::normalized(axis);
  double c[3][3] = {};
  for (const Pending& s : samples) {
    const Vec3 d = s.tip - mean;
    const double e[3] = {d.x, d.y, d.z};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) c[i][j] += e[i] * e[j];
    }
  }
  for (auto& row : c) {
    for (double& x : row) x /= static_cast<double>(samples.size());
  }
  double middle = 0.0;
  const Vec3 n = smallest_eigenvector(c, middle);
  if (curved != nullptr) {
    double off = 0.0;  // the variance along n
    for (const Pending& s : samples) off += core::dot(s.tip - mean, n) * core::dot(s.tip - mean, n);
    *curved = samples.size() >= 3 && off / static_cast<double>(samples.size()) > spread_mm * spread_mm;
  }
  if (samples.size() < 3 || middle < spread_mm * spread_mm) return axis;
  return core::dot(n, axis) < 0.0 ? n * -1.0 : n;
}

// A sampled pose of the head, to be checked against the material laid before it.
struct HeadQuery {
  std::array<float, 3> tip, axis;
  std::uint32_t before = 0;  // material samples laid before it
  float gap_mm = 0.0f, gap_rad = 0.0f;  // the tip's travel and the axis's turn since the previous sample
  std::uint32_t line = 0;
  std::int32_t layer = 0, region = 0;
};

Vec3 vec(const std::array<float, 3>& a) { return {a[0], a[1], a[2]}; }

// A head pose between samples: the tip straight, the axis along the chord (the samples are at
// most a quarter bead and 1° apart, so the chord is the motion within a few micrometres).
HeadQuery between(const HeadQuery& a, const HeadQuery& b, double u) {
  HeadQuery q = b;
  for (int k = 0; k < 3; ++k) {
    q.tip[k] = static_cast<float>(a.tip[k] + (b.tip[k] - a.tip[k]) * u);
    q.axis[k] = static_cast<float>(a.axis[k] + (b.axis[k] - a.axis[k]) * u);
  }
  const Vec3 axis = core::normalized(vec(q.axis));
  q.axis = {static_cast<float>(axis.x), static_cast<float>(axis.y), static_cast<float>(axis.z)};
  q.gap_mm = static_cast<float>(b.gap_mm / kRefinePieces), q.gap_rad = static_cast<float>(b.gap_rad / kRefinePieces);
  return q;
}

// Sample I came within its margin of the material but did not reach it: the motion from sample
// I − 1 to I + 1 is checked at kRefinePieces poses per step, each with the margin of its own
// (kRefinePieces times smaller) gaps. The deepest hit, none when the finer poses all clear.
std::optional<detail::MaterialHit> refine(const std::vector<HeadQuery>& samples, std::size_t i, const detail::MaterialIndex& index,
                                          const detail::HeadProfile& head, double radius, double ignore, bool any) {
  std::optional<detail::MaterialHit> best;
  const HeadQuery& at = samples[i];
  for (std::size_t j = i > 0 ? i : i + 1; j <= i + 1 && j < samples.size(); ++j) {
    const HeadQuery& a = samples[j - 1];
    const HeadQuery& b = samples[j];
    if (b.gap_mm == 0.0f && b.gap_rad == 0.0f && j != i) continue;
    for (int k = 0; k <= kRefinePieces; ++k) {
      const HeadQuery q = between(a, b, static_cast<double>(k) / kRefinePieces);
      auto hit = index.deepest(head, vec(q.tip), vec(q.axis), at.before, radius, ignore, 0.5 * q.gap_mm, 0.5 * q.gap_rad, any);
      if (hit && (!best || hit->depth_mm > best->depth_mm)) best = hit;
      if (any && best && best->depth_mm >= 0.0) return best;
    }
  }
  return best;
}

// The axes of at least kCommonAxisShare of the coarse checks, at most kCommonAxes of them, most
// shared first: those the shortcut of detail::BelowTheTip keeps heights for.
constexpr double kCommonAxisShare = 0.02;
constexpr std::size_t kCommonAxes = 8;

std::vector<std::array<float, 3>> common_axes(const std::vector<HeadQuery>& samples, const std::vector<std::uint32_t>& coarse) {
  std::map<std::array<float, 3>, std::size_t> count;
  for (const std::uint32_t i : coarse) ++count[samples[i].axis];
  std::vector<std::pair<std::size_t, std::array<float, 3>>> common;
  for (const auto& [axis, c] : count) {
    if (static_cast<double>(c) >= kCommonAxisShare * static_cast<double>(coarse.size())) common.push_back({c, axis});
  }
  std::sort(common.begin(), common.end(), std::greater<>());
  if (common.size() > kCommonAxes) common.resize(kCommonAxes);
  std::vector<std::array<float, 3>> out;
  for (const auto& [c, axis] : common) out.push_back(axis);
  return out;
}

// Samples checked side by side in the fine pass of check_material, in program order.
constexpr std::size_t kDenseBlock = 4096;

// Checks the samples against the material (in parallel) in two passes: every COARSE sample (at
// most kQueryBeads / kQueryDeg apart) with the margin of the gaps to its coarse neighbours, then,
// around those that come within it, every sample with the margin of its own gaps. Adds the
// collisions to OUT in program order.
void check_material(const std::vector<HeadQuery>& samples, const std::vector<std::uint32_t>& coarse,
                    std::vector<detail::MaterialSample> material, const machine::BuildModel& model, double bead_mm, BuildCheck& out) {
  const detail::HeadProfile head(model);
  // A bead is covered by balls at most kMaterialBeads apart of radius √((bead/2)² + (gap/2)²).
  const double radius = std::hypot(0.5 * bead_mm, 0.5 * kMaterialBeads * bead_mm), ignore = kIgnoreBeads * bead_mm;
  const double prebuilt_ignore = kIgnorePrebuiltBeads * bead_mm;
  // The shortcut is exact for the nearest material it may leave out.
  const detail::BelowTheTip below(common_axes(samples, coarse), material, model, radius, model.prebuilt.empty() ? ignore : prebuilt_ignore);
  const detail::MaterialIndex index(std::move(material), prebuilt_ignore);
  // The travel and turn from sample A to sample B (A < B), summed over the samples between.
  std::vector<double> run_mm(samples.size() + 1, 0.0), run_rad(samples.size() + 1, 0.0);
  for (std::size_t i = 0; i < samples.size(); ++i) run_mm[i + 1] = run_mm[i] + samples[i].gap_mm, run_rad[i + 1] = run_rad[i] + samples[i].gap_rad;
  auto check = [&](std::size_t i, std::size_t prev, std::size_t next, bool any) {
    // Gaps to the neighbours: the sums over (prev, i] and (i, next].
    const double gap = std::max(run_mm[i + 1] - run_mm[prev + 1], run_mm[next + 1] - run_mm[i + 1]);
    const double turn = std::max(run_rad[i + 1] - run_rad[prev + 1], run_rad[next + 1] - run_rad[i + 1]);
    const HeadQuery& q = samples[i];
    if (below.clear(q.tip, q.axis, q.before, 0.5 * gap, 0.5 * turn)) return std::optional<detail::MaterialHit>{};
    return index.deepest(head, vec(q.tip), vec(q.axis), q.before, radius, ignore, 0.5 * gap, 0.5 * turn, any);
  };
  std::vector<char> near(coarse.size(), 0);
  tbb::parallel_for(std::size_t{0}, coarse.size(), [&](std::size_t k) {
    const std::size_t prev = k > 0 ? coarse[k - 1] : coarse[k], next = k + 1 < coarse.size() ? coarse[k + 1] : coarse[k];
    near[k] = check(coarse[k], prev, next, true) ? 1 : 0;
  });
  out.material_checks = coarse.size();
  std::vector<std::uint32_t> dense;  // the samples around the coarse ones that came near, in order
  for (std::size_t k = 0; k < coarse.size(); ++k) {
    if (!near[k]) continue;
    const std::size_t from = k > 0 ? coarse[k - 1] + 1 : 0, to = k + 1 < coarse.size() ? coarse[k + 1] : samples.size() - 1;
    for (std::size_t i = std::max<std::size_t>(from, dense.empty() ? 0 : dense.back() + 1); i <= to; ++i) dense.push_back(static_cast<std::uint32_t>(i));
  }
  // In program order, a block at a time: the deepest ball at each sample until kMaxListedCollisions
  // are found, then the first ball found (a program striking a prebuilt part all along would
  // otherwise visit every ball the head overlaps at every sample).
  std::vector<std::optional<detail::MaterialHit>> hits(dense.size());
  std::size_t found = 0;
  for (std::size_t from = 0; from < dense.size(); from += kDenseBlock) {
    const std::size_t to = std::min(dense.size(), from + kDenseBlock);
    const bool any = found >= kMaxListedCollisions;
    tbb::parallel_for(from, to, [&](std::size_t k) {
      const std::size_t i = dense[k];
      hits[k] = check(i, i > 0 ? i - 1 : i, i + 1 < samples.size() ? i + 1 : i, any);
      // Within the margin only: the motion to the neighbours, finer, with its own smaller margin.
      if (hits[k] && hits[k]->depth_mm < 0.0) hits[k] = refine(samples, i, index, head, radius, ignore, any);
    });
    for (std::size_t k = from; k < to; ++k) found += hits[k] ? 1 : 0;
  }
  out.material_checks += dense.size();
  for (std::size_t k = 0; k < dense.size(); ++k) {
    if (!hits[k]) continue;
    ++out.material_collisions;
    if (index.sample(hits[k]->sample).layer == detail::kPrebuiltLayer) ++out.prebuilt_collisions;
    out.worst_material_depth_mm = std::max(out.worst_material_depth_mm, hits[k]->depth_mm);
    if (out.collision_places.size() < kMaxCollisionPlaces) {
      const HeadQuery& at = samples[dense[k]];
      out.collision_places.emplace_back(static_cast<std::uint32_t>(std::max(0, at.layer)), vec(at.tip));
    }
    if (out.collision_list.size() >= kMaxListedCollisions) continue;
    const detail::MaterialSample& s = index.sample(hits[k]->sample);
    const HeadQuery& q = samples[dense[k]];
    out.collision_list.push_back({q.line, q.layer, q.region, vec(q.tip),
                                  s.layer == detail::kPrebuiltLayer ? std::string(kPrebuiltBody) : fmt::format("deposit of layer {} region {}", s.layer, s.region),
                                  hits[k]->depth_mm});
  }
}

// Moves read at a time before they are sampled in parallel.
constexpr std::size_t kBlockMoves = 8192;

struct Sample {
  machine::MachineToolPose pose;
  double clearance_mm = 0.0;  // of the head to the plate and the table (machine/build_model.h; exact below 0)
};

// The samples of every move of BLOCK, SPACING apart along the tip and kSampleDeg of rotary motion
// apart: move I's are OUT[FIRST[I]] … OUT[FIRST[I + 1] − 1], its start first (the end of the move
// before) for a known start, its end alone for the first move. In parallel; the same at any thread count.
void sample_moves(const machine::MachineConfig& m, const machine::BuildModel& model, const std::vector<detail::WalkMove>& block, double spacing,
                  std::vector<std::size_t>& first, std::vector<Sample>& out) {
  std::vector<int> pieces(block.size(), 0);
  tbb::parallel_for(std::size_t{0}, block.size(), [&](std::size_t i) {
    const detail::WalkMove& mv = block[i];
    if (!mv.from_known) return;
    const Vec3 a = detail::tool_at(m, mv, 0.0).tip_part_mm, b = detail::tool_at(m, mv, 1.0).tip_part_mm;
    const double rot = std::max(mv.d_tilt_deg, mv.d_c_deg);
    pieces[i] = std::max(1, static_cast<int>(std::ceil(std::max(core::norm(b - a) / spacing, rot / kSampleDeg))));
  });
  first.assign(block.size() + 1, 0);
  for (std::size_t i = 0; i < block.size(); ++i) first[i + 1] = first[i] + static_cast<std::size_t>(pieces[i]) + 1;
  out.resize(first.back());
  tbb::parallel_for(std::size_t{0}, block.size(), [&](std::size_t i) {
    const detail::WalkMove& mv = block[i];
    auto put = [&](std::size_t k, machine::MachineToolPose tp) {
      out[k] = {tp, std::min(machine::head_clearance_mm(model, tp.tip_part_mm, tp.tool_axis_part, 0.0), machine::tip_clearance_mm(model, tp.tip_part_mm))};
    };
    if (!mv.from_known) {
      put(first[i], detail::tool_at(m, mv, 1.0));
      return;
    }
    // With the rotary axes still, forward kinematics is affine in the linear axes: the tip moves
    // straight from A to B with one tool axis (a TRAORI block's tip moves straight anyway).
    const bool still = mv.d_tilt_deg == 0.0 && mv.d_c_deg == 0.0;
    const machine::MachineToolPose end = detail::tool_at(m, mv, 1.0);
    const Vec3 a = detail::tool_at(m, mv, 0.0).tip_part_mm, b = end.tip_part_mm;
    out[first[i]].pose = {a, end.tool_axis_part};  // the start: only its tip is read (the move's length)
    const int n = pieces[i];
    for (int k = 1; k <= n; ++k) {
      const double u = static_cast<double>(k) / n;
      put(first[i] + static_cast<std::size_t>(k), still ? machine::MachineToolPose{a + (b - a) * u, end.tool_axis_part} : detail::tool_at(m, mv, u));
    }
  });
}

}  // namespace

core::Result<BuildCheck> verify_build(const machine::MachineConfig& m, const process::ProcessConfig& process,
                                      const machine::BuildModel& model, std::string_view gcode) {
  BuildCheck out;
  const double spacing = process.bead_width_mm * kSampleBeadShare;
  const double step = std::max(process.max_step_bead_share * process.bead_width_mm,
                               process.layer_max_mm * std::tan(process.self_supporting_deg * std::numbers::pi / 180.0));
  // Along the layer's normal: the layer below's plane, or the surface of an earlier region the
  // layer is laid on (its beads' centres half a bead inside it, this layer's half a layer above).
  const double h_max = std::max(process.layer_max_mm, 0.5 * (process.layer_max_mm + process.bead_width_mm)) + spacing;
  // Across: the nearest bead centre under a point is at most half a bead away inside a layer, and
  // a contour steps out by at most `step`; plus the sample spacing (half on each of two paths).
  const double lateral_max = std::max(0.5 * process.bead_width_mm, step) + spacing;
  out.ground_mm = h_max;
  out.ground_lateral_mm = lateral_max;
  DepositGrid grid(std::hypot(h_max, lateral_max));
  std::vector<Pending> this_layer;
  std::int64_t current_layer = -1;
  std::vector<std::int64_t> regions_started;
  const machine::SubstratePlate& plate = model.substrate;
  auto problem = [&](std::uint64_t line, std::int64_t layer, std::int64_t region, const std::string& what) {
    if (out.first_problems.size() < kMaxProblems) {
      out.first_problems.push_back(fmt::format("line {} (layer {} region {}): {}", line, layer, region, what));
    }
  };
  // LAST: the point that grounded the sample before, tried first (consecutive samples along a
  // bead mostly rest on the same one), and set to the one found.
  auto grounded = [&](Vec3 tip, Vec3 n, std::optional<Vec3>& last) {
    const bool over_plate = tip.x >= plate.x_min_mm && tip.x <= plate.x_max_mm && tip.y >= plate.y_min_mm && tip.y <= plate.y_max_mm;
    const double above = tip.z - plate.top_z_mm;
    if (over_plate && above >= -kClearanceSlackMm && above <= h_max) return true;
    auto under = [&](Vec3 q) {
      const Vec3 d = tip - q;
      const double h = core::dot(d, n);
      return h >= -kClearanceSlackMm && h <= h_max && core::norm(d - n * h) <= lateral_max;
    };
    if (last && under(*last)) return true;
    last = grid.find(tip, tip - n * (0.5 * h_max), under);
    return last.has_value();
  };
  auto end_layer = [&] {
    if (this_layer.empty()) return;
    bool curved = false;
    const Vec3 n = layer_normal(this_layer, spacing, &curved);
    // The grid is only read while a layer is checked: its samples in parallel.
    std::vector<char> ok(this_layer.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, this_layer.size()), [&](const tbb::blocked_range<std::size_t>& range) {
      std::optional<Vec3> last;
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        ok[i] = grounded(this_layer[i].tip, curved ? core::normalized(this_layer[i].axis) : n, last) ? 1 : 0;
      }
    });
    for (std::size_t i = 0; i < this_layer.size(); ++i) {
      if (ok[i]) continue;
      const Pending& p = this_layer[i];
      ++out.ungrounded_samples;
      if (p.first_of_region) out.mid_air_regions.push_back(p.region);
      if (out.ungrounded_samples <= 3) {
        problem(p.line, p.layer, p.region,
                fmt::format("deposit at ({:.3f}, {:.3f}, {:.3f}) {} within {:.3f} mm under it and {:.3f} mm across",
                            p.tip.x, p.tip.y, p.tip.z, kUngroundedProblem, h_max, lateral_max));
      }
    }
    for (const Pending& p : this_layer) grid.add(p.tip);
    this_layer.clear();
  };
  // A prebuilt body is material laid before the program, and ground the first beads rest on.
  std::vector<detail::MaterialSample> material =
      detail::prebuilt_material(model.prebuilt, std::hypot(0.5 * process.bead_width_mm, 0.5 * kMaterialBeads * process.bead_width_mm));
  for (const Vec3& p : model.prebuilt.surface_mm) grid.add(p);
  std::vector<HeadQuery> head_samples;
  std::vector<std::uint32_t> coarse;
  double since_coarse_mm = 0.0, since_coarse_rad = 0.0, since_material_mm = 0.0;
  std::uint64_t last_material_line = 0;
  std::vector<Collision> fixture_collisions;  // the plate or the table
  // C: the head's clearance to the plate and the table there (sample_moves).
  auto check_sample = [&](const detail::WalkMove& mv, const machine::MachineToolPose& tp, double c, bool last_of_move) {
    ++out.samples;
    if (c < -kClearanceSlackMm) {
      ++out.head_collisions;
      if (mv.process_on) ++out.head_collisions_depositing;
      if (-c > out.worst_head_depth_mm) out.worst_head_depth_mm = -c, out.worst_head_line = mv.line;
      if (out.head_collisions == 1) problem(mv.line, mv.layer, mv.region, fmt::format("the head is {:.3f} mm into the plate or the table", -c));
      if (fixture_collisions.size() < kMaxListedCollisions) {
        fixture_collisions.push_back({mv.line, mv.layer, mv.region, tp.tip_part_mm, "plate or table", -c});
      }
      // Where the tilted head dips into the plate on a layer's path (or on the approach to it), the
      // planner turns the torch (it takes only places on the path).
      if (mv.layer >= 0 && out.collision_places.size() < kMaxCollisionPlaces) {
        out.collision_places.emplace_back(static_cast<std::uint32_t>(mv.layer), tp.tip_part_mm);
      }
    }
    HeadQuery q;
    q.tip = {static_cast<float>(tp.tip_part_mm.x), static_cast<float>(tp.tip_part_mm.y), static_cast<float>(tp.tip_part_mm.z)};
    q.axis = {static_cast<float>(tp.tool_axis_part.x), static_cast<float>(tp.tool_axis_part.y), static_cast<float>(tp.tool_axis_part.z)};
    q.before = static_cast<std::uint32_t>(material.size());
    q.line = static_cast<std::uint32_t>(mv.line), q.layer = static_cast<std::int32_t>(mv.layer), q.region = static_cast<std::int32_t>(mv.region);
    if (!head_samples.empty() && mv.from_known) {
      const HeadQuery& p = head_samples.back();
      q.gap_mm = static_cast<float>(core::norm(tp.tip_part_mm - vec(p.tip)));
      q.gap_rad = static_cast<float>(std::acos(std::clamp(core::dot(tp.tool_axis_part, vec(p.axis)), -1.0, 1.0)));
    }
    since_coarse_mm += q.gap_mm, since_coarse_rad += q.gap_rad;
    // Coarse samples: every kQueryBeads of travel or kQueryDeg of turn along the motion (not at
    // every move's end: the margins span the gaps whatever the moves), and the program's last.
    if (coarse.empty() || !mv.from_known || since_coarse_mm >= kQueryBeads * process.bead_width_mm ||
        since_coarse_rad >= kQueryDeg * std::numbers::pi / 180.0) {
      coarse.push_back(static_cast<std::uint32_t>(head_samples.size()));
      since_coarse_mm = since_coarse_rad = 0.0;
    }
    head_samples.push_back(q);
    if (!mv.process_on) return;
    // Material samples at most kMaterialBeads apart along a bead (the first and last of each move kept).
    const bool bead_start = material.empty() || head_samples.back().gap_mm == 0.0f || !mv.from_known || mv.line != last_material_line;
    since_material_mm += q.gap_mm;
    if (bead_start || last_of_move || since_material_mm >= kMaterialBeads * process.bead_width_mm) {
      material.push_back({q.tip, static_cast<std::uint32_t>(material.size()), static_cast<std::int32_t>(mv.layer), static_cast<std::int32_t>(mv.region)});
      since_material_mm = 0.0;
      last_material_line = mv.line;
    }
    ++out.deposit_samples;
    const bool first_of_region =
        std::find(regions_started.begin(), regions_started.end(), mv.region) == regions_started.end();
    if (first_of_region) regions_started.push_back(mv.region);
    this_layer.push_back({tp.tip_part_mm, tp.tool_axis_part, mv.line, mv.layer, mv.region, first_of_region});
  };
  detail::WalkCallbacks cb;
  cb.dwell = [&](std::uint64_t, double seconds, bool on) {
    if (on) out.process_on_dwell_s += seconds;
  };
  // Moves are sampled (forward kinematics and the head's clearance, the bulk of the work) a block
  // at a time in parallel, then taken in program order.
  std::vector<detail::WalkMove> block;
  std::vector<Sample> sampled;
  std::vector<std::size_t> first;
  auto take = [&] {
    sample_moves(m, model, block, spacing, first, sampled);
    for (std::size_t i = 0; i < block.size(); ++i) {
      const detail::WalkMove& mv = block[i];
      if (mv.layer != current_layer) end_layer(), current_layer = mv.layer;
      double length = 0.0;
      for (std::size_t k = first[i]; k < first[i + 1]; ++k) {
        if (k > first[i]) length += core::norm(sampled[k].pose.tip_part_mm - sampled[k - 1].pose.tip_part_mm);
        // The move's start (sample first[i] of a known move) is the previous move's end: not checked again.
        if (mv.from_known && k == first[i]) continue;
        check_sample(mv, sampled[k].pose, sampled[k].clearance_mm, k + 1 == first[i + 1]);
      }
      if (!mv.from_known || !mv.process_on || mv.rapid || mv.time_min <= 0.0) continue;
      const double seconds = mv.time_min * 60.0;
      out.process_on_s += seconds;
      if (length / seconds < kStallShare * process.deposit_feed_mm_s) {
        if (out.stalled_s == 0.0) problem(mv.line, mv.layer, mv.region, fmt::format("the tip moves {:.3f} mm in {:.3f} s with the process on", length, seconds));
        out.stalled_s += seconds;
      }
    }
    block.clear();
  };
  cb.move = [&](const detail::WalkMove& mv) {
    block.push_back(mv);
    if (block.size() == kBlockMoves) take();
  };
  bool end = false;
  if (auto st = detail::walk_gcode(m, gcode, &process, cb, &end); !st) return st.error();
  take();
  end_layer();
  if (!head_samples.empty() && coarse.back() + 1 != head_samples.size()) coarse.push_back(static_cast<std::uint32_t>(head_samples.size() - 1));
  check_material(head_samples, coarse, std::move(material), model, process.bead_width_mm, out);
  if (out.material_collisions > 0) {
    const Collision& c = out.collision_list.front();
    problem(c.line, c.layer, c.region, fmt::format("the head strikes the {} ({:.3f} mm)", c.body, c.depth_mm));
  }
  // Both kinds in program order, the first kMaxListedCollisions.
  out.collision_list.insert(out.collision_list.end(), fixture_collisions.begin(), fixture_collisions.end());
  std::stable_sort(out.collision_list.begin(), out.collision_list.end(), [](const Collision& a, const Collision& b) { return a.line < b.line; });
  if (out.collision_list.size() > kMaxListedCollisions) out.collision_list.resize(kMaxListedCollisions);
  out.collisions = out.head_collisions + out.material_collisions;
  return out;
}

}  // namespace polyaxis::verify
