// SPDX-License-Identifier: GPL-3.0-or-later
// The area of a union of grid polygons, cluster by cluster.
//
// A receiver's casts fall into groups that do not touch: the shadows of the boxes around one
// street corner never meet those of the next block. Polygons whose bounding boxes do not overlap
// (interiors disjoint) add their areas, so the union's area is the sum over clusters of
// overlapping boxes (connected components), each united on its own. A cluster of one convex
// polygon needs no union at all: its shoelace area is exact on the grid. Under the year's suns
// most of a city's casts are such singletons or small clusters, and Clipper's sweep, whose
// active edge list spans the whole receiver, was a third of the fast path's time.
//
// Areas are exact integer sums (twice the area, in __int128), so the order of the clusters does
// not matter. A singleton's area is bit for bit what a union of it alone would give. A cluster
// of several polygons goes through one Clipper union like the whole set did: its intersection
// points are rounded once (the same level of rounding as the one-pass union, so the same bound;
// docs/numeric-contract.md, "The fast path").
#pragma once

#include <polyclipping/clipper.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <vector>

namespace shadow::fast {

__extension__ typedef __int128 ClusterInt128;

/// Twice the signed area of a grid polygon, exactly.
inline ClusterInt128 twice_area(const ClipperLib::Path& path) {
  ClusterInt128 sum = 0;
  const std::size_t n = path.size();
  for (std::size_t a = 0; a < n; ++a) {
    const ClipperLib::IntPoint& p = path[a];
    const ClipperLib::IntPoint& q = path[(a + 1) % n];
    sum += static_cast<ClusterInt128>(p.X) * q.Y - static_cast<ClusterInt128>(q.X) * p.Y;
  }
  return sum;
}

/// Whether a grid polygon is convex and counter-clockwise with positive area, so that its
/// non-zero-fill region is its shoelace area. Every turn is to the left (or straight on, going
/// the same way), and the x direction changes sign at most twice around it: each full turn of
/// the edge direction changes it twice, so the boundary winds once (a pentagram turns left
/// everywhere but winds twice).
inline bool is_convex_ccw(const ClipperLib::Path& path) {
  const std::size_t n = path.size();
  if (n < 3) return false;
  int changes = 0, last_sign = 0, first_sign = 0;
  for (std::size_t a = 0; a < n; ++a) {
    const ClipperLib::IntPoint& p = path[a];
    const ClipperLib::IntPoint& q = path[(a + 1) % n];
    const ClipperLib::IntPoint& r = path[(a + 2) % n];
    const ClusterInt128 ux = q.X - p.X, uy = q.Y - p.Y, vx = r.X - q.X, vy = r.Y - q.Y;
    const ClusterInt128 cross = ux * vy - uy * vx;
    if (cross < 0) return false;
    if (cross == 0 && ux * vx + uy * vy <= 0) return false;  // a spike back, or a repeated point
    const int sign = ux > 0 ? 1 : ux < 0 ? -1 : 0;
    if (sign != 0) {
      if (first_sign == 0) first_sign = sign;
      if (last_sign != 0 && sign != last_sign) ++changes;
      last_sign = sign;
    }
  }
  if (last_sign != 0 && first_sign != 0 && last_sign != first_sign) ++changes;  // around the end
  return changes <= 2 && twice_area(path) > 0;
}

/// Counts of what the clustered union did (for the benchmarks' per-instant summary).
struct ClusterUnionCounts {
  std::size_t singletons = 0;  ///< convex polygons measured without a union
  std::size_t unions = 0;      ///< Clipper unions run (one per cluster of several polygons)
};

/// Twice the area of the union (non-zero fill) of `polygons`, each closed and counter-clockwise
/// (as the fast path's casts are), computed cluster by cluster. Polygons in one cluster are
/// those whose bounding boxes overlap with positive area, transitively.
inline ClusterInt128 clustered_union_area2(const ClipperLib::Paths& polygons, ClusterUnionCounts* counts = nullptr) {
  namespace CL = ClipperLib;
  const std::size_t n = polygons.size();
  struct Box {
    CL::cInt x0, y0, x1, y1;
  };
  std::vector<Box> box(n);
  for (std::size_t p = 0; p < n; ++p) {
    Box b{polygons[p].empty() ? 0 : polygons[p][0].X, polygons[p].empty() ? 0 : polygons[p][0].Y,
          polygons[p].empty() ? 0 : polygons[p][0].X, polygons[p].empty() ? 0 : polygons[p][0].Y};
    for (const CL::IntPoint& q : polygons[p]) {
      b.x0 = std::min(b.x0, q.X);
      b.y0 = std::min(b.y0, q.Y);
      b.x1 = std::max(b.x1, q.X);
      b.y1 = std::max(b.y1, q.Y);
    }
    box[p] = b;
  }
  // Union-find over a sweep in x: each box against the boxes still open at its left edge.
  std::vector<std::size_t> parent(n);
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  auto find = [&](std::size_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return box[a].x0 != box[b].x0 ? box[a].x0 < box[b].x0 : a < b;
  });
  std::vector<std::size_t> open;
  for (std::size_t p : order) {
    const Box& b = box[p];
    std::size_t kept = 0;
    for (std::size_t o : open) {
      const Box& c = box[o];
      if (c.x1 <= b.x0) continue;  // closed before this one starts (touching adds no area)
      open[kept++] = o;
      if (c.y1 > b.y0 && b.y1 > c.y0) parent[find(p)] = find(o);
    }
    open.resize(kept);
    open.push_back(p);
  }
  // Members of each cluster, in input order (the one-pass union's order).
  std::vector<std::size_t> first(n, n), next(n, n), last(n, n);
  for (std::size_t p = 0; p < n; ++p) {
    const std::size_t r = find(p);
    if (first[r] == n) first[r] = p;
    else next[last[r]] = p;
    last[r] = p;
  }
  ClusterInt128 total = 0;
  CL::Paths cluster, united;
  for (std::size_t r = 0; r < n; ++r) {
    if (first[r] == n) continue;
    if (next[first[r]] == n && is_convex_ccw(polygons[first[r]])) {
      total += twice_area(polygons[first[r]]);
      if (counts) ++counts->singletons;
      continue;
    }
    cluster.clear();
    for (std::size_t p = first[r]; p != n; p = next[p]) cluster.push_back(polygons[p]);
    CL::Clipper clipper;
    clipper.StrictlySimple(false);
    clipper.AddPaths(cluster, CL::ptSubject, true);
    united.clear();
    clipper.Execute(CL::ctUnion, united, CL::pftNonZero, CL::pftNonZero);
    for (const CL::Path& p : united) total += twice_area(p);  // holes come out negative
    if (counts) ++counts->unions;
  }
  return total;
}

}  // namespace shadow::fast
