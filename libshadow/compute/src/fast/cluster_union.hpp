// SPDX-License-Identifier: GPL-3.0-or-later
// The area of a union of grid polygons, cluster by cluster.
//
// A receiver's casts fall into groups that do not touch: the shadows of the boxes around one
// street corner never meet those of the next block. Polygons whose bounding boxes do not overlap,
// or whose extents across the shadows' direction are apart (interiors disjoint either way), add
// their areas, so the union's area is the sum over clusters of polygons that meet in both
// (connected components), each united on its own. A cluster of one convex
// polygon needs no union at all: its shoelace area is exact on the grid. Under the year's suns
// most of a city's casts are such singletons or small clusters, and Clipper's sweep, whose
// active edge list spans the whole receiver, was a third of the fast path's time.
//
// A cluster of several convex polygons is measured by its boundary (boundary_union_area2): the
// parts of each edge that no other polygon covers, integrated, with exact integer decisions and
// the interval ends in doubles. Its area is then that of the exact union of the grid polygons up
// to a few ulps (a stated bound), where Clipper's union rounded every intersection point to the
// grid. Only a cluster holding a polygon that is not convex still goes through Clipper. The
// integer parts are exact sums (twice the area, in __int128): their order does not matter.
#pragma once

#include "fast/cluster_scratch.hpp"
#include "geometry/box_sweep.hpp"
#include "geometry/cyclic_index.hpp"
#include "geometry/shared_edge_merge.hpp"
#include "geometry/winds_once.hpp"

#include <polyclipping/clipper.hpp>

#include <algorithm>
#include <cstddef>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <numeric>
#include <optional>
#include <type_traits>
#include <vector>

