// Fans, orientation and shells. The nesting test uses the generalised winding number
// (Jacobson et al. 2013, solid angles by Van Oosterom & Strackee 1983): it needs no ray and no
// tie rule, and is ±1 inside a closed shell and 0 outside.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <numeric>
#include <span>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <atomic>

#include "polyaxis/mesh/properties.h"
#include "repair_steps.h"

namespace polyaxis::mesh::detail {
namespace {

std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

void unite(std::vector<std::uint32_t>& parent, std::uint32_t a, std::uint32_t b) {
  a = find_root(parent, a);
  b = find_root(parent, b);
  if (a != b) parent[std::max(a, b)] = std::min(a, b);
}

std::uint32_t corner_of(const Mesh& mesh, std::uint32_t face, std::uint32_t vertex) {
  const Triangle& t = mesh.triangles[face];
  return 3 * face + (t[0] == vertex ? 0u : (t[1] == vertex ? 1u : 2u));
}

constexpr double kFourPi = 4.0 * 3.14159265358979323846;
constexpr std::size_t kMaxShellsForNesting = 2000;  // nesting is pairwise: bound the cost
constexpr std::size_t kNestingProbes = 8;          // corners tested per shell, besides one face centroid

struct ComponentInfo {
  double volume = 0.0;
  double area = 0.0;
  core::Box3 box;
  int depth = 0;
  bool drop = false;
};

// The corner at VERTEX of the face of half-edge H, and the edge of that corner other than H.
std::uint32_t other_edge_at(const Mesh& mesh, std::uint32_t h, std::uint32_t vertex) {
  const std::uint32_t f = h / 3;
  const std::uint32_t c = corner_of(mesh, f, vertex) % 3;  // the corner's outgoing edge is 3f+c
  const std::uint32_t out = 3 * f + c, in = 3 * f + (c + 2) % 3;
  return h == out ? in : out;
}

// Corners of VERTEX reached from corner C by crossing two-face edges at the vertex, both ways
// round (a fan is a path or a cycle of corners); stops after LIMIT.
std::uint32_t fan_size(const Mesh& mesh, const EdgeTopology& topo, std::uint32_t c, std::uint32_t vertex, std::uint32_t limit) {
  const std::uint32_t f = c / 3, k = c % 3;
  std::uint32_t visited = 1;
  const std::uint32_t start_edges[2] = {3 * f + k, 3 * f + (k + 2) % 3};
  for (const std::uint32_t first : start_edges) {
    for (std::uint32_t e = first; visited <= limit;) {
      const std::uint32_t o = topo.opposite[e];
      if (o == kNoHalfEdge) break;
      if (o / 3 == f) return visited;  // back at the start: a closed fan, walked once
      ++visited;
      e = other_edge_at(mesh, o, vertex);
    }
  }
  return visited;
}

// True when every vertex's corners form one fan, so split_nonmanifold_vertices has nothing to do.
// Parallel and read-only: the common case of a clean mesh costs one walk round each vertex.
bool every_vertex_one_fan(const Mesh& mesh, const EdgeTopology& topo) {
  const std::size_t nv = mesh.vertices.size(), nc = 3 * mesh.triangles.size();
  std::vector<std::uint32_t> corners(nv, 0), first(nv, kNoHalfEdge);
  for (std::uint32_t c = 0; c < nc; ++c) {
    const std::uint32_t v = mesh.triangles[c / 3][c % 3];
    if (corners[v]++ == 0) first[v] = c;
  }
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, nv, std::size_t{1} << 14), true,
      [&](const tbb::blocked_range<std::size_t>& r, bool ok) {
        for (std::size_t v = r.begin(); ok && v != r.end(); ++v) {
          if (corners[v] == 0) continue;
          ok = fan_size(mesh, topo, first[v], static_cast<std::uint32_t>(v), corners[v]) == corners[v];
        }
        return ok;
      },
      [](bool a, bool b) { return a && b; });
}

}  // namespace

