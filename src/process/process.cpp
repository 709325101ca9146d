#include "polyaxis/process/process.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <regex>
#include <sstream>

#include "core/config_json.h"

namespace polyaxis::process {

using nlohmann::json;

namespace {

// Same text as examples/processes/ded_steel.json (a test keeps them equal).
constexpr std::string_view kDefaultProcess = R"({
  "name": "ded_steel",
  "bead_width_mm": 0.9,
  "layer_mm": 0.6,
  "layer_min_mm": 0.3,
  "layer_max_mm": 0.7,
  "self_supporting_deg": 30,
  "deposit_feed_mm_s": 8,
  "travel_feed_mm_s": 50,
  "process_on": "M64 P0",
  "process_off": "M65 P0",
  "dwell_on_s": 0.5,
  "max_step_bead_share": 0.5,
  "adaptive_layers": true,
  "cusp_mm": 0.3,
  "voldiff": 0.05,
  "off_vertical_max_deg": 0,
  "substrate": {"thickness_mm": 10, "margin_mm": 10, "size_x_mm": 0, "size_y_mm": 0},
  "rules": {"interleave": true, "c_space_margin_mm": 0}
}
)";

// One block of plain G-code words, e.g. "M64 P0" or "M3 S1000": written verbatim into the program,
// so nothing that could start a comment, a parameter or a second line.
bool is_plain_block(const std::string& s) {
  static const std::regex kBlock(R"(^[A-Z][-+]?[0-9]+(\.[0-9]+)?( [A-Z][-+]?[0-9]+(\.[0-9]+)?)*$)");
  return std::regex_match(s, kBlock);
}

// What a process switch may not contain: only M-codes with their P, Q, E and S words and a G4
// dwell switch a process; motion, feed, other G-codes and the program stops (M0, M1, M2, M30,
// M60) or a tool change (M6) would move the machine or end the program behind the planner's
// back. Empty when BLOCK (a plain block) is a switch.
std::string switch_problem(const std::string& block) {
  std::istringstream words(block);
  std::string w;
  bool dwell = false, has_p = false;
  while (words >> w) {
    const char letter = w[0];
    const double v = std::stod(w.substr(1));
    switch (letter) {
      case 'M':
        if (v == 0 || v == 1 || v == 2 || v == 30 || v == 60) return fmt::format("'{}' stops or ends the program", w);
        if (v == 6) return fmt::format("'{}' changes the tool", w);
        break;
      case 'G':
        if (v != 4) return fmt::format("'{}' is not a dwell (G4): a process switch may not move the machine", w);
        dwell = true;
        break;
      case 'P': has_p = true; [[fallthrough]];
      case 'Q':
      case 'E':
      case 'S':
        if (v < 0) return fmt::format("'{}' is negative", w);
        break;
      default: return fmt::format("'{}': a process switch holds M-codes with P, Q, E, S words and G4 dwells only", w);
    }
  }
  if (dwell && !has_p) return "G4 needs its P word (seconds)";
  return {};
}

// "rapid": {"switch": "signal" | "arc", "signal": NAME, "seam": NAME, "weld": NAME}; names are
// RAPID identifiers (a letter, then letters, digits or _, at most 32).
void read_rapid(core::detail::ConfigReader& r, const json& obj, ProcessConfig::Rapid& out) {
  if (!r.check_object(obj, "rapid", {"switch", "signal", "seam", "weld"})) return;
  const std::string sw = r.string(obj, "rapid", "switch", std::string("signal"));
  if (sw != "signal" && sw != "arc") return r.fail(fmt::format("'rapid.switch' ('{}') must be \"signal\" or \"arc\"", sw));
  out.arc = sw == "arc";
  for (const auto& [key, v] : {std::pair<const char*, std::string*>{"signal", &out.signal}, {"seam", &out.seam}, {"weld", &out.weld}}) {
    *v = r.string(obj, "rapid", key, *v);
    const bool ok = !v->empty() && v->size() <= 32 && std::isalpha(static_cast<unsigned char>((*v)[0])) != 0 &&
                    std::all_of(v->begin(), v->end(), [](char ch) { return std::isalnum(static_cast<unsigned char>(ch)) != 0 || ch == '_'; });
    if (!r.failed() && !ok) return r.fail(fmt::format("'rapid.{}' ('{}') must be a RAPID name: a letter, then letters, digits or _", key, *v));
  }
}

}  // namespace