namespace shadow::fast {

__extension__ typedef __int128 ClusterInt128;
static_assert(std::is_same_v<ClipperLib::cInt, long long>, "GridBox (fast/cluster_scratch.hpp) holds cInt");

/// Twice the signed area of a grid polygon, exactly.
inline ClusterInt128 twice_area(const ClipperLib::Path& path) {
  ClusterInt128 sum = 0;
  const std::size_t n = path.size();
  for (std::size_t a = 0; a < n; ++a) {
    const ClipperLib::IntPoint& p = path[a];
    const ClipperLib::IntPoint& q = path[geometry::cyclic_next(a, n)];
    sum += static_cast<ClusterInt128>(p.X) * q.Y - static_cast<ClusterInt128>(q.X) * p.Y;
  }
  return sum;
}

/// Whether the turn from direction (ux, uy) to (vx, vy) is to the left or straight on (not back,
/// and neither is zero): exact for grid coordinates (|coordinates| < 2^31, products in 128 bits).
inline bool left_or_straight(ClusterInt128 ux, ClusterInt128 uy, ClusterInt128 vx, ClusterInt128 vy) {
  const ClusterInt128 cross = ux * vy - uy * vx;
  return cross > 0 || (cross == 0 && ux * vx + uy * vy > 0);
}

/// Whether a grid polygon is convex and counter-clockwise with positive area, so that its
/// non-zero-fill region is its shoelace area. Every turn is to the left (or straight on, going
/// the same way), and the boundary winds once (geometry::XSignChanges: a pentagram turns left
/// everywhere but winds twice).
inline bool is_convex_ccw(const ClipperLib::Path& path) {
  const std::size_t n = path.size();
  if (n < 3) return false;
  geometry::XSignChanges winding;
  for (std::size_t a = 0; a < n; ++a) {
    const ClipperLib::IntPoint& p = path[a];
    const ClipperLib::IntPoint& q = path[geometry::cyclic_next(a, n)];
    const ClipperLib::IntPoint& r = path[geometry::cyclic_next(geometry::cyclic_next(a, n), n)];
    const ClusterInt128 ux = q.X - p.X, uy = q.Y - p.Y, vx = r.X - q.X, vy = r.Y - q.Y;
    if (!left_or_straight(ux, uy, vx, vy)) return false;  // a right turn, a spike back, or a repeated point
    winding.add(geometry::sign_of_difference(p.X, q.X));
  }
  return winding.winds_once() && twice_area(path) > 0;
}

inline GridBox grid_box(const ClipperLib::Path& path) {
  if (path.empty()) return {};
  GridBox b{path[0].X, path[0].Y, path[0].X, path[0].Y};
  for (const ClipperLib::IntPoint& q : path) {
    b.x0 = std::min(b.x0, q.X);
    b.y0 = std::min(b.y0, q.Y);
    b.x1 = std::max(b.x1, q.X);
    b.y1 = std::max(b.y1, q.Y);
  }
  return b;
}

/// The unit normal (nx, ny) to the shadows' direction (ax, ay) in grid units: a low sun's casts
/// are long along (ax, ay) and narrow across it. Where the direction is zero or not finite
/// (a sun straight above the receiver), the normal to (0, 1).
struct AcrossAxis {
  double nx = -1, ny = 0;
};

inline AcrossAxis across_axis(double ax, double ay) {
  double length = std::hypot(ax, ay);
  if (!(length > 0) || !std::isfinite(length)) {
    ax = 0;
    ay = 1;
    length = 1;
  }
  return {-ay / length, ax / length};
}

/// How far a polygon's extent across is widened on either side: far beyond the rounding of
/// nx X + ny Y for grid coordinates (|coordinates| <= 2^31, a unit normal: under 1e-6), so that
/// two polygons whose widened extents are apart are disjoint (a separating axis).
inline constexpr double kAcrossMargin = 1e-3;

/// A polygon's extent along the axis, widened by kAcrossMargin on both sides.
inline std::pair<double, double> across_extent(const ClipperLib::Path& path, const AcrossAxis& axis) {
  double lo = std::numeric_limits<double>::max(), hi = std::numeric_limits<double>::lowest();
  for (const ClipperLib::IntPoint& q : path) {
    const double t = axis.nx * static_cast<double>(q.X) + axis.ny * static_cast<double>(q.Y);
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  return {lo - kAcrossMargin, hi + kAcrossMargin};
}

/// Whether two widened extents are apart (the polygons are then disjoint).
inline bool apart(const std::pair<double, double>& u, const std::pair<double, double>& v) {
  return u.second < v.first || v.second < u.first;
}

/// The measure of a union of intervals (sorted here; at least one), in doubles: the runs of
/// overlapping ones, each its end minus its start, summed in order.
inline double union_measure(std::vector<std::pair<double, double>>& intervals) {
  std::sort(intervals.begin(), intervals.end());
  double measure = 0, run_lo = intervals[0].first, run_hi = intervals[0].second;
  for (std::size_t c = 1; c < intervals.size(); ++c) {
    if (intervals[c].first > run_hi) {
      measure += run_hi - run_lo;
      run_lo = intervals[c].first;
    }
    run_hi = std::max(run_hi, intervals[c].second);
  }
  return measure + (run_hi - run_lo);
}

/// The area of one cluster of convex counter-clockwise polygons from its boundary, without a
/// union: area(P_1 u ... u P_n) = 1/2 sum over the edges e = (s, s + d) of every P_i of
/// cross(s, d) L_e, where L_e is the measure of the parameters t in [0, 1] at which s + t d is
/// not covered (an uncovered piece [t0, t1] of the edge contributes cross(s + t0 d, s + t1 d) / 2
/// = (t1 - t0) cross(s, d) / 2). A point of e is covered by P_j (j != i) when it lies in P_j's
/// interior, or on an edge of P_j collinear with e pointing the same way and j < i: a boundary
/// shared by polygons on the same side counts once, and one with polygons on both sides counts
/// once each way, which cancels (the union is on both sides there). All decisions are exact in
/// integers; only the interval ends t = -a/b and the sums are in doubles, and `error` bounds what
/// that costs (docs/numeric-contract.md, "The fast path").
struct BoundaryArea {
  double twice_area = 0;  ///< twice the union's area, grid units squared
  double error = 0;       ///< bound on |twice_area - the exact value|
};

///
/// Coordinates within 2^30 of 0 (the fast path's grid), so that 64-bit integers hold every
/// product exactly. `axis` (across_axis of any direction: the shadows' in grid units) only speeds
/// up the search for overlapping pairs: long thin shadows have wide boxes but narrow extents
/// across their direction.
/// `boxes`, `extents`: the bounding box (grid_box) and the extent across `axis` (across_extent) of
/// every polygon, made once by the caller for all its clusters.
/// `scratch`: vectors reused from call to call (the caller's worker keeps them: most receivers'
/// clusters are small and many, and allocating for each, or finding a thread-local scratch
/// through the dynamic linker's TLS look-up, was a visible share of the measure).
inline BoundaryArea boundary_union_area2(const ClipperLib::Paths& polygons, const std::vector<GridBox>& boxes,
                                         const std::vector<std::pair<double, double>>& extents,
                                         const std::vector<std::size_t>& members, const AcrossAxis& axis,
                                         ClusterScratch& scratch) {
  namespace CL = ClipperLib;
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  const std::size_t m = members.size();
  std::vector<GridBox>& box = scratch.box;
  box.resize(m);
  GridBox all{};
  // Extents across the shadows (across_extent): two polygons whose extents are apart are disjoint.
  const double nx = axis.nx, ny = axis.ny, margin = kAcrossMargin;
  std::vector<std::pair<double, double>>& across = scratch.across;
  across.resize(m);
  for (std::size_t a = 0; a < m; ++a) {
    const GridBox& b = box[a] = boxes[members[a]];
    across[a] = extents[members[a]];
    all = a == 0 ? b : GridBox{std::min(all.x0, b.x0), std::min(all.y0, b.y0), std::max(all.x1, b.x1), std::max(all.y1, b.y1)};
  }
  // Neighbours: polygons whose boxes meet (closed: a shared edge on the box's side matters) and
  // whose extents across are not apart, found by a sweep across the shadows
  // (geometry::sweep_across). The lists' order does not matter below: each edge's covered
  // intervals are sorted by value before they are measured, and an edge found inside one
  // polygon adds nothing whichever polygon that is.
  std::vector<std::vector<std::size_t>>& near = scratch.near;
  if (near.size() < m) near.resize(m);
  for (std::size_t a = 0; a < m; ++a) near[a].clear();
  geometry::sweep_across<true>(box, across, scratch.sweep, [&](std::size_t p, std::size_t o) {
    near[p].push_back(o);
    near[o].push_back(p);
  });
  // Local coordinates about the cluster's centre keep cross(s, d) small (the area is the same:
  // the uncovered pieces close up into the union's boundary).
  const CL::cInt cx = all.x0 / 2 + all.x1 / 2, cy = all.y0 / 2 + all.y1 / 2;
  BoundaryArea out;
  double sum_abs = 0;
  std::size_t terms = 0;
  std::vector<std::pair<double, double>>& covered = scratch.covered;
  for (std::size_t a = 0; a < m; ++a) {
    const CL::Path& P = polygons[members[a]];
    const std::size_t i = members[a];
    for (std::size_t k = 0; k < P.size(); ++k) {
      const CL::IntPoint& s = P[k];
      const CL::IntPoint& e = P[geometry::cyclic_next(k, P.size())];
      // Grid coordinates are within 2^30 of 0: differences below 2^31, products below 2^62, and
      // the difference of two products below 2^63, so 64-bit integers hold every value exactly.
      const std::int64_t dx = e.X - s.X, dy = e.Y - s.Y;
      const std::int64_t sx = s.X - cx, sy = s.Y - cy;
      const std::int64_t cross_sd = sx * dy - sy * dx;
      const CL::cInt ex0 = std::min(s.X, e.X), ex1 = std::max(s.X, e.X), ey0 = std::min(s.Y, e.Y),
                     ey1 = std::max(s.Y, e.Y);
      const double ts = nx * static_cast<double>(s.X) + ny * static_cast<double>(s.Y);
      const double te = nx * static_cast<double>(e.X) + ny * static_cast<double>(e.Y);
      const std::pair<double, double> edge_across{std::min(ts, te) - margin, std::max(ts, te) + margin};
      covered.clear();
      std::size_t reached = 0;  // intervals with a computed end, kept or not (rounding may drop one)
      bool inside = false;      // the whole edge lies in one polygon, decided in integers alone
      for (std::size_t b : near[a]) {
        const GridBox& q = box[b];
        if (q.x1 < ex0 || ex1 < q.x0 || q.y1 < ey0 || ey1 < q.y0 || apart(edge_across, across[b])) continue;
        const CL::Path& Q = polygons[members[b]];
        const std::size_t j = members[b];
        double lo = 0, hi = 1;
        bool empty = false, computed = false, divided = false;
        for (std::size_t f = 0; f < Q.size() && !empty; ++f) {
          const CL::IntPoint& q0 = Q[f];
          const CL::IntPoint& q1 = Q[geometry::cyclic_next(f, Q.size())];
          const std::int64_t gx = q1.X - q0.X, gy = q1.Y - q0.Y;
          // h(p) = cross(g, p - q0): positive inside (counter-clockwise); h(s + t d) = A + t B.
          const std::int64_t A = gx * (s.Y - q0.Y) - gy * (s.X - q0.X);
          const std::int64_t B = gx * dy - gy * dx;
          if (B == 0) {
            if (A > 0) continue;
            if (A < 0 || !(gx * dx + gy * dy > 0 && j < i)) empty = true;
            continue;  // collinear, same way, lower index: this side's boundary, counted there
          }
          computed = true;
          // Both ends of the edge inside h >= 0 (A >= 0 and A + B >= 0): t = -A / B is at most 0
          // (B > 0) or at least 1 (B < 0), and lo >= 0, hi <= 1 already, so it changes neither
          // (rounding is monotonic, and 0 and 1 are doubles). Most of a cluster's edge pairs are
          // such; their division was the measure's most expensive instruction. (A + B is taken
          // only where B < 0 <= A: opposite signs, no overflow.)
          if (A >= 0 && (B > 0 || A + B >= 0)) continue;
          divided = true;
          const double t = -static_cast<double>(A) / static_cast<double>(B);
          if (B > 0) lo = std::max(lo, t);
          else hi = std::min(hi, t);
          if (!(lo < hi)) empty = true;
        }
        if (!empty && !divided) {
          // Every test was an integer one and none cut the edge: it lies in this polygon (where
          // it runs along the polygon's boundary, the same way, the polygon comes first: the
          // rule for shared lines above), so its uncovered measure is exactly 0, whatever the
          // other polygons do. Most edges of a crowded cluster (a ground under long shadows) are
          // such, and their other intervals and sort were most of the measure.
          inside = true;
          break;
        }
        reached += computed ? 1 : 0;
        if (!empty) covered.emplace_back(lo, hi);
      }
      if (inside) continue;  // no term and no rounding: nothing to add, to the area or the bound
      const double uncovered = covered.empty() ? 1.0 : std::max(0.0, 1 - union_measure(covered));
      const double c = static_cast<double>(cross_sd);
      // Each interval end is within 4 eps of its exact value (two conversions and a division,
      // |t| <= 1 where it counts), so each interval's measure within 8 eps, plus the roundings
      // of the measure's sums (under 2 eps an interval) and of the product and c's conversion.
      // Charged for every interval that got a computed end, also one that rounding emptied, and
      // also when the edge came out wholly covered (a real gap of a few ulps may have closed),
      // except on an edge found inside one polygon by the integer tests alone (skipped above).
      out.error += std::abs(c) * (12 * kEps * static_cast<double>(reached) + 4 * kEps);
      if (uncovered == 0) continue;
      const double term = c * uncovered;
      out.twice_area += term;
      sum_abs += std::abs(term);
      ++terms;
    }
  }
  // Recursive summation: |error| <= (terms - 1) eps sum |term|.
  out.error += static_cast<double>(terms) * kEps * sum_abs;
  out.error *= 1 + 1e-9;
  return out;
}

/// Whether `inner` lies in the convex counter-clockwise polygon `outer` (is_convex_ccw), its
/// boundary included: every vertex of `inner` on the inner side of every edge of `outer`, decided
/// in integers (the boundary measure's bounds: 64 bits hold every product). Boxes first: an
/// inner box not inside the outer one settles most pairs.
inline bool contains_polygon(const ClipperLib::Path& outer, const GridBox& outer_box, const ClipperLib::Path& inner,
                             const GridBox& inner_box) {
  if (inner_box.x0 < outer_box.x0 || inner_box.x1 > outer_box.x1 || inner_box.y0 < outer_box.y0 ||
      inner_box.y1 > outer_box.y1)
    return false;
  const std::size_t n = outer.size();
  for (std::size_t f = 0; f < n; ++f) {
    const ClipperLib::IntPoint& q0 = outer[f];
    const ClipperLib::IntPoint& q1 = outer[geometry::cyclic_next(f, n)];
    const std::int64_t gx = q1.X - q0.X, gy = q1.Y - q0.Y;
    for (const ClipperLib::IntPoint& v : inner)
      if (gx * (v.Y - q0.Y) - gy * (v.X - q0.X) < 0) return false;
  }
  return true;
}

/// Counts of what the clustered union did (for the tests and the benchmarks).
struct ClusterUnionCounts {
  std::size_t singletons = 0;  ///< convex polygons measured without a union
  std::size_t boundaries = 0;  ///< clusters of convex polygons measured by their boundary
  std::size_t unions = 0;      ///< Clipper unions run (a cluster with a polygon that is not convex)
  std::size_t merged = 0;      ///< clusters whose polygons merge_shared_edges united (some of them)
  std::size_t inside = 0;      ///< polygons left out, inside another (contains_polygon)
};

/// From this many convex polygons on, a cluster's polygons that share an edge run both ways are
/// first merged where convex (merge_shared_edges).
inline constexpr std::size_t kMergeClusterFrom = 16;

/// The convex polygons `members` of `polygons` with those that share an edge run both ways
/// united where the result is convex (geometry/shared_edge_merge.hpp: the casts of neighbouring
/// faces of one mesh on either side of their edge), into `out`; false (out unchanged) when none
/// merged. The same point set, so the same exact union: only fewer edges to measure.
inline bool merge_shared_edges(const ClipperLib::Paths& polygons, const std::vector<std::size_t>& members,
                               ClusterScratch& s, ClipperLib::Paths& out) {
  std::vector<long long>&xs = s.merge_x, &ys = s.merge_y;
  xs.clear();
  ys.clear();
  s.merge_first.assign(1, 0);
  s.merge_next.clear();
  for (std::size_t m : members) {
    const std::size_t begin = xs.size();
    for (const ClipperLib::IntPoint& p : polygons[m]) {
      xs.push_back(p.X);
      ys.push_back(p.Y);
    }
    for (std::size_t k = begin; k < xs.size(); ++k) s.merge_next.push_back(k + 1 == xs.size() ? begin : k + 1);
    s.merge_first.push_back(xs.size());
  }
  const std::size_t merges = s.merge.run(
      s.merge_next, s.merge_first,
      [&](std::size_t v) {
        return geometry::SharedEdgeMerge::point_hash(static_cast<double>(xs[v]), static_cast<double>(ys[v]));
      },
      [&](std::size_t a, std::size_t b) { return xs[a] == xs[b] && ys[a] == ys[b]; },
      [&](std::size_t p, std::size_t q, std::size_t r) {
        return left_or_straight(xs[q] - xs[p], ys[q] - ys[p], xs[r] - xs[q], ys[r] - ys[q]);
      });
  if (merges == 0) return false;
  const std::size_t count = s.merge_first.size() - 1;
  out.resize(count);
  const std::vector<std::size_t>& order = s.merge.order();
  for (std::size_t i = 0; i < count; ++i) {
    out[i].clear();
    for (std::size_t k = s.merge_first[i]; k < s.merge_first[i + 1]; ++k) out[i].push_back({xs[order[k]], ys[order[k]]});
  }
  return true;
}

/// The area of a union of grid polygons, cluster by cluster.
struct ClusteredArea {
  ClusterInt128 exact2 = 0;   ///< twice the area of the singletons and the Clipper clusters, exactly
  BoundaryArea boundary;      ///< the clusters measured by their boundary, in doubles
  bool clipper = false;       ///< some cluster went through a Clipper union (rounded points)
};

/// The area of the union (non-zero fill) of `polygons`, each closed and counter-clockwise (as the
/// fast path's casts are), computed cluster by cluster: polygons in one cluster are those whose
/// bounding boxes overlap with positive area and whose extents across (ax, ay) are not apart
/// (geometry::sweep_across), transitively. (ax, ay): the shadows' direction, any non-zero one
/// giving the same area; along it a low sun's casts are long. A convex singleton is its shoelace
/// area; a cluster of convex polygons is measured by its boundary (boundary_union_area2); any
/// other cluster goes through one Clipper union.
/// `scratch`: the caller's reusable vectors (a fast-path worker's), or none (allocated here).
/// `merge_shared`: merge a large cluster's casts along shared edges first (false when the
/// caller expects none to: convex solids' hulls rarely share an edge, single faces' casts do).
inline ClusteredArea clustered_union_area(const ClipperLib::Paths& polygons, double ax = 0, double ay = 1,
                                          ClusterUnionCounts* counts = nullptr, ClusterScratch* scratch = nullptr,
                                          bool merge_shared = true) {
  namespace CL = ClipperLib;
  std::optional<ClusterScratch> local;  // only when the caller keeps none
  ClusterScratch& s = scratch ? *scratch : local.emplace();
  const std::size_t n = polygons.size();
  std::vector<GridBox>& box = s.boxes;
  box.resize(n);
  for (std::size_t p = 0; p < n; ++p) box[p] = grid_box(polygons[p]);
  // Union-find over the pairs whose boxes overlap with positive area (touching adds no area) and
  // whose extents across are not apart.
  std::vector<std::size_t>& parent = s.parent;
  parent.resize(n);
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  auto find = [&](std::size_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  // Pairs found by a sweep across the shadows (geometry::sweep_across): a low sun's casts on a
  // ground are long and narrow, and a pair apart across them is disjoint, so it joins no cluster.
  const AcrossAxis axis = across_axis(ax, ay);
  std::vector<std::pair<double, double>>& across = s.across_all;
  across.resize(n);
  for (std::size_t p = 0; p < n; ++p) across[p] = across_extent(polygons[p], axis);
  std::vector<char>& convex = s.convex;
  convex.resize(n);
  for (std::size_t p = 0; p < n; ++p) convex[p] = is_convex_ccw(polygons[p]) ? 1 : 0;
  // A polygon inside a convex one adds nothing to the union: it is left out (half the polygons
  // of the year's clusters are, the casts of low solids inside a tall one's on a wall), and
  // with it the pairs it made, and a cluster left with one convex polygon is its shoelace area.
  // Every pair that such a polygon (of positive area, as every cast is) makes with its container
  // overlaps with positive area, and their extents across meet, so the sweep below meets it (one
  // of zero area may stay, which is harmless). Of polygons equal as sets, the first stays.
  std::vector<char>& inside = s.inside;
  inside.assign(n, 0);
  std::size_t left_out = 0;
  // A pair with a polygon already left out is passed over whole (the sweep is told so): its
  // container holds the polygon, so the container meets the other one too and joins its cluster
  // (or it lies in one that stays and does), or is apart from it across (to within the extents'
  // rounding, far below their margin) and so disjoint from it; and a polygon inside the one left
  // out lies in the container too.
  geometry::sweep_across<false>(box, across, s.sweep, [&](std::size_t p, std::size_t o) {
    parent[find(p)] = find(o);
    const GridBox &bp = box[p], &bo = box[o];
    const bool p_in_o = convex[o] && contains_polygon(polygons[o], bo, polygons[p], bp);
    const bool o_in_p = convex[p] && contains_polygon(polygons[p], bp, polygons[o], bo);
    if (p_in_o || o_in_p) {
      inside[p_in_o && o_in_p ? std::max(p, o) : p_in_o ? p : o] = 1;
      ++left_out;
    }
  }, [&](std::size_t p) { return inside[p] != 0; });
  if (counts) counts->inside += left_out;
  // Members of each cluster, in input order.
  std::vector<std::size_t>&first = s.first, &next = s.next, &last = s.last;
  first.assign(n, n);
  next.assign(n, n);
  last.assign(n, n);
  for (std::size_t p = 0; p < n; ++p) {
    const std::size_t r = find(p);
    if (first[r] == n) first[r] = p;
    else next[last[r]] = p;
    last[r] = p;
  }
  ClusteredArea out;
  std::vector<std::size_t>& members = s.members;
  CL::Paths cluster, united, merged;
  // Clusters in the order of their first member (not of their root, which depends on the
  // order the sweep found the pairs in): the boundary areas' double sum in a fixed order.
  for (std::size_t q = 0; q < n; ++q) {
    const std::size_t r = find(q);
    if (first[r] != q) continue;
    members.clear();
    bool all_convex = true;
    for (std::size_t p = first[r]; p != n; p = next[p]) {
      if (inside[p]) continue;
      members.push_back(p);
      all_convex &= convex[p] != 0;
    }
    if (members.size() == 1 && all_convex) {
      out.exact2 += twice_area(polygons[members[0]]);
      if (counts) ++counts->singletons;
      continue;
    }
    if (all_convex) {
      const CL::Paths* measured = &polygons;
      const std::vector<GridBox>* boxes = &box;
      const std::vector<std::pair<double, double>>* extents = &across;
      if (merge_shared && members.size() >= kMergeClusterFrom &&
          fast::merge_shared_edges(polygons, members, s, merged)) {
        if (counts) ++counts->merged;
        if (merged.size() == 1) {  // one convex polygon: its shoelace area, exactly
          out.exact2 += twice_area(merged[0]);
          continue;
        }
        measured = &merged;
        s.merged_boxes.resize(merged.size());
        s.merged_across.resize(merged.size());
        for (std::size_t p = 0; p < merged.size(); ++p) {
          s.merged_boxes[p] = grid_box(merged[p]);
          s.merged_across[p] = across_extent(merged[p], axis);
        }
        boxes = &s.merged_boxes;
        extents = &s.merged_across;
        members.resize(merged.size());
        std::iota(members.begin(), members.end(), std::size_t{0});
      }
      const BoundaryArea b = boundary_union_area2(*measured, *boxes, *extents, members, axis, s);
      out.boundary.twice_area += b.twice_area;
      out.boundary.error += b.error + 2 * std::numeric_limits<double>::epsilon() * std::abs(out.boundary.twice_area);
      if (counts) ++counts->boundaries;
      continue;
    }
    cluster.clear();
    for (std::size_t p : members) cluster.push_back(polygons[p]);
    CL::Clipper clipper;
    clipper.StrictlySimple(false);
    clipper.AddPaths(cluster, CL::ptSubject, true);
    united.clear();
    clipper.Execute(CL::ctUnion, united, CL::pftNonZero, CL::pftNonZero);
    for (const CL::Path& p : united) out.exact2 += twice_area(p);  // holes come out negative
    out.clipper = true;
    if (counts) ++counts->unions;
  }
  return out;
}

}  // namespace shadow::fast