std::uint64_t split_nonmanifold_vertices(Mesh& mesh, const EdgeTopology& topo) {
  if (topo.nonmanifold_edges == 0 && every_vertex_one_fan(mesh, topo)) return 0;
  const std::size_t nc = 3 * mesh.triangles.size();
  std::vector<std::uint32_t> parent(nc);
  std::iota(parent.begin(), parent.end(), 0u);
  for (std::uint32_t h = 0; h < nc; ++h) {
    const std::uint32_t o = topo.opposite[h];
    if (o == kNoHalfEdge || o < h) continue;
    const std::uint32_t a = half_edge_from(mesh, h), b = half_edge_to(mesh, h);
    unite(parent, h, corner_of(mesh, o / 3, a));
    unite(parent, 3 * (h / 3) + (h % 3 + 1) % 3, corner_of(mesh, o / 3, b));
  }
  // For each vertex, the fan of its lowest corner keeps it; other fans get copies in corner order.
  const std::size_t nv = mesh.vertices.size();
  std::vector<std::uint32_t> owner_root(nv, kNoHalfEdge);
  std::vector<std::uint32_t> copy_of_root(nc, kNoHalfEdge);
  std::uint64_t copies = 0;
  for (std::uint32_t c = 0; c < nc; ++c) {
    const std::uint32_t v = mesh.triangles[c / 3][c % 3];
    const std::uint32_t r = find_root(parent, c);
    if (owner_root[v] == kNoHalfEdge) owner_root[v] = r;
    if (owner_root[v] == r) continue;
    if (copy_of_root[r] == kNoHalfEdge) {
      copy_of_root[r] = static_cast<std::uint32_t>(mesh.vertices.size());
      mesh.vertices.push_back(mesh.vertices[v]);
      ++copies;
    }
    mesh.triangles[c / 3][c % 3] = copy_of_root[r];
  }
  return copies;
}

// Connected components of faces across two-face edges, numbered by their lowest face, by a
// lock-free union-find that always links the larger root under the smaller (so the roots, and the
// numbering, do not depend on the interleaving). Used when no face needs flipping.
std::vector<std::uint32_t> face_components(const EdgeTopology& topo, std::size_t nf) {
  std::vector<std::atomic<std::uint32_t>> parent(nf);
  tbb::parallel_for(std::size_t{0}, nf, [&](std::size_t f) { parent[f].store(static_cast<std::uint32_t>(f), std::memory_order_relaxed); });
  auto find = [&](std::uint32_t x) {
    while (true) {
      const std::uint32_t p = parent[x].load(std::memory_order_relaxed);
      if (p == x) return x;
      const std::uint32_t g = parent[p].load(std::memory_order_relaxed);
      if (g != p) {  // path halving: point X at its grandparent, an ancestor in the same tree
        std::uint32_t expected = p;
        parent[x].compare_exchange_weak(expected, g, std::memory_order_relaxed);
      }
      x = g;
    }
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, 3 * nf, std::size_t{1} << 14), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t h = r.begin(); h != r.end(); ++h) {
      const std::uint32_t o = topo.opposite[h];
      if (o == kNoHalfEdge || o < h) continue;
      std::uint32_t a = static_cast<std::uint32_t>(h / 3), b = o / 3;
      while (true) {
        a = find(a);
        b = find(b);
        if (a == b) break;
        if (a < b) std::swap(a, b);
        std::uint32_t expected = a;
        if (parent[a].compare_exchange_strong(expected, b, std::memory_order_relaxed)) break;
      }
    }
  });
  constexpr std::uint32_t kUnset = 0xffffffffu;
  std::vector<std::uint32_t> id_of_root(nf, kUnset), component(nf);
  std::uint32_t next_id = 0;
  for (std::uint32_t f = 0; f < nf; ++f) {
    const std::uint32_t r = find(f);
    if (id_of_root[r] == kUnset) id_of_root[r] = next_id++;
    component[f] = id_of_root[r];
  }
  return component;
}

