// libFuzzer target: machine and process files (`--machine`, `--process`, laminate's waterjet process) on arbitrary bytes, and
// `--set` overrides of the embedded defaults. A file is accepted or refused with kUsage (P1-P9),
// never a signal: 60 000 nested arrays once overflowed the parser's stack (issue 14). An accepted
// machine has ordered limits and positive feeds; an accepted process finite positive feeds within
// the accepted range.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "fuzz_require.h"
#include "polyaxis/core/config_document.h"
#include "polyaxis/lamination/waterjet.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/process/process.h"

using polyaxis::fuzz::require;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace polyaxis;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  if (auto m = machine::parse_machine(text, "fuzz.json")) {
    const machine::MachineConfig& c = m.value();
    require(c.x_mm.min <= c.x_mm.max && c.y_mm.min <= c.y_mm.max && c.z_mm.min <= c.z_mm.max);
    require(c.feed.linear_max_mm_min >= 1.0 && std::isfinite(c.feed.linear_max_mm_min));
  } else {
    require(m.error().code == core::ErrorCode::kUsage);
  }
  if (auto p = process::parse_process(text, "fuzz.json")) {
    require(p.value().deposit_feed_mm_s >= process::kMinFeedMmS && p.value().deposit_feed_mm_s <= process::kMaxFeedMmS);
    require(p.value().bead_width_mm > 0.0 && std::isfinite(p.value().bead_width_mm));
  } else {
    require(p.error().code == core::ErrorCode::kUsage);
  }
  // A waterjet process file (laminate --process).
  if (auto w = lamination::parse_waterjet_process(text, "fuzz.json")) {
    const lamination::WaterjetProcess& c = w.value();
    require(c.kerf_mm > 0.0 && std::isfinite(c.kerf_mm) && c.min_feed_mm_s <= c.max_feed_mm_s);
    require(c.lead_in_mm <= 0.5 * c.margin_mm && c.lead_out_mm <= 0.5 * c.margin_mm);
    const double v = lamination::waterjet_feed_mm_s(c, 1.0, 0.3);
    require(v >= c.min_feed_mm_s && v <= c.max_feed_mm_s);
  } else {
    require(w.error().code == core::ErrorCode::kUsage);
  }
  // The same bytes as the value of an override.
  auto doc = core::parse_config_document(process::default_process_json(), "default");
  require(doc.ok());
  const std::string set = "process_on=" + std::string(text.substr(0, 256));
  if (core::apply_override(doc.value(), set)) {
    auto p = process::parse_process(doc.value().dump(), "override");
    if (!p) require(p.error().code == core::ErrorCode::kUsage);
  }
  return 0;
}
