// libFuzzer target: the plan.json reader (`polyaxis view`, `polyaxis simulate --plan`) on arbitrary
// bytes. A plan it accepts has indices in range and finite numbers, and writing it out and reading
// that back gives the same text (the writer and the reader agree on every plan the reader accepts).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "fuzz_require.h"
#include "polyaxis/report/plan_view.h"

using polyaxis::fuzz::require;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace polyaxis;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  (void)report::read_plan_program(text, "fuzz.json");
  auto r = report::read_plan_view(text, "fuzz.json");
  if (!r) {
    require(r.error().code == core::ErrorCode::kInvalidInput);
    return 0;
  }
  const report::PlanView& v = r.value();
  for (const auto& region : v.regions) {
    for (const auto& t : region.mesh.triangles) {
      for (auto c : t) require(c < region.mesh.vertices.size());
    }
  }
  if (v.axis) {
    for (const auto& l : v.axis->links) require(l[0] < v.axis->nodes.size() && l[1] < v.axis->nodes.size());
  }
  for (const auto& p : v.program) require(p.layer < v.layers.size() && core::is_finite(p.tip_part_mm) && std::isfinite(p.feed_mm_s));
  const std::string once = report::plan_view_json(v);
  auto again = report::read_plan_view(once, "again.json");
  require(again.ok());
  require(report::plan_view_json(again.value()) == once);
  return 0;
}