core::Result<std::uint64_t> orient_faces(Mesh& mesh, const EdgeTopology& topo, std::vector<std::uint32_t>& component) {
  const std::size_t nf = mesh.triangles.size();
  if (topo.misoriented_edges == 0) {  // every two-face edge already agrees: nothing to flip
    component = face_components(topo, nf);
    return std::uint64_t{0};
  }
  constexpr std::uint32_t kUnset = 0xffffffffu;
  component.assign(nf, kUnset);
  std::vector<char> flip(nf, 0);
  std::vector<std::uint32_t> queue;
  std::vector<std::uint64_t> flips_in, size_of;
  std::uint32_t next_id = 0;
  for (std::uint32_t seed = 0; seed < nf; ++seed) {
    if (component[seed] != kUnset) continue;
    const std::uint32_t id = next_id++;
    std::uint64_t flips = 0, size = 0;
    queue.assign(1, seed);
    component[seed] = id;
    for (std::size_t qi = 0; qi < queue.size(); ++qi) {
      const std::uint32_t f = queue[qi];
      ++size;
      flips += static_cast<std::uint64_t>(flip[f]);
      for (std::uint32_t k = 0; k < 3; ++k) {
        const std::uint32_t h = 3 * f + k, o = topo.opposite[h];
        if (o == kNoHalfEdge) continue;
        const std::uint32_t g = o / 3;
        const char same_direction = half_edge_from(mesh, h) == half_edge_from(mesh, o) ? 1 : 0;
        const char want = static_cast<char>(flip[f] ^ same_direction);
        if (component[g] == kUnset) {
          component[g] = id;
          flip[g] = want;
          queue.push_back(g);
        } else if (flip[g] != want) {
          const Vec3 p = mesh.vertices[half_edge_from(mesh, h)];
          return core::make_error(core::ErrorCode::kInfeasible,
                                  fmt::format("non-orientable surface (a Möbius-like band) at facet {} near ({:g}, {:g}, {:g})", g, p.x,
                                              p.y, p.z));
        }
      }
    }
    flips_in.push_back(flips);
    size_of.push_back(size);
  }
  std::uint64_t flipped = 0;
  for (std::uint32_t f = 0; f < nf; ++f) {
    const std::uint32_t id = component[f];
    const bool majority_flipped = 2 * flips_in[id] > size_of[id];
    if (static_cast<bool>(flip[f]) != majority_flipped) {
      std::swap(mesh.triangles[f][1], mesh.triangles[f][2]);
      ++flipped;
    }
  }
  return flipped;
}

namespace {

// Box, volume and area of each component. One component (the common case) is measured in
// parallel over fixed blocks of faces whose sums are added in block order, so the figures do not
// depend on the thread count.
void measure_components(const Mesh& mesh, const std::vector<std::uint32_t>& component, std::vector<ComponentInfo>& info) {
  const std::size_t nf = mesh.triangles.size();
  auto volume_and_area = [&](std::uint32_t f, Vec3 o) {
    const Vec3 a = mesh.corner(f, 0) - o, b = mesh.corner(f, 1) - o, d = mesh.corner(f, 2) - o;
    return std::pair<double, double>{dot(a, cross(b, d)), norm(cross(b - a, d - a))};
  };
  if (info.size() == 1) {
    constexpr std::size_t kBlock = std::size_t{1} << 15;
    const std::size_t blocks = (nf + kBlock - 1) / kBlock;
    std::vector<core::Box3> box(blocks);
    std::vector<std::pair<double, double>> sums(blocks, {0.0, 0.0});
    auto faces = [&](std::size_t b) { return std::pair<std::size_t, std::size_t>{b * kBlock, std::min(nf, (b + 1) * kBlock)}; };
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
      for (auto [f, end] = faces(b); f < end; ++f) {
        for (int k = 0; k < 3; ++k) box[b].add(mesh.corner(f, k));
      }
    });
    for (const core::Box3& b : box) info[0].box.add(b.min), info[0].box.add(b.max);
    const Vec3 o = (info[0].box.min + info[0].box.max) * 0.5;
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
      for (auto [f, end] = faces(b); f < end; ++f) {
        const auto [v, a] = volume_and_area(static_cast<std::uint32_t>(f), o);
        sums[b].first += v;
        sums[b].second += a;
      }
    });
    double six_v = 0.0, twice_a = 0.0;
    for (const auto& [v, a] : sums) six_v += v, twice_a += a;
    info[0].volume = six_v / 6.0;
    info[0].area = twice_a / 2.0;
    return;
  }
  for (std::uint32_t f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) info[component[f]].box.add(mesh.corner(f, k));
  }
  std::vector<double> six_v(info.size(), 0.0), twice_a(info.size(), 0.0);
  for (std::uint32_t f = 0; f < nf; ++f) {
    const std::uint32_t c = component[f];
    const auto [v, a] = volume_and_area(f, (info[c].box.min + info[c].box.max) * 0.5);
    six_v[c] += v;
    twice_a[c] += a;
  }
  for (std::size_t c = 0; c < info.size(); ++c) {
    info[c].volume = six_v[c] / 6.0;
    info[c].area = twice_a[c] / 2.0;
  }
}

}  // namespace

