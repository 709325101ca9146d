#include "read_backs.h"

#include <bit>
#include <cstring>

namespace polyaxis::planner::detail {
namespace {

// FNV-1a, 64 bits.
class Fnv {
 public:
  void bytes(const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) h_ = (h_ ^ p[i]) * 0x100000001b3ULL;
  }
  void number(double v) { word(std::bit_cast<std::uint64_t>(v)); }
  void word(std::uint64_t w) { bytes(&w, sizeof w); }
  void vec(const core::Vec3& v) { number(v.x), number(v.y), number(v.z); }
  std::uint64_t value() const { return h_; }

 private:
  std::uint64_t h_ = 0xcbf29ce484222325ULL;
};

}  // namespace

ReadBackKey read_back_key(std::string_view gcode, const std::vector<post::ProgramPoint>& program, const machine::BuildModel& model) {
  ReadBackKey key;
  Fnv g;
  g.bytes(gcode.data(), gcode.size());
  key.gcode = g.value();
  Fnv p;
  p.word(program.size());
  for (const post::ProgramPoint& q : program) {
    p.vec(q.tip_part_mm), p.vec(q.tool_axis_part), p.number(q.feed_mm_s);
    p.word((static_cast<std::uint64_t>(q.layer) << 32) | q.region);
    p.word((q.process_on ? 1U : 0U) | (q.c_unwind ? 2U : 0U));
    p.word(q.comment_if_new_block.size());
    p.bytes(q.comment_if_new_block.data(), q.comment_if_new_block.size());
  }
  key.program = p.value();
  // The nozzle and the head boxes are the machine's, the same for the whole call.
  Fnv b;
  const machine::SubstratePlate& s = model.substrate;
  for (double v : {s.x_min_mm, s.y_min_mm, s.x_max_mm, s.y_max_mm, s.top_z_mm, s.thickness_mm, model.table_radius_mm, model.prebuilt.spacing_mm}) b.number(v);
  b.vec(model.table_centre_mm);
  b.word(model.prebuilt.surface_mm.size());
  for (const core::Vec3& v : model.prebuilt.surface_mm) b.vec(v);
  for (const core::Vec3& v : model.prebuilt.normals) b.vec(v);
  key.build_model = b.value();
  return key;
}

std::optional<ReadBack> ReadBacks::find(const ReadBackKey& key) const {
  const std::lock_guard lock(mutex_);
  const auto it = kept_.find(key);
  if (it == kept_.end()) return std::nullopt;
  return it->second;
}

void ReadBacks::keep(const ReadBackKey& key, const ReadBack& read_back) {
  const std::lock_guard lock(mutex_);
  kept_.emplace(key, read_back);
}

std::size_t ReadBacks::size() const {
  const std::lock_guard lock(mutex_);
  return kept_.size();
}

}  // namespace polyaxis::planner::detail
