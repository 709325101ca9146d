// Planar sections of a closed mesh along a direction d. Topology rests on one classification per
// vertex and plane, never on a distance tolerance:
//
//   Tie rule: a vertex is ABOVE the plane at height h when s(v) = p(v)·d >= h, else BELOW.
//   (A vertex on the plane counts as above: the plane is perturbed symbolically downwards.)
//
// A triangle is crossed when it has corners on both sides; each of its edges whose ends differ
// is crossed once, at a point constructed from the edge's ends in a fixed order, so the two faces
// of an edge agree. Each crossed triangle gives one segment, from the crossing on its
// above-to-below edge to the crossing on its below-to-above edge (in the face's corner order);
// with outward faces, solid lies to the left, so outer loops run counter-clockwise in (u, v) and
// holes clockwise. Segments are chained through the shared mesh edges, which closes every loop
// on a closed manifold mesh for any d.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "polyaxis/geom2d/polygon.h"
#include "polyaxis/mesh/mesh.h"
#include "polyaxis/mesh/topology.h"
#include "polyaxis/slicing/layer.h"

namespace polyaxis::slicing {

// What a section needs of a mesh, computed once per direction: heights of vertices along d,
// edge adjacency, the frame axes.
class SectionContext {
 public:
  // MESH must outlive the context. Precondition: closed, manifold, consistently oriented
  // (mesh::repair output). TOPOLOGY: the mesh's edge adjacency when the caller has it (repair
  // does), else it is built here. Cost: O(V + F).
  SectionContext(const mesh::Mesh& mesh, Vec3 direction, const mesh::EdgeTopology* topology = nullptr);
  // A context whose heights are FIELD's values at the vertices (one per vertex of MESH) instead of
  // p·d: its sections are the level sets of the field, linear over each face, projected along
  // DIRECTION onto the frame's plane (conformal layers, conformal.h). Outer loops run
  // counter-clockwise about DIRECTION where the field grows along it.
  SectionContext(const mesh::Mesh& mesh, Vec3 direction, std::vector<double> field, const mesh::EdgeTopology* topology = nullptr);
  // The field's value at any point of the mesh, for a field that is not linear over a face (a
  // distance): a crossing is then moved along its edge, from the linear estimate, to where
  // FIELD_AT meets the level (regula falsi between the edge's ends, whose field values bracket
  // it). The sides of the vertices, and with them the topology, do not change; the contour runs
  // on the field's true level set instead of a sawtooth about it where the level set meets the
  // surface at a grazing angle (a linear error of e mm in the field moves the crossing by
  // e / |the field's gradient along the surface|). FIELD_AT must be safe to call from several
  // threads.
  void set_field_at(std::function<double(Vec3)> field_at) { field_at_ = std::move(field_at); }
  const std::function<double(Vec3)>& field_at() const { return field_at_; }

  const mesh::Mesh& mesh() const { return mesh_; }
  const mesh::EdgeTopology& topology() const { return topology_ ? *topology_ : own_topology_; }
  Vec3 direction() const { return d_; }
  double height(std::uint32_t vertex) const { return height_[vertex]; }
  double min_height() const { return min_; }
  double max_height() const { return max_; }
  // Lowest and highest corner height of face F (computed on demand: 16 bytes a face saved).
  double face_min(std::uint32_t f) const {
    const auto& t = mesh_.triangles[f];
    return std::min({height_[t[0]], height_[t[1]], height_[t[2]]});
  }
  double face_max(std::uint32_t f) const {
    const auto& t = mesh_.triangles[f];
    return std::max({height_[t[0]], height_[t[1]], height_[t[2]]});
  }

 private:
  const mesh::Mesh& mesh_;
  const mesh::EdgeTopology* topology_;
  mesh::EdgeTopology own_topology_;
  Vec3 d_;
  std::vector<double> height_;
  std::function<double(Vec3)> field_at_;
  double min_ = 0.0, max_ = 0.0;
};

// Reusable per-thread memory for sections: a visit stamp per face of the mesh (4 bytes a face,
// allocated on first use and cleared only when the epoch wraps), so that a section costs its
// candidates and crossings, not the mesh. Keep one per thread and reuse it.
struct SectionScratch {
  std::vector<std::uint32_t> stamp;  // stamp[f] == epoch: face f is done in this section
  std::uint32_t epoch = 0;
};

struct SectionResult {
  std::vector<geom2d::Polygon> polygons;  // nonzero union of the loops (RELIABILITY T6)
  double area_mm2 = 0.0;
  std::uint32_t open_chains = 0;          // chains that did not close (an open mesh)
};

// The section of the context's mesh by the plane at height H_MM, in FRAME's (u, v) coordinates
// (frame.d must be the context's direction). CANDIDATES: faces that may cross the plane (a
// superset is fine; the tie rule decides). Cost: O(|candidates| + k log k) for k crossings.
SectionResult section(const SectionContext& context, double h_mm, const Frame& frame, std::span<const std::uint32_t> candidates,
                      SectionScratch& scratch);

// POLYGONS (in FROM's (u, v) frame) projected along TO's normal onto TO's plane, in TO's (u, v):
// a layer's section seen from the next one when the two planes are not parallel (tilted layers).
// The map is affine, so rings stay simple; they keep their turn while FROM.d·TO.d > 0.
std::vector<geom2d::Polygon> project(const std::vector<geom2d::Polygon>& polygons, const Frame& from, const Frame& to);

}  // namespace polyaxis::slicing
