// The 3MF Toolpath Extension as a neutral per-point pose format (issue 15, item 3): a package
// `PART.build.3mf` that any 3MF consumer reads, with the part and its 6-axis toolpath (3MF
// Consortium, "3MF Toolpath Extension" 1.0, namespace http://schemas.3mf.io/3dmanufacturing/toolpath/2026/03).
//
// What is written (docs/plan.md, "The 3MF toolpath"):
//   [Content_Types].xml, _rels/.rels                the OPC package
//   3D/3dmodel.model                                the part (object 2, part frame) and the build item;
//                                                   <tp:toolpathresource id 1 toolpathtype 6axis unitfactor 0.0001>
//                                                   with one profile "deposit" (depositionspeed mm/s,
//                                                   beadwidth, beadheight, prewaittime µs: the dwell after
//                                                   switching on) and the layers in build order;
//                                                   requiredextensions "p tp" (UUIDs of the production extension)
//   3D/_rels/3dmodel.model.rels                     one relationship of the toolpath layer type per layer
//   Toolpath/Layers/layerNNNNN.xml                  one part per layer of the program (a new layer or region)
// Each bead run is a <segment type="polyline6d"> of <point6d>: the tip in 0.1 µm and the tool's frame
// as a unit quaternion whose local z is the tool axis (from the tip up the nozzle). Frames are
// carried along the program by the smallest rotation between consecutive axes, so the spec's
// nlerp between two points turns the axis along the great circle, as TRAORI's ORIVECT does. A
// deposit feed the axes slowed is the depositionspeed modifier's factor f on the point ending the
// move. The spec leaves the jumps between segments to the consumer; polyaxis's own route (travel
// around and over the part, turns in place) is kept in each layer's <data> as <pa:jump> elements
// before the segment they lead to, in polyaxis's namespace (not required: a consumer may ignore it).
// The machine file chooses this post ("post": "3mf-toolpath"); the machine's inverse kinematics
// checks every pose (kMachineLimit as the other posts), and its feed maxima slow the feeds.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "polyaxis/core/result.h"
#include "polyaxis/machine/machine.h"
#include "polyaxis/post/gcode.h"
#include "polyaxis/post/program.h"
#include "polyaxis/process/process.h"

namespace polyaxis::post {

inline constexpr std::string_view kToolpathNamespace = "http://schemas.3mf.io/3dmanufacturing/toolpath/2026/03";
inline constexpr std::string_view kToolpathLayerRelationship = "http://schemas.3mf.io/3dmanufacturing/toolpath/2026/03/layer";
inline constexpr std::string_view kPolyaxisNamespace = "https://github.com/polyaxis/polyaxis/3mf/2026";
inline constexpr double kToolpathUnitMm = 0.0001;  // unitfactor: device units of 0.1 µm, the 4 decimals of mm the other posts write

// The package for POINTS, with OPTIONS.part as the build item's mesh (required). Errors as
// write_gcode's (kMachineLimit, kInternal, kInfeasible for an empty program or a tip beyond the
// ±214 m that 32-bit coordinates of 0.1 µm hold, kOutput above max_output_bytes), kUsage without a part.
// Deterministic: the same input gives the same bytes.
core::Result<std::string> write_toolpath_3mf(const machine::MachineConfig& machine, const process::ProcessConfig& process,
                                             std::span<const ProgramPoint> points, const GcodeOptions& options = {});

// PACKAGE with ID in its model's metadata "pa:set" (the model part alone is rewritten).
core::Result<std::string> stamp_toolpath_3mf(std::string_view package, std::string_view id);

// PROGRAM with the output set's ID in its first comment (G-code, TRAORI, RAPID: the line count
// stays) or in the model's metadata "pa:set" (3MF toolpath).
core::Result<std::string> with_set_id(const machine::MachineConfig& machine, std::string program, std::string_view id);

}  // namespace polyaxis::post
