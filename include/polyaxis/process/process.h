// The process file: bead and layer geometry, feeds and the codes that switch the deposition process.
#pragma once

#include <string>
#include <string_view>

#include "polyaxis/core/result.h"
#include "polyaxis/core/tolerances.h"

namespace polyaxis::process {

struct ProcessConfig {
  std::string name;
  double bead_width_mm = 0.9;         // d: width of one deposited bead (laser DED, powder)
  double layer_mm = 0.6;              // nominal layer height
  double layer_min_mm = 0.3;          // adaptive slicing never goes below
  double layer_max_mm = 0.7;          // nor above; at most kMaxLayerToBeadRatio · bead_width_mm (P2)
  double self_supporting_deg = core::kDefaultSelfSupportingDeg;  // overhang from vertical that needs no support
  double deposit_feed_mm_s = 8.0;     // tool-tip speed over the part while depositing
  double travel_feed_mm_s = 50.0;     // tool-tip speed over the part while the process is off
  std::string process_on = "M64 P0";  // G-code words that switch the process on (one block)
  std::string process_off = "M65 P0"; // and off
  double dwell_on_s = 0.5;            // wait after switching on before moving (G4 P…), 0 for none
  // Under a tilted torch a layer may step sideways over the one below by at most this share of
  // the bead width (planner/support.h), whatever the tilt; (0, 1].
  double max_step_bead_share = 0.5;
  // Adaptive layer thickness within [layer_min_mm, layer_max_mm] (cusp and VolDiff limits and the
  // overhang step): on by default where the range is not a single value.
  bool adaptive_layers = true;
  double cusp_mm = 0.3;  // adaptive layers: largest staircase height t·|n·d| on the part's surface
  // Tilted layers: the largest volumetric difference between adjacent layers (Ruan Eq. 9), as the
  // area of the two sections' symmetric difference over the larger one's (slicing/tilted.cpp).
  double voldiff = 0.05;
  // On a machine that tilts its head over a fixed part (xyzac-head, xyzbc-head) gravity does not
  // turn with a region: a region may be built along a direction at most this far from vertical
  // (degrees, [0, 90)); 0 builds every region straight up, the torch still tilting. Table-table
  // machines turn each region's direction up, so it does not apply to them.
  double off_vertical_max_deg = 0.0;
  // The substrate plate the part is built on (its top is the part's base, Z = 0 on the table):
  // THICKNESS, and either an explicit size (both > 0) or the part's footprint grown by MARGIN.
  struct Substrate {
    double thickness_mm = 10.0;
    double margin_mm = 10.0;
    double size_x_mm = 0.0;  // 0: footprint + 2·margin
    double size_y_mm = 0.0;
  } substrate;
  // Parameters of the planning rules (plan.json "rules", docs/plan.md "The rule base").
  struct Rules {
    // Interfering layers of brother regions are built level by level (order.level); false builds
    // each region to its end before the next (order.continue only).
    bool interleave = true;
    // The C-space contours are grown by the head's radius plus this (mm).
    double c_space_margin_mm = 0.0;
  } rules;
  // ABB RAPID programs (machine "post" abb-rapid, post/rapid.h): how the process is switched.
  struct Rapid {
    bool arc = false;                 // "switch": "signal" (SetDO SIGNAL, 1 / 0) or "arc" (ArcLStart, ArcL, ArcLEnd)
    std::string signal = "doProcess"; // the digital output set while depositing
    std::string seam = "seam1";       // the arc instructions' seamdata and welddata, declared on the controller
    std::string weld = "weld1";
  } rapid;
};

// A layer higher than this fraction of the bead width cannot be deposited as one bead (P2).
inline constexpr double kMaxLayerToBeadRatio = 0.8;

// Feeds outside this range (mm/s) are refused as absurd: 1e-12 mm/s wrote F0.000000000060.
inline constexpr double kMinFeedMmS = 0.01;
inline constexpr double kMaxFeedMmS = 10000.0;

// Parses a process file (JSON, comments allowed). kUsage naming the key for: unknown or duplicate
// keys (P6), non-finite numbers (P5), a layer height ≤ 0 (P1) or > 0.8·bead_width_mm (P2),
// layer_min_mm > layer_mm or layer_mm > layer_max_mm naming both keys (P3), feeds outside
// [kMinFeedMmS, kMaxFeedMmS], a self-supporting angle outside (0°, 90°), a negative dwell, and
// process codes that are not plain G-code words (`M64 P0`, `M3 S1000`) or hold more than a
// process switch needs (motion, feed, other G-codes than a G4 dwell, program stops: P7).
// Cost: linear in size.
core::Result<ProcessConfig> parse_process(std::string_view json, const std::string& source);

// What is wrong with CODE as a process switch (the rule of process_on/process_off above), or "".
std::string switch_code_problem(const std::string& code);

// The embedded default process (ded_steel), same text as examples/processes/ded_steel.json.
std::string_view default_process_json();

}  // namespace polyaxis::process
