// Direction-parallel fill: the piece is rotated once so the scan lines are horizontal, every edge
// is crossed with the lines exactly (integer arithmetic, one tie rule), crossings on a line are
// paired inside/outside, and neighbouring lines are chained along the boundary between them.
//
// Tie rule: edge (a, b) crosses the line y = Y when exactly one of its ends has y > Y, i.e. when
// min(a.y, b.y) <= Y < max(a.y, b.y). Each closed ring then crosses every line an even number of
// times, so sorted crossings pair up into the spans inside the piece.
#include "zigzag.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace polyaxis::toolpath::detail {
namespace {

using geom2d::Int128;
using geom2d::Point;
using geom2d::Ring;

struct Crossing {
  std::int64_t k = 0;  // scan line
  std::int64_t x = 0;
  std::uint32_t ring = 0;
  std::uint32_t edge = 0;  // edge e runs from vertex e to vertex e + 1 of the ring
};

struct Span {
  std::int64_t k = 0;
  Crossing left, right;
};

struct EndKey {
  std::uint32_t ring, edge;
  std::int64_t k;
  std::uint32_t span;
  bool right;
};

// floor(a / b) for b > 0.
std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  std::int64_t q = a / b;
  if ((a % b != 0) && (a < 0)) --q;
  return q;
}

// num / den rounded to nearest (halves up), den > 0.
std::int64_t round_div(Int128 num, Int128 den) {
  Int128 n2 = 2 * num + den, d2 = 2 * den;
  Int128 q = n2 / d2;
  if ((n2 % d2 != 0) && (n2 < 0)) --q;
  return static_cast<std::int64_t>(q);
}

Ring rotated(const Ring& ring, double c, double s) {
  Ring out;
  out.reserve(ring.size());
  for (const Point& p : ring) {
    const double x = static_cast<double>(p.x), y = static_cast<double>(p.y);
    const Point q{std::llround(c * x + s * y), std::llround(-s * x + c * y)};
    if (out.empty() || !(out.back() == q)) out.push_back(q);
  }
  while (out.size() > 1 && out.front() == out.back()) out.pop_back();
  return out;
}

}  // namespace