std::string_view default_process_json() { return kDefaultProcess; }

core::Result<ProcessConfig> parse_process(std::string_view text, const std::string& source) {
  auto doc = core::detail::parse_document(text, source);
  if (!doc) return doc.error();
  const json& root = doc.value();
  core::detail::ConfigReader r(source);
  if (!r.check_object(root, "", {"name", "bead_width_mm", "layer_mm", "layer_min_mm", "layer_max_mm",
                                 "self_supporting_deg", "deposit_feed_mm_s", "travel_feed_mm_s", "process_on",
                                 "process_off", "dwell_on_s", "max_step_bead_share", "adaptive_layers", "cusp_mm", "voldiff", "off_vertical_max_deg", "substrate", "rules", "rapid"})) {
    return r.error();
  }
  ProcessConfig p;
  p.name = r.string(root, "", "name", std::nullopt);
  p.bead_width_mm = r.number(root, "", "bead_width_mm", std::nullopt);
  p.layer_mm = r.number(root, "", "layer_mm", std::nullopt);
  p.layer_min_mm = r.number(root, "", "layer_min_mm", p.layer_mm);
  p.layer_max_mm = r.number(root, "", "layer_max_mm", p.layer_mm);
  p.self_supporting_deg = r.number(root, "", "self_supporting_deg", core::kDefaultSelfSupportingDeg);
  p.deposit_feed_mm_s = r.number(root, "", "deposit_feed_mm_s", std::nullopt);
  p.travel_feed_mm_s = r.number(root, "", "travel_feed_mm_s", std::nullopt);
  p.process_on = r.string(root, "", "process_on", std::nullopt);
  p.process_off = r.string(root, "", "process_off", std::nullopt);
  p.dwell_on_s = r.number(root, "", "dwell_on_s", 0.0);
  p.max_step_bead_share = r.number(root, "", "max_step_bead_share", p.max_step_bead_share);
  p.adaptive_layers = r.boolean(root, "", "adaptive_layers", p.adaptive_layers);
  p.cusp_mm = r.number(root, "", "cusp_mm", p.cusp_mm);
  p.voldiff = r.number(root, "", "voldiff", p.voldiff);
  p.off_vertical_max_deg = r.number(root, "", "off_vertical_max_deg", p.off_vertical_max_deg);
  if (r.has(root, "substrate")) {
    const json& s = root.at("substrate");
    if (!r.check_object(s, "substrate", {"thickness_mm", "margin_mm", "size_x_mm", "size_y_mm"})) return r.error();
    p.substrate.thickness_mm = r.number(s, "substrate", "thickness_mm", p.substrate.thickness_mm);
    p.substrate.margin_mm = r.number(s, "substrate", "margin_mm", p.substrate.margin_mm);
    p.substrate.size_x_mm = r.number(s, "substrate", "size_x_mm", 0.0);
    p.substrate.size_y_mm = r.number(s, "substrate", "size_y_mm", 0.0);
  }
  if (r.has(root, "rules")) {
    const json& s = root.at("rules");
    if (!r.check_object(s, "rules", {"interleave", "c_space_margin_mm"})) return r.error();
    p.rules.interleave = r.boolean(s, "rules", "interleave", p.rules.interleave);
    p.rules.c_space_margin_mm = r.number(s, "rules", "c_space_margin_mm", p.rules.c_space_margin_mm);
  }
  if (r.has(root, "rapid")) read_rapid(r, root.at("rapid"), p.rapid);
  if (r.failed()) return r.error();
  if (p.rules.c_space_margin_mm < 0.0) r.fail("'rules.c_space_margin_mm' must be >= 0");
  if (!(p.max_step_bead_share > 0.0 && p.max_step_bead_share <= 1.0)) {
    r.fail(fmt::format("'max_step_bead_share' ({}) must be in (0, 1]: a bead must rest on the one below", p.max_step_bead_share));
  }
  if (!(p.off_vertical_max_deg >= 0.0 && p.off_vertical_max_deg < 90.0)) {
    r.fail(fmt::format("'off_vertical_max_deg' ({}) must be in [0, 90): the largest angle from vertical a region may be built along "
                       "where the part stays fixed",
                       p.off_vertical_max_deg));
  }
  if (!(p.cusp_mm > 0.0)) r.fail(fmt::format("'cusp_mm' ({}) must be > 0", p.cusp_mm));
  if (!(p.voldiff > 0.0 && p.voldiff <= 2.0)) r.fail(fmt::format("'voldiff' ({}) must be in (0, 2]: a share of the larger section", p.voldiff));
  if (p.substrate.thickness_mm < 0.0) r.fail("'substrate.thickness_mm' must be >= 0");
  if (p.substrate.margin_mm < 0.0) r.fail("'substrate.margin_mm' must be >= 0");
  if (p.substrate.size_x_mm < 0.0 || p.substrate.size_y_mm < 0.0 || ((p.substrate.size_x_mm > 0.0) != (p.substrate.size_y_mm > 0.0))) {
    r.fail("'substrate.size_x_mm' and 'substrate.size_y_mm' must both be 0 (footprint + margin) or both > 0");
  }

  if (p.bead_width_mm <= 0.0) r.fail(fmt::format("'bead_width_mm' ({}) must be > 0", p.bead_width_mm));
  const double nozzle_limit = kMaxLayerToBeadRatio * p.bead_width_mm;
  for (const auto& [key, v] : {std::pair<std::string_view, double>{"layer_mm", p.layer_mm},
                               {"layer_min_mm", p.layer_min_mm},
                               {"layer_max_mm", p.layer_max_mm}}) {
    if (v <= 0.0) r.fail(fmt::format("'{}' ({}) must be > 0 (P1)", key, v));
    if (v > nozzle_limit) {
      r.fail(fmt::format("'{}' ({}) exceeds {}·bead_width_mm = {} mm: one bead cannot build it (P2)", key, v,
                         kMaxLayerToBeadRatio, nozzle_limit));
    }
  }
  r.require_le(p.layer_min_mm, "layer_min_mm", p.layer_max_mm, "layer_max_mm");
  r.require_le(p.layer_min_mm, "layer_min_mm", p.layer_mm, "layer_mm");
  r.require_le(p.layer_mm, "layer_mm", p.layer_max_mm, "layer_max_mm");
  if (!(p.self_supporting_deg > 0.0 && p.self_supporting_deg < 90.0)) {
    r.fail(fmt::format("'self_supporting_deg' ({}) must be between 0 and 90 (exclusive)", p.self_supporting_deg));
  }
  for (const auto& [key, v] : {std::pair<std::string_view, double>{"deposit_feed_mm_s", p.deposit_feed_mm_s},
                               {"travel_feed_mm_s", p.travel_feed_mm_s}}) {
    if (!(v >= kMinFeedMmS && v <= kMaxFeedMmS)) {
      r.fail(fmt::format("'{}' ({}) must be between {} and {} mm/s", key, v, kMinFeedMmS, kMaxFeedMmS));
    }
  }
  if (p.dwell_on_s < 0.0) r.fail(fmt::format("'dwell_on_s' ({}) must be ≥ 0", p.dwell_on_s));
  for (const auto& [key, v] : {std::pair<std::string_view, const std::string&>{"process_on", p.process_on},
                               {"process_off", p.process_off}}) {
    if (!is_plain_block(v)) {
      r.fail(fmt::format("'{}' (\"{}\") must be upper-case G-code words separated by single spaces, e.g. \"M64 P0\"",
                         key, v));
    } else if (const std::string why = switch_problem(v); !why.empty()) {
      r.fail(fmt::format("'{}' (\"{}\"): {}", key, v, why));
    }
  }
  if (p.process_on == p.process_off) r.fail("'process_on' and 'process_off' must differ");
  if (r.failed()) return r.error();
  return p;
}

std::string switch_code_problem(const std::string& code) {
  if (!is_plain_block(code)) return "must be upper-case G-code words separated by single spaces, e.g. \"M64 P0\"";
  return switch_problem(code);
}

}  // namespace polyaxis::process