std::vector<Shell> build_shells(Mesh& mesh, const std::vector<std::uint32_t>& component, bool closed, RepairReport& report) {
  const std::size_t nf = mesh.triangles.size();
  std::uint32_t count = 0;
  for (auto c : component) count = std::max(count, c + 1);
  std::vector<ComponentInfo> info(count);
  // Faces grouped by component (a counting sort), keeping face order within each.
  std::vector<std::uint32_t> start(count + 1, 0);
  for (auto c : component) ++start[c + 1];
  for (std::uint32_t c = 0; c < count; ++c) start[c + 1] += start[c];
  std::vector<std::uint32_t> by_component(nf);
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::uint32_t f = 0; f < nf; ++f) by_component[fill[component[f]]++] = f;
  }
  auto faces_of = [&](std::uint32_t c) {
    return std::span<const std::uint32_t>(by_component.data() + start[c], start[c + 1] - start[c]);
  };
  measure_components(mesh, component, info);
  if (closed && count > 1 && count <= kMaxShellsForNesting) {
    for (std::uint32_t s = 0; s < count; ++s) {
      // Probes: the centroid of the shell's largest face and up to kNestingProbes of its corners,
      // spread over its faces. A shell is inside another only when every probe is: shells that
      // merely overlap (a self-intersecting model) are not nested.
      std::vector<Vec3> probes;
      {
        std::uint32_t best = faces_of(s).front();
        double best_area = -1.0;
        for (auto f : faces_of(s)) {
          const double a = norm(face_area_vector(mesh, f));
          if (a > best_area) best_area = a, best = f;
        }
        probes.push_back((mesh.corner(best, 0) + mesh.corner(best, 1) + mesh.corner(best, 2)) / 3.0);
        const auto faces = faces_of(s);
        const std::size_t step = std::max<std::size_t>(1, faces.size() / kNestingProbes);
        for (std::size_t i = 0; i < faces.size() && probes.size() <= kNestingProbes; i += step) {
          probes.push_back((mesh.corner(faces[i], 0) * 0.98 + mesh.corner(faces[i], 1) * 0.01 + mesh.corner(faces[i], 2) * 0.01));
        }
      }
      for (std::uint32_t t = 0; t < count; ++t) {
        if (t == s) continue;
        const core::Box3& b = info[t].box;
        bool inside = true;
        for (const Vec3& p : probes) {
          if (p.x < b.min.x || p.x > b.max.x || p.y < b.min.y || p.y > b.max.y || p.z < b.min.z || p.z > b.max.z) {
            inside = false;
            break;
          }
          double omega = 0.0;
          for (auto f : faces_of(t)) omega += solid_angle(mesh.corner(f, 0) - p, mesh.corner(f, 1) - p, mesh.corner(f, 2) - p);
          if (!(std::fabs(omega / kFourPi) > core::kInsideWindingNumber)) {
            inside = false;
            break;
          }
        }
        if (inside) ++info[s].depth;
      }
    }
  }
  for (std::uint32_t c = 0; c < count; ++c) {
    ComponentInfo& ci = info[c];
    const bool inside = ci.depth % 2 == 1;
    if (!inside && ci.volume < 0.0) {  // T3: inside-out solid
      for (auto f : faces_of(c)) std::swap(mesh.triangles[f][1], mesh.triangles[f][2]);
      ci.volume = -ci.volume;
      ++report.inverted_shells;
      report.flipped_faces += faces_of(c).size();
    } else if (inside && ci.volume > 0.0) {  // T8: same orientation inside another: union drops it
      ci.drop = true;
      ++report.interior_shells_removed;
    }
  }
  // Solids by descending volume, then cavities by descending |volume|; ties by component id.
  std::vector<std::uint32_t> order(count);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    const bool ca = info[a].volume < 0.0, cb = info[b].volume < 0.0;
    if (ca != cb) return !ca;
    return std::fabs(info[a].volume) > std::fabs(info[b].volume);
  });
  std::vector<Shell> shells;
  std::vector<Triangle> ordered;
  const bool reorder = count > 1;  // one component: faces are already in shell order
  if (reorder) ordered.reserve(nf);
  for (auto id : order) {
    const ComponentInfo& ci = info[id];
    if (ci.drop) continue;
    Shell shell;
    shell.first_face = reorder ? static_cast<std::uint32_t>(ordered.size()) : 0;
    shell.face_count = static_cast<std::uint32_t>(faces_of(id).size());
    shell.volume_mm3 = ci.volume;
    shell.area_mm2 = ci.area;
    shell.cavity = ci.volume < 0.0;
    shell.closed = closed;
    if (reorder) {
      for (auto f : faces_of(id)) ordered.push_back(mesh.triangles[f]);
    }
    shells.push_back(shell);
  }
  if (reorder) mesh.triangles = std::move(ordered);
  return shells;
}

}  // namespace polyaxis::mesh::detail
