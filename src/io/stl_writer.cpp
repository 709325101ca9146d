#include "polyaxis/io/stl_writer.h"

#include <algorithm>
#include <cstring>

namespace polyaxis::io {

std::string binary_stl(const RawMesh& mesh, const std::string& name) {
  std::string out(80, ' ');
  out.replace(0, std::min<std::size_t>(name.size(), 80), name.substr(0, 80));
  if (out.starts_with("solid")) out[0] = 'S';  // never look like ASCII to a reader that checks the word
  auto put = [&](const void* p, std::size_t n) { out.append(static_cast<const char*>(p), n); };
  const auto count = static_cast<std::uint32_t>(mesh.triangles.size());
  put(&count, 4);
  out.reserve(out.size() + 50 * mesh.triangles.size());
  for (const Triangle& t : mesh.triangles) {
    const core::Vec3 a = mesh.points[t[0]], b = mesh.points[t[1]], c = mesh.points[t[2]];
    const core::Vec3 n = core::normalized(core::cross(b - a, c - a));
    const float rec[12] = {static_cast<float>(n.x), static_cast<float>(n.y), static_cast<float>(n.z),
                           static_cast<float>(a.x), static_cast<float>(a.y), static_cast<float>(a.z),
                           static_cast<float>(b.x), static_cast<float>(b.y), static_cast<float>(b.z),
                           static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z)};
    put(rec, sizeof rec);
    const std::uint16_t attribute = 0;
    put(&attribute, 2);
  }
  return out;
}

}  // namespace polyaxis::io
