// Measures of a mesh: volume, area, bounding box, overhang area.
#pragma once

#include <vector>

#include "polyaxis/core/vec3.h"
#include "polyaxis/mesh/mesh.h"

namespace polyaxis::mesh {

// Signed volume enclosed by the faces, mm³ (divergence theorem about the bounding-box centre for
// precision). Positive for an outward-oriented closed mesh.
double signed_volume(const Mesh& mesh);
double surface_area(const Mesh& mesh);  // mm²
core::Box3 bounding_box(const Mesh& mesh);

// Signed solid angle of the triangle (A, B, C) seen from the origin, steradians (Van Oosterom and
// Strackee); positive when the triangle turns counter-clockwise seen from the origin.
double solid_angle(core::Vec3 a, core::Vec3 b, core::Vec3 c);

// Generalised winding number of MESH at P: the facets' solid angles over 4π; about 1 inside a
// closed outward mesh, 0 outside (compare with core::kInsideWindingNumber). O(F).
double winding_number(const Mesh& mesh, core::Vec3 p);

// Facets whose unit normal n has n·d < −sin(α_max) for build direction D (unit) and
// self-supporting angle α_max from vertical (SPEC §2.2), excluding facets that lie on the build
// plate (every corner within kPlateContactMm of the lowest point along D). Returns their area, mm².
double overhang_area(const Mesh& mesh, core::Vec3 direction, double self_supporting_rad);

// The connected pieces of M (faces sharing vertices), each a mesh of its own; a piece of negative
// volume (a cavity's surface) goes with the first solid piece whose box holds it. Cost: O(F log F).
std::vector<Mesh> connected_solids(const Mesh& m);

// Facets resting on the build plate are not overhangs; this is how close "on" is, mm.
inline constexpr double kPlateContactMm = 1e-3;

}  // namespace polyaxis::mesh
