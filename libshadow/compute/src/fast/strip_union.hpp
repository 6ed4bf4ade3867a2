// SPDX-License-Identifier: GPL-3.0-or-later
// The union of many cast polygons on the fast path's integer grid, in strips.
//
// Under a low sun a ground receives thousands of long, thin shadows that overlap their
// neighbours along the sun's direction. Clipper unites by a sweep over y whose active edge list
// holds every edge that crosses the current scanline: with n long shadows that is O(n) edges
// on most scanlines, and the union of the 10,000-box city's ground at a 5 degree sun cost more
// than the exact engine's. Sorted by their position across the sun's direction and cut into
// groups of neighbours, each group is a narrow band along the shadows: a scanline crosses few
// of its edges. The groups' unions are then merged pairwise, neighbours with neighbours, and
// each merge sees mostly the outlines of what is already united.
//
// Every union rounds the intersection points it creates to the grid: the result's boundary is
// within `levels` times one union's rounding of the exact union's (the caller widens the bound
// with the level count this returns; docs/numeric-contract.md, "The fast path").
#pragma once

#include <polyclipping/clipper.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numeric>
#include <utility>
#include <vector>

namespace shadow::fast {

/// How the union of many polygons is split (ShadowOptions has no knob for it: fixed here, chosen
/// so that the golden scenes, whose receivers have fewer polygons, keep their one-pass union).
struct StripUnionOptions {
  /// At most this many polygons: one Clipper union of them all (bit for bit as before).
  std::size_t threshold = 8192;
  /// Polygons per group in the first pass.
  std::size_t group = 128;
  /// Groups' unions merged per union in each later pass (neighbours with neighbours); 0: all of
  /// them in one union. Each pass is one more level of rounding in the bound.
  std::size_t fan_in = 0;
};

/// The options the engine's fast receivers use (fast/fast_receiver.cpp): StripUnionOptions{}
/// unless a test changed them, and how many receivers (or tiles) went through the strips. An
/// internal knob for the tests (test_strip_union: a low threshold, so that a small city reaches
/// the strips inside the engine); change it only while no computation runs. Defined in
/// fast/fast_receiver.cpp.
struct EngineStripUnion {
  StripUnionOptions options;
  std::atomic<std::uint64_t> used{0};
};
EngineStripUnion& engine_strip_union();

/// Unites `polygons` (closed, non-zero fill) into `out` (Clipper's union: outer boundaries
/// counter-clockwise, holes clockwise, non-overlapping). (dx, dy), in grid units, points along
/// the shadows (the sun's direction in the chart; (0, 1) when there is none). Returns the number
/// of unions any output point went through: 1 for the one-pass union (polygons.size() <=
/// options.threshold), more for strips.
inline int strip_union(const ClipperLib::Paths& polygons, double dx, double dy, ClipperLib::Paths& out,
                       const StripUnionOptions& options = {}) {
  namespace CL = ClipperLib;
  auto unite = [](const CL::Paths& in, CL::Paths& result) {
    CL::Clipper clipper;
    clipper.StrictlySimple(false);
    clipper.AddPaths(in, CL::ptSubject, true);
    result.clear();
    clipper.Execute(CL::ctUnion, result, CL::pftNonZero, CL::pftNonZero);
  };
  if (polygons.size() <= options.threshold || options.group < 2) {
    unite(polygons, out);
    return 1;
  }
  // Position across the shadows: the centre of each polygon's extent along the normal of (dx, dy).
  double length = std::hypot(dx, dy);
  if (!(length > 0) || !std::isfinite(length)) {
    dx = 0;
    dy = 1;
    length = 1;
  }
  const double nx = -dy / length, ny = dx / length;
  std::vector<std::pair<double, std::size_t>> order;
  order.reserve(polygons.size());
  for (std::size_t p = 0; p < polygons.size(); ++p) {
    double lo = std::numeric_limits<double>::max(), hi = std::numeric_limits<double>::lowest();
    for (const CL::IntPoint& q : polygons[p]) {
      const double t = nx * static_cast<double>(q.X) + ny * static_cast<double>(q.Y);
      lo = std::min(lo, t);
      hi = std::max(hi, t);
    }
    order.emplace_back(0.5 * (lo + hi), p);
  }
  std::sort(order.begin(), order.end());  // ties by index: the same order on every run
  std::vector<CL::Paths> strips;
  for (std::size_t first = 0; first < order.size(); first += options.group) {
    const std::size_t last = std::min(order.size(), first + options.group);
    CL::Paths group;
    group.reserve(last - first);
    for (std::size_t a = first; a < last; ++a) group.push_back(polygons[order[a].second]);
    strips.emplace_back();
    unite(group, strips.back());
  }
  int levels = 1;
  const std::size_t fan_in = options.fan_in >= 2 ? options.fan_in : strips.size();
  while (strips.size() > 1) {  // neighbours with neighbours
    std::vector<CL::Paths> merged;
    merged.reserve((strips.size() + fan_in - 1) / fan_in);
    for (std::size_t a = 0; a < strips.size(); a += fan_in) {
      const std::size_t b = std::min(strips.size(), a + fan_in);
      if (b == a + 1) {
        merged.push_back(std::move(strips[a]));
        continue;
      }
      CL::Paths some = std::move(strips[a]);
      for (std::size_t c = a + 1; c < b; ++c) some.insert(some.end(), strips[c].begin(), strips[c].end());
      merged.emplace_back();
      unite(some, merged.back());
    }
    strips.swap(merged);
    ++levels;
  }
  out = std::move(strips.front());
  return levels;
}

}  // namespace shadow::fast
