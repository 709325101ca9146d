#include "polyaxis/mesh/properties.h"

#include <cmath>

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

}  // namespace polyaxis::mesh
