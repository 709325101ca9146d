#include "polyaxis/mesh/properties.h"

#include <array>
#include <cmath>
#include <map>

namespace polyaxis::mesh {

core::Box3 bounding_box(const Mesh& mesh) {
  core::Box3 box;
  for (const Vec3& v : mesh.vertices) box.add(v);
  return box;
}

double solid_angle(Vec3 a, Vec3 b, Vec3 c) {
  const double la = core::norm(a), lb = core::norm(b), lc = core::norm(c);
  const double num = core::dot(a, core::cross(b, c));
  const double den = la * lb * lc + core::dot(a, b) * lc + core::dot(a, c) * lb + core::dot(b, c) * la;
  return 2.0 * std::atan2(num, den);
}

double winding_number(const Mesh& mesh, Vec3 p) {
  double omega = 0.0;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) omega += solid_angle(mesh.corner(f, 0) - p, mesh.corner(f, 1) - p, mesh.corner(f, 2) - p);
  return omega / (4.0 * 3.14159265358979323846);
}

double signed_volume(const Mesh& mesh) {
  const core::Box3 box = bounding_box(mesh);
  const Vec3 o = box.empty() ? Vec3{} : (box.min + box.max) * 0.5;
  double six_v = 0.0;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    six_v += dot(mesh.corner(f, 0) - o, cross(mesh.corner(f, 1) - o, mesh.corner(f, 2) - o));
  }
  return six_v / 6.0;
}

double surface_area(const Mesh& mesh) {
  double twice = 0.0;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) twice += norm(face_area_vector(mesh, f));
  return twice / 2.0;
}

double overhang_area(const Mesh& mesh, Vec3 direction, double self_supporting_rad) {
  const Vec3 d = normalized(direction);
  double lowest = INFINITY;
  for (const Vec3& v : mesh.vertices) lowest = std::fmin(lowest, dot(v, d));
  const double limit = -std::sin(self_supporting_rad);
  double area = 0.0;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const Vec3 n2 = face_area_vector(mesh, f);
    const double len = norm(n2);
    if (len == 0.0 || dot(n2, d) >= limit * len) continue;
    bool on_plate = true;
    for (int k = 0; k < 3; ++k) on_plate = on_plate && dot(mesh.corner(f, k), d) - lowest <= kPlateContactMm;
    if (!on_plate) area += len / 2.0;
  }
  return area;
}

std::vector<Mesh> connected_solids(const Mesh& m) {
  std::vector<std::uint32_t> parent(m.vertices.size());
  for (std::uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
  auto find = [&](std::uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (const auto& t : m.triangles) {
    const std::uint32_t a = find(t[0]);
    parent[find(t[1])] = a;
    parent[find(t[2])] = a;
  }
  std::map<std::uint32_t, std::size_t> piece_of_root;
  std::vector<Mesh> pieces;
  std::vector<std::map<std::uint32_t, std::uint32_t>> index;
  for (const auto& t : m.triangles) {
    const std::uint32_t root = find(t[0]);
    auto [it, added] = piece_of_root.try_emplace(root, pieces.size());
    if (added) pieces.emplace_back(), index.emplace_back();
    Mesh& piece = pieces[it->second];
    std::array<std::uint32_t, 3> out{};
    for (int k = 0; k < 3; ++k) {
      auto [v, fresh] = index[it->second].try_emplace(t[static_cast<std::size_t>(k)], static_cast<std::uint32_t>(piece.vertices.size()));
      if (fresh) piece.vertices.push_back(m.vertices[t[static_cast<std::size_t>(k)]]);
      out[static_cast<std::size_t>(k)] = v->second;
    }
    piece.triangles.push_back(out);
  }
  std::vector<Mesh> solids, cavities;
  for (Mesh& p : pieces) (mesh::signed_volume(p) > 0.0 ? solids : cavities).push_back(std::move(p));
  for (const Mesh& c : cavities) {
    for (Mesh& host : solids) {
      core::Box3 box;
      for (const core::Vec3& v : host.vertices) box.add(v);
      const core::Vec3 q = c.vertices.front();
      if (q.x < box.min.x || q.x > box.max.x || q.y < box.min.y || q.y > box.max.y || q.z < box.min.z || q.z > box.max.z) continue;
      const auto base = static_cast<std::uint32_t>(host.vertices.size());
      host.vertices.insert(host.vertices.end(), c.vertices.begin(), c.vertices.end());
      for (const auto& t : c.triangles) host.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
      break;
    }
  }
  return solids;
}

}  // namespace polyaxis::mesh
