// Geometry helpers of the decomposition (decompose.cpp, split_screen.cpp): planar faces, inside
// tests, distances, overhang of a region in its own direction, shells. Private to the analysis module.
#pragma once

#include <cstdint>
#include <vector>

#include "polyaxis/core/vec3.h"
#include "polyaxis/mesh/mesh.h"
#include "polyaxis/mesh/topology.h"

namespace polyaxis::analysis::detail {

using core::Vec3;

inline constexpr double kPi = 3.14159265358979323846;
// A facet within this of a region's base plane rests on it (the parent or the plate), mm.
inline constexpr double kOnBaseMm = 1e-6;
// An overhang patch (overhanging facets joined across edges) smaller than this is the cut's own
// noise: the sliver a plane leaves where it grazes a tessellated curve (a wall cut along one facet
// of a cylinder keeps films up to the chordal deviation thick over the neighbouring facets), mm².
// A single bead (about 1 mm wide) bridges far more.
inline constexpr double kUnsupportedNoiseMm2 = 0.25;
// A cut along a planar face of the part is moved this far into the child, mm: corefinement of a
// plane with coplanar facets of an already cut region can fail to end (CGAL clip), and the parent
// keeps a film this thin of the child: where the face is the parent's and the child grows out of
// it, a sliver of the cap (its faces far below kUnsupportedNoiseMm2); where it is the child's own
// underside, the whole face (underside_in_cut_mm2 counts it as the child's overhang).
inline constexpr double kFaceCutOffsetMm = 1e-3;

struct PlanarFace {
  Vec3 normal;  // unit, outward
  Vec3 point;   // a corner of one of its facets
  double area_mm2 = 0.0;
  std::uint32_t facets = 0;
  bool concave_edge = false;  // a neighbouring facet across its boundary rises above its plane at a crease
  std::vector<std::uint32_t> facet_ids;
};

// Planar faces of M: coplanar facets joined across shared edges. Cost O(F).
std::vector<PlanarFace> planar_faces(const mesh::Mesh& m);

double angle_deg(Vec3 a, Vec3 b);

// Generalised winding number of M at P: about 1 inside a closed outward mesh, 0 outside. O(F).
double winding(const mesh::Mesh& m, Vec3 p);

// Distance from P to the solid bounded by M: 0 inside (winding), else to the nearest facet. O(F).
double distance_to_solid(const mesh::Mesh& m, Vec3 p);

// Squared distance from P to the triangle ABC, mm².
double distance2_to_triangle(Vec3 p, Vec3 a, Vec3 b, Vec3 c);

struct OverhangPatch {
  std::vector<std::uint32_t> facets;  // facet ids of M, joined across edges
  double area_mm2 = 0.0;
};

// The overhang patches of M built along D at ALPHA_DEG (facets on the base plane BASE_POINT,
// BASE_NORMAL left out), largest first, those below kUnsupportedNoiseMm2 dropped. O(F).
std::vector<OverhangPatch> overhang_patches(const mesh::Mesh& m, const mesh::EdgeTopology& topo, Vec3 d, double alpha_deg,
                                            Vec3 base_point, Vec3 base_normal);

// Overhang area of M built along D at the self-supporting angle ALPHA_DEG, not counting facets on
// the base plane (BASE_POINT, BASE_NORMAL): they rest on the parent region or the plate.
// (mesh::overhang_area would count a base that is not perpendicular to D.) Patches below
// kUnsupportedNoiseMm2 are not counted. O(F).
double unsupported(const mesh::Mesh& m, Vec3 d, double alpha_deg, Vec3 base_point, Vec3 base_normal);

// Area of the facets of M that lie in the cut plane (POINT, unit NORMAL towards the child), or up
// to twice kFaceCutOffsetMm on the parent's side of it, facing away from the child: the child's own
// underside, which the cut leaves on nothing but a film of the parent (or on nothing at all), mm².
// Also, seen along NORMAL, the facets less than FILM_MM (the least layer) under the cut that face
// away from it within kFilmFacingDeg: the cut leaves the parent a film there that no layer lays (a
// plane grazing a tube's bore), and the child's first layer over it rests on nothing. Such a face
// is an overhang of the child whatever its direction. O(F).
double underside_in_cut_mm2(const mesh::Mesh& m, Vec3 point, Vec3 normal, double film_mm = 0.0);

// The corners of M where a region built along D starts in mid-air: local minima of the height
// along D (no corner sharing a facet with it lower; level corners ordered by a fixed tie-break, so
// a level keel counts once) off the base plane (BASE_POINT, BASE_NORMAL), with the solid above them
// (the facets around face down along D; a pocket's floor is a minimum with the solid below). The
// first layer there is an island resting on nothing, whatever the facets' angles: a keel or a spike
// pointing down passes the facet test of `unsupported` with every facet steep. A corner with some
// of the solid within PROBE_MM below it (straight down, or as far across; 0.05 mm at least) is
// not one: the island there would be no thicker than a piece the decomposition counts as a film.
// The 64 lowest candidates are probed at most. O(F) plus O(F) per probe.
std::vector<Vec3> mid_air_starts(const mesh::Mesh& m, Vec3 d, Vec3 base_point, Vec3 base_normal, double probe_mm);

// The shells of a closed mesh, as separate closed meshes (mesh::repair groups faces by shell).
std::vector<mesh::Mesh> shells_of(const mesh::Mesh& piece);


}  // namespace polyaxis::analysis::detail
