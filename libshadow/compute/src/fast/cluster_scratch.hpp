// SPDX-License-Identifier: GPL-3.0-or-later
// The clustered union's scratch (fast/cluster_union.hpp), kept by each fast-path worker so that
// a receiver's union allocates nothing. No Clipper types: the engine includes this through
// fast_receiver.hpp.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

namespace shadow::fast {

/// A grid polygon's bounding box (in ClipperLib::cInt, which is `long long`).
struct GridBox {
  long long x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

/// Vectors reused from one union to the next (their contents mean nothing between calls).
struct ClusterScratch {
  // clustered_union_area: the polygons' boxes, the union-find, the clusters' member lists.
  std::vector<GridBox> boxes;
  std::vector<std::size_t> parent, first, next, last, members, order, open;
  std::vector<char> convex;
  // boundary_union_area2: one cluster's boxes, extents across the shadows, neighbours, the
  // covered intervals of an edge.
  std::vector<GridBox> box;
  std::vector<std::pair<double, double>> across, covered;
  std::vector<std::vector<std::size_t>> near;
  std::vector<std::size_t> near_order, near_open;
};

}  // namespace shadow::fast
