// Point-to-surface distance through CGAL's AABB tree (Simple_cartesian<double>: the queries are
// constructions, and a filtered kernel buys nothing here). One of the translation units that
// include CGAL (src/CMakeLists.txt).
#include "polyaxis/mesh/distance.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <queue>
#include <unordered_map>
#include <vector>

namespace polyaxis::mesh {

using K = CGAL::Simple_cartesian<double>;
using Triangle3 = K::Triangle_3;
using Iterator = std::vector<Triangle3>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<K, Iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

struct SurfaceDistance::Impl {
  std::vector<Triangle3> triangles;
  std::vector<std::array<std::uint32_t, 3>> corners;  // the mesh vertices of each triangle
  std::vector<Vec3> normals;                           // per triangle, unit
  std::vector<std::array<Vec3, 3>> edge_normals;       // per triangle, edge k from corner k to k+1
  std::vector<Vec3> vertex_normals;                    // per mesh vertex, angle-weighted
  Tree tree;
};

namespace {

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

double angle_at(Vec3 p, Vec3 a, Vec3 b) {
  const Vec3 u = a - p, v = b - p;
  return std::atan2(core::norm(core::cross(u, v)), core::dot(u, v));
}

// A barycentric coordinate at most this is zero: the nearest point is on an edge or a vertex.
constexpr double kOnFeature = 1e-9;

}  // namespace

SurfaceDistance::SurfaceDistance(const Mesh& surface) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.vertex_normals.assign(surface.vertices.size(), Vec3{});
  std::unordered_map<std::uint64_t, Vec3> edge_sum;
  for (std::size_t f = 0; f < surface.triangles.size(); ++f) {
    const Vec3 n = face_area_vector(surface, f);
    const double len = core::norm(n);
    if (!(len > 0.0)) continue;
    const auto& t = surface.triangles[f];
    const Vec3 p[3] = {surface.corner(f, 0), surface.corner(f, 1), surface.corner(f, 2)};
    m.triangles.emplace_back(K::Point_3(p[0].x, p[0].y, p[0].z), K::Point_3(p[1].x, p[1].y, p[1].z), K::Point_3(p[2].x, p[2].y, p[2].z));
    m.corners.push_back({t[0], t[1], t[2]});
    m.normals.push_back(n / len);
    for (int k = 0; k < 3; ++k) {
      m.vertex_normals[t[k]] = m.vertex_normals[t[k]] + m.normals.back() * angle_at(p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
      Vec3& e = edge_sum[edge_key(t[k], t[(k + 1) % 3])];
      e = e + m.normals.back();
    }
  }
  for (const auto& t : m.corners) {
    std::array<Vec3, 3> e;
    for (std::size_t k = 0; k < 3; ++k) e[k] = edge_sum[edge_key(t[k], t[(k + 1) % 3])];
    m.edge_normals.push_back(e);
  }
  if (m.triangles.empty()) return;
  m.tree.insert(m.triangles.cbegin(), m.triangles.cend());
  m.tree.build();
  m.tree.accelerate_distance_queries();
}

SurfaceDistance::~SurfaceDistance() = default;

bool SurfaceDistance::empty() const { return impl_->triangles.empty(); }

Nearest SurfaceDistance::nearest(Vec3 p) const {
  const K::Point_3 q(p.x, p.y, p.z);
  const auto [point, primitive] = impl_->tree.closest_point_and_primitive(q);
  return described(p, {point.x(), point.y(), point.z()}, static_cast<std::size_t>(primitive - impl_->triangles.cbegin()));
}

Nearest SurfaceDistance::nearest(Vec3 p, const Nearest& near) const {
  const K::Point_3 q(p.x, p.y, p.z);
  const Tree::Point_and_primitive_id hint(K::Point_3(near.point.x, near.point.y, near.point.z), impl_->triangles.cbegin() + near.face);
  const auto [point, primitive] = impl_->tree.closest_point_and_primitive(q, hint);
  return described(p, {point.x(), point.y(), point.z()}, static_cast<std::size_t>(primitive - impl_->triangles.cbegin()));
}

Nearest SurfaceDistance::described(Vec3 p, Vec3 point, std::size_t i) const {
  const Impl& m = *impl_;
  Nearest out;
  out.face = static_cast<std::uint32_t>(i);
  out.point = point;
  // Barycentric coordinates of the nearest point: which feature it lies on.
  const Triangle3& t = m.triangles[i];
  const Vec3 a{t[0].x(), t[0].y(), t[0].z()}, b{t[1].x(), t[1].y(), t[1].z()}, c{t[2].x(), t[2].y(), t[2].z()};
  const Vec3 n = m.normals[i];
  const double whole = core::dot(core::cross(b - a, c - a), n);
  const double l[3] = {core::dot(core::cross(b - out.point, c - out.point), n) / whole, core::dot(core::cross(c - out.point, a - out.point), n) / whole,
                       core::dot(core::cross(a - out.point, b - out.point), n) / whole};
  const int zeros = (l[0] <= kOnFeature) + (l[1] <= kOnFeature) + (l[2] <= kOnFeature);
  Vec3 pseudo = n;
  if (zeros >= 2) {
    const std::size_t v = l[0] > kOnFeature ? 0 : (l[1] > kOnFeature ? 1 : 2);
    pseudo = m.vertex_normals[m.corners[i][v]];
  } else if (zeros == 1) {
    const std::size_t opposite = l[0] <= kOnFeature ? 0 : (l[1] <= kOnFeature ? 1 : 2);
    pseudo = m.edge_normals[i][(opposite + 1) % 3];
  }
  out.normal = core::norm(pseudo) > 0.0 ? core::normalized(pseudo) : n;
  const double dist = core::norm(p - out.point);
  out.signed_mm = core::dot(p - out.point, out.normal) < 0.0 ? -dist : dist;
  return out;
}

namespace {

constexpr std::uint32_t kNone = 0xffffffffu;

}  // namespace

Mesh refine(const Mesh& mesh, double max_edge_mm) {
  const double limit2 = max_edge_mm * max_edge_mm;
  auto long_edge = [&](Vec3 a, Vec3 b) { return core::dot(b - a, b - a) > limit2; };
  return *refine(mesh, long_edge, std::numeric_limits<std::size_t>::max());
}

std::optional<Mesh> refine(const Mesh& mesh, const std::function<bool(Vec3 a, Vec3 b)>& split, std::size_t max_faces) {
  Mesh out = mesh;
  auto& tris = out.triangles;
  auto& verts = out.vertices;
  // Edge -> its (up to two) faces.
  std::unordered_map<std::uint64_t, std::array<std::uint32_t, 2>> faces_of;
  faces_of.reserve(tris.size() * 2);
  for (std::uint32_t f = 0; f < tris.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      auto [it, fresh] = faces_of.try_emplace(edge_key(tris[f][k], tris[f][(k + 1) % 3]), std::array<std::uint32_t, 2>{f, kNone});
      if (!fresh && it->second[1] == kNone) it->second[1] = f;
    }
  }
  auto replace = [&](std::uint32_t a, std::uint32_t b, std::uint32_t from, std::uint32_t to) {
    auto it = faces_of.find(edge_key(a, b));
    if (it == faces_of.end()) return;
    for (std::uint32_t& g : it->second)
      if (g == from) g = to;
  };
  // The longest edge of face F that SPLIT takes, or -1.
  auto to_split = [&](std::uint32_t f) {
    int order[3] = {0, 1, 2};
    double len2[3];
    for (int k = 0; k < 3; ++k) {
      const Vec3 e = verts[tris[f][(k + 1) % 3]] - verts[tris[f][k]];
      len2[k] = core::dot(e, e);
    }
    std::sort(order, order + 3, [&](int x, int y) { return len2[x] > len2[y]; });
    for (const int k : order) {
      if (split(verts[tris[f][k]], verts[tris[f][(k + 1) % 3]])) return k;
    }
    return -1;
  };
  std::queue<std::uint32_t> todo;
  for (std::uint32_t f = 0; f < tris.size(); ++f) todo.push(f);
  while (!todo.empty()) {
    const std::uint32_t f = todo.front();
    todo.pop();
    const int k = to_split(f);
    if (k < 0) continue;
    if (tris.size() + 2 > max_faces) return std::nullopt;
    const std::uint32_t a = tris[f][k], b = tris[f][(k + 1) % 3], c = tris[f][(k + 2) % 3];
    const auto key = edge_key(a, b);
    const std::array<std::uint32_t, 2> pair = faces_of.at(key);
    const std::uint32_t g = pair[0] == f ? pair[1] : pair[0];
    const auto m = static_cast<std::uint32_t>(verts.size());
    verts.push_back((verts[a] + verts[b]) * 0.5);
    faces_of.erase(key);
    // f = (a, b, c) becomes (a, m, c) and f2 = (m, b, c).
    const auto f2 = static_cast<std::uint32_t>(tris.size());
    tris[f] = {a, m, c};
    tris.push_back({m, b, c});
    replace(b, c, f, f2);
    faces_of[edge_key(m, c)] = {f, f2};
    std::uint32_t g_am = kNone, g_mb = kNone;
    if (g != kNone) {
      // g = (p, q, d) with {p, q} = {a, b} becomes (p, m, d) and g2 = (m, q, d).
      const auto tg = tris[g];
      int j = 0;
      while (j < 3 && edge_key(tg[j], tg[(j + 1) % 3]) != key) ++j;
      const std::uint32_t p = tg[j], q = tg[(j + 1) % 3], d = tg[(j + 2) % 3];
      const auto g2 = static_cast<std::uint32_t>(tris.size());
      tris[g] = {p, m, d};
      tris.push_back({m, q, d});
      replace(q, d, g, g2);
      faces_of[edge_key(m, d)] = {g, g2};
      g_am = p == a ? g : g2, g_mb = p == a ? g2 : g;
      todo.push(g), todo.push(g2);
    }
    faces_of[edge_key(a, m)] = {f, g_am};
    faces_of[edge_key(m, b)] = {f2, g_mb};
    todo.push(f), todo.push(f2);
  }
  return out;
}

}  // namespace polyaxis::mesh
