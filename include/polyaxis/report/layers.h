// Text renderings of sliced layers: JSON for programs, SVG for people.
#pragma once

#include <string>

#include "polyaxis/io/write_file.h"
#include "polyaxis/slicing/slice.h"
#include "polyaxis/toolpath/toolpath.h"

namespace polyaxis::report {

struct LayersMeta {
  std::string part;          // the part file, as given
  slicing::SliceOptions options;
};

// layers.json: {"part", "direction", "mode", "layers": [{"index", "origin", "normal", "u", "v",
// "height_mm", "thickness_mm", "below_mm", "above_mm", "area_mm2", "polygons": [{"outer":
// [[u, v], ...], "holes": [[[u, v], ...], ...]}]}], "summary": {...}}. Coordinates in mm with
// 6 decimals (the 1 nm grid). Deterministic: the same layers give the same bytes.
std::string layers_json(const slicing::SliceResult& result, const LayersMeta& meta);
// The same bytes into FILE as they are made (blocks of layers formatted side by side, written in
// order while later ones are formatted); the caller commits FILE. Errors are FILE's.
core::Status write_layers_json(io::AtomicFile& file, const slicing::SliceResult& result, const LayersMeta& meta);

// The summary object printed by `polyaxis slice --json`: layers, total_area_mm2,
// volume_estimate_mm3, min/max thickness, open_chains, limit_violations.
std::string slice_summary_json(const slicing::SliceResult& result, const LayersMeta& meta);

// One layer as a standalone SVG (mm units, +v up): outer loops filled, holes cut out. With PATHS
// (the layer's toolpaths), also the paths (perimeters, fill, travel) and a dot at every closed
// path's seam.
std::string layer_svg(const slicing::Layer& layer, const toolpath::LayerToolpaths* paths = nullptr);

}  // namespace polyaxis::report
