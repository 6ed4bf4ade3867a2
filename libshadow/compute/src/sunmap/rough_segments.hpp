// SPDX-License-Identifier: GPL-3.0-or-later
// An instant's boundary segments on a face in doubles, about a tenth of the memory of the exact
// curves: all that the threshold map alone needs before its rounds (the face's strips, its tiles,
// the order its instants are swept in, and each strip's pending boundaries), so that the exact
// curves need not be gathered over the whole period. A face whose exact boundaries are many has
// them computed again, a band of instants at a time, as its rounds take them
// (docs/sun-hours-map.md, step 7).
#pragma once

#include "sunmap/face_overlay.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace shadow::sunmap {

/// One boundary segment of an instant's lit region on a face: from (xa, ya), its
/// lexicographically smaller end, to (xb, yb), rounded to doubles; x between xlo and xhi for
/// sure (interval bounds, as the exact curves are bucketed into strips by); `left`: the lit
/// region lies on its left.
struct RoughSegment {
  double xa, ya, xb, yb;
  double xlo, xhi;
  std::uint32_t instant;
  bool left;
};

/// The rough form of a curve (tagged as face_overlay.hpp tags them: its instant and side).
RoughSegment rough_segment(const Curve& curve);
/// The same of an x-monotone curve by its first tag (one instant's, or the outline's).
RoughSegment rough_segment(const XCurve& curve);

/// The indices of `segments` that may enter each strip: those of the exact curves
/// (bucket_curves) and possibly more.
std::vector<std::vector<std::size_t>> bucket_rough(const std::vector<RoughSegment>& segments,
                                                   const std::vector<Strip>& strips);

/// choose_strips from rough segments.
std::vector<Strip> choose_strips(const std::vector<RoughSegment>& segments, std::size_t expected,
                                 const exact::Polygon2& chart, std::size_t strip_edges);

}  // namespace shadow::sunmap
