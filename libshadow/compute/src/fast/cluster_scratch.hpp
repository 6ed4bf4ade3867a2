// SPDX-License-Identifier: GPL-3.0-or-later
// The clustered union's scratch (fast/cluster_union.hpp) and the window clip's
// (fast/window_clip.hpp), kept by each fast-path worker so that a receiver's union allocates
// nothing. No Clipper types: the engine includes this through
// fast_receiver.hpp.
#pragma once

#include "geometry/box_sweep.hpp"
#include "geometry/shared_edge_merge.hpp"

#include <cstddef>
#include <utility>
#include <vector>

namespace shadow::fast {

__extension__ typedef __int128 WindowInt128;

/// The line a x + b y + c = 0 through two grid points, positive on the left of p -> q
/// (fast/window_clip.hpp's bounds: |a|, |b| < 2^31, |c| < 2^62).
struct GridLine {
  WindowInt128 a = 0, b = 0, c = 0;
};

/// A point of the exact clip: (X / W, Y / W), W > 0; W = 1 for grid points.
struct WindowPoint {
  WindowInt128 x = 0, y = 0, w = 1;
};

/// Vectors reused from one clip to the next (a fast-path worker's).
struct WindowClipScratch {
  std::vector<WindowPoint> points, next_points;
  std::vector<GridLine> lines, next_lines;  ///< lines[k]: the edge from points[k] to points[k + 1]
  std::vector<GridLine> window;             ///< the window's edges' lines
  std::vector<int> side;
};

/// A grid polygon's bounding box (in ClipperLib::cInt, which is `long long`).
struct GridBox {
  long long x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

/// Vectors reused from one union to the next (their contents mean nothing between calls).
struct ClusterScratch {
  // clustered_union_area: the polygons' boxes, the union-find, the clusters' member lists.
  std::vector<GridBox> boxes;
  std::vector<std::size_t> parent, first, next, last, members;
  std::vector<std::pair<double, double>> across_all;  ///< every polygon's extent across the shadows
  std::vector<geometry::AcrossSweepEntry<GridBox>> sweep;  ///< sweep_across's order (both sweeps)
  std::vector<char> convex, inside;
  // boundary_union_area2: one cluster's boxes, extents across the shadows, neighbours, the
  // covered intervals of an edge.
  std::vector<GridBox> box;
  std::vector<std::pair<double, double>> across, covered;
  std::vector<std::vector<std::size_t>> near;
  // merge_shared_edges: a cluster's points and slots and the merge's own scratch; the merged
  // polygons' boxes.
  std::vector<long long> merge_x, merge_y;
  std::vector<std::size_t> merge_next, merge_first;
  geometry::SharedEdgeMerge merge;
  std::vector<GridBox> merged_boxes;
  std::vector<std::pair<double, double>> merged_across;
};

}  // namespace shadow::fast
