// Point-to-surface distance through CGAL's AABB tree (Simple_cartesian<double>: the queries are
// constructions, and a filtered kernel buys nothing here). One of the translation units that
// include CGAL (src/CMakeLists.txt).
#include "polyaxis/mesh/distance.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <array>
#include <cmath>
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
  std::vector<Vec3> normals;
  Tree tree;
};

SurfaceDistance::SurfaceDistance(const Mesh& surface) : impl_(std::make_unique<Impl>()) {
  for (std::size_t f = 0; f < surface.triangles.size(); ++f) {
    const Vec3 n = face_area_vector(surface, f);
    const double len = core::norm(n);
    if (!(len > 0.0)) continue;
    const Vec3 a = surface.corner(f, 0), b = surface.corner(f, 1), c = surface.corner(f, 2);
    impl_->triangles.emplace_back(K::Point_3(a.x, a.y, a.z), K::Point_3(b.x, b.y, b.z), K::Point_3(c.x, c.y, c.z));
    impl_->normals.push_back(n / len);
  }
  if (impl_->triangles.empty()) return;
  impl_->tree.insert(impl_->triangles.cbegin(), impl_->triangles.cend());
  impl_->tree.build();
  impl_->tree.accelerate_distance_queries();
}

SurfaceDistance::~SurfaceDistance() = default;

bool SurfaceDistance::empty() const { return impl_->triangles.empty(); }

Nearest SurfaceDistance::nearest(Vec3 p) const {
  const K::Point_3 q(p.x, p.y, p.z);
  const auto [point, primitive] = impl_->tree.closest_point_and_primitive(q);
  Nearest out;
  out.point = {point.x(), point.y(), point.z()};
  out.normal = impl_->normals[static_cast<std::size_t>(primitive - impl_->triangles.cbegin())];
  const double dist = core::norm(p - out.point);
  out.signed_mm = core::dot(p - out.point, out.normal) < 0.0 ? -dist : dist;
  return out;
}

namespace {

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

constexpr std::uint32_t kNone = 0xffffffffu;

}  // namespace

Mesh refine(const Mesh& mesh, double max_edge_mm) {
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
  const double limit2 = max_edge_mm * max_edge_mm;
  auto longest = [&](std::uint32_t f, double& len2) {
    int best = 0;
    len2 = -1.0;
    for (int k = 0; k < 3; ++k) {
      const double l = [](Vec3 e) { return core::dot(e, e); }(verts[tris[f][(k + 1) % 3]] - verts[tris[f][k]]);
      if (l > len2) len2 = l, best = k;
    }
    return best;
  };
  std::queue<std::uint32_t> todo;
  for (std::uint32_t f = 0; f < tris.size(); ++f) todo.push(f);
  while (!todo.empty()) {
    const std::uint32_t f = todo.front();
    todo.pop();
    double len2 = 0.0;
    const int k = longest(f, len2);
    if (len2 <= limit2) continue;
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