std::vector<Ring> zigzag(const geom2d::Polygon& piece, double angle_rad, std::int64_t spacing) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  std::vector<Ring> rings;
  auto add = [&](const Ring& ring) {
    Ring q = rotated(ring, c, s);
    if (q.size() >= 3) rings.push_back(std::move(q));
  };
  add(piece.outer);
  for (const Ring& h : piece.holes) add(h);
  if (rings.empty()) return {};
  std::int64_t ymin = rings.front().front().y, ymax = ymin;
  for (const Ring& r : rings) {
    for (const Point& p : r) {
      ymin = std::min(ymin, p.y);
      ymax = std::max(ymax, p.y);
    }
  }
  // The lines are spread evenly across the piece: as many as a spacing of at most SPACING needs,
  // the first and the last the same half spacing from its lowest and highest points. Lines laid
  // from one side at exactly SPACING leave up to a spacing bare along the far side, a strip a bead
  // can only bridge (a 0.45 mm void along a 0.9 mm bead's perimeter).
  const std::int64_t height = ymax - ymin;
  if (height <= spacing / 2) return {};
  const std::int64_t lines = (height + spacing - 1) / spacing;  // ceil: spacing' = height / lines <= spacing
  const std::int64_t step = std::max<std::int64_t>(1, height / lines);
  const std::int64_t y0 = ymin + (height - (lines - 1) * step) / 2;
  const std::int64_t kmax = floor_div(ymax - 1 - y0, step);
  auto line_y = [&](std::int64_t k) { return y0 + k * step; };

  std::vector<Crossing> crossings;
  for (std::uint32_t ri = 0; ri < rings.size(); ++ri) {
    const Ring& r = rings[ri];
    for (std::uint32_t e = 0; e < r.size(); ++e) {
      const Point a = r[e], b = r[(e + 1) % r.size()];
      const std::int64_t lo = std::min(a.y, b.y), hi = std::max(a.y, b.y);
      if (lo == hi) continue;
      const std::int64_t k0 = std::max<std::int64_t>(0, -floor_div(y0 - lo, step));  // ceil((lo - y0) / step)
      const std::int64_t k1 = std::min(kmax, floor_div(hi - 1 - y0, step));
      for (std::int64_t k = k0; k <= k1; ++k) {
        const std::int64_t y = line_y(k);
        const Int128 num = static_cast<Int128>(y - a.y) * (b.x - a.x);
        Int128 den = b.y - a.y;
        Int128 n = num;
        if (den < 0) {
          den = -den;
          n = -n;
        }
        crossings.push_back({k, a.x + round_div(n, den), ri, e});
      }
    }
  }
  std::sort(crossings.begin(), crossings.end(), [](const Crossing& p, const Crossing& q) {
    return std::tie(p.k, p.x, p.ring, p.edge) < std::tie(q.k, q.x, q.ring, q.edge);
  });
  std::vector<Span> spans;
  std::vector<EndKey> ends;
  for (std::size_t i = 0; i + 1 < crossings.size();) {
    if (crossings[i + 1].k != crossings[i].k) {
      ++i;  // unpaired (only if rounding made a ring non-simple); skip it
      continue;
    }
    const auto id = static_cast<std::uint32_t>(spans.size());
    spans.push_back({crossings[i].k, crossings[i], crossings[i + 1]});
    ends.push_back({crossings[i].ring, crossings[i].edge, crossings[i].k, id, false});
    ends.push_back({crossings[i + 1].ring, crossings[i + 1].edge, crossings[i + 1].k, id, true});
    i += 2;
  }
  std::sort(ends.begin(), ends.end(), [](const EndKey& p, const EndKey& q) {
    return std::tie(p.ring, p.edge, p.k) < std::tie(q.ring, q.edge, q.k);
  });
  auto find_end = [&](std::uint32_t ring, std::uint32_t edge, std::int64_t k) -> const EndKey* {
    auto it = std::lower_bound(ends.begin(), ends.end(), std::tuple(ring, edge, k), [](const EndKey& p, const auto& key) {
      return std::tie(p.ring, p.edge, p.k) < key;
    });
    if (it == ends.end() || it->ring != ring || it->edge != edge || it->k != k) return nullptr;
    return &*it;
  };

  // From crossing END on line k, follows the boundary upwards (into y > Y_k). Returns the end it
  // reaches on line k + 1, collecting the boundary vertices passed into CONNECTOR, or nullptr
  // when the boundary turns back to line k first (the two lines are not neighbours there).
  auto walk_up = [&](const Crossing& end, Ring& connector) -> const EndKey* {
    const Ring& r = rings[end.ring];
    const auto n = static_cast<std::int64_t>(r.size());
    const std::int64_t y_here = line_y(end.k), y_next = line_y(end.k + 1);
    const bool forward = r[(end.edge + 1) % r.size()].y > y_here;
    std::int64_t i = forward ? static_cast<std::int64_t>(end.edge) + 1 : static_cast<std::int64_t>(end.edge);
    for (std::int64_t steps = 0; steps < n; ++steps) {
      const std::int64_t wi = ((i % n) + n) % n;
      const Point v = r[static_cast<std::size_t>(wi)];
      if (v.y > y_next) {
        if (end.k + 1 > kmax) return nullptr;
        const std::int64_t edge = forward ? (((wi - 1) % n) + n) % n : wi;
        return find_end(end.ring, static_cast<std::uint32_t>(edge), end.k + 1);
      }
      if (v.y <= y_here) return nullptr;
      connector.push_back(v);
      i += forward ? 1 : -1;
    }
    return nullptr;
  };

  std::vector<Ring> out;
  std::vector<char> used(spans.size(), 0);
  for (std::uint32_t first = 0; first < spans.size(); ++first) {
    if (used[first]) continue;
    Ring line;
    auto push = [&line](Point p) {
      if (line.empty() || !(line.back() == p)) line.push_back(p);
    };
    std::uint32_t cur = first;
    bool rightwards = true;
    while (true) {
      used[cur] = 1;
      const Span& sp = spans[cur];
      const std::int64_t y = line_y(sp.k);
      const Crossing& from = rightwards ? sp.left : sp.right;
      const Crossing& to = rightwards ? sp.right : sp.left;
      push({from.x, y});
      push({to.x, y});
      Ring connector;
      const EndKey* next = walk_up(to, connector);
      // The boundary leaving the right end of a span reaches the right end of the next span
      // (interior on the same side); anything else is a rounding artefact: stop there.
      if (next == nullptr || next->right != rightwards || used[next->span]) break;
      for (const Point& p : connector) push(p);
      cur = next->span;
      rightwards = !rightwards;
    }
    if (line.size() < 2) continue;
    for (Point& p : line) {
      const double x = static_cast<double>(p.x), yy = static_cast<double>(p.y);
      p = {std::llround(c * x - s * yy), std::llround(s * x + c * yy)};
    }
    Ring clean;
    for (const Point& p : line) {
      if (clean.empty() || !(clean.back() == p)) clean.push_back(p);
    }
    if (clean.size() >= 2) out.push_back(std::move(clean));
  }
  return out;
}

}  // namespace polyaxis::toolpath::detail
