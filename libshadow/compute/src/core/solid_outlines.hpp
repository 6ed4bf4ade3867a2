// SPDX-License-Identifier: GPL-3.0-or-later
// The outlines of a scene's convex solids as seen from one directional light, found once per
// light instead of once per receiver.
//
// A solid wholly in front of a receiver casts the convex hull of its vertices projected along
// the light onto the receiver's plane. That projection is an affine map of the plane orthogonal
// to the light (both kill the light's direction), so the vertices at the hull's corners, and
// their cyclic order, are the same for every receiver: only the map, and with it the turning
// direction, changes. The fast path sorted and walked each solid's projected points for every
// receiver it shades; with the outline it takes the corners in order instead
// (fast/fast_receiver_casts.cpp), and so does the exact engine on its areas-only route
// (exact/exact_receiver_casts.cpp): the outline is certain for the exact projection.
#pragma once

#include "core/convex_solid.hpp"
#include "geometry/monotone_chain.hpp"
#include "runtime/parallel.hpp"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace shadow::core {

/// For one directional light, each convex solid's outline seen from it: the vertices whose
/// projections along the light are the corners of the projected convex hull, counter-clockwise
/// about the direction to the light. Kept only where that is certain for the exact projection:
/// every corner turns, and every other vertex lies inside every edge, by a margin of 1e-9 of the
/// solid's light-space reach times its 3D reach, some 1e5 times what the doubles' rounding (and
/// the direction's) can move such a cross product. Elsewhere (a face edge-on to the light, say) a
/// solid has no outline, and its casts take the hull of all their points as before.
class SolidOutlines {
 public:
  SolidOutlines() = default;

  /// `u` and `v`: unit vectors across the light, u x v towards it (the light-space grid's frame),
  /// so that counter-clockwise in (u, v) is counter-clockwise seen from the light.
  SolidOutlines(const std::vector<ConvexSolid>& solids, const glm::dvec3& u, const glm::dvec3& v, unsigned threads = 1) {
    const std::size_t n = solids.size();
    // Each block's outlines one after another (a block's solids are consecutive, so its run is
    // one piece of corners_), then the runs joined in order.
    constexpr std::size_t kBlock = 1024;
    std::vector<std::uint8_t> count(n, 0);
    std::vector<std::vector<std::uint8_t>> runs((n + kBlock - 1) / kBlock);
    runtime::parallel_for_blocks(n, kBlock, threads, [&](unsigned, std::size_t b, std::size_t begin, std::size_t end) {
      std::array<std::uint8_t, 2 * kMaxCorners> corners;  // (the chain's room)
      for (std::size_t s = begin; s < end; ++s) {
        const std::size_t m = find_outline(solids[s], u, v, corners.data());
        count[s] = static_cast<std::uint8_t>(m);
        runs[b].insert(runs[b].end(), corners.begin(), corners.begin() + static_cast<std::ptrdiff_t>(m));
      }
    });
    start_.assign(n + 1, 0);
    for (std::size_t s = 0; s < n; ++s) start_[s + 1] = start_[s] + count[s];
    corners_.reserve(start_[n]);
    for (const std::vector<std::uint8_t>& run : runs) corners_.insert(corners_.end(), run.begin(), run.end());
    solids_ = &solids;
  }

  /// Whether these are the outlines of `solids` (the same vector, as find_outlines was given):
  /// outlines hold vertex indices, which mean nothing for other solids.
  [[nodiscard]] bool of(const std::vector<ConvexSolid>* solids) const { return solids != nullptr && solids == solids_; }

  /// Solid `s`'s outline: `size` vertex indices from `data`, counter-clockwise seen from the
  /// light; size 0 where the outline is not certain (or for an outline of no solids).
  struct Outline {
    const std::uint8_t* data = nullptr;
    std::size_t size = 0;
  };
  [[nodiscard]] Outline outline(std::size_t s) const {
    if (s + 1 >= start_.size()) return {};
    return {corners_.data() + start_[s], start_[s + 1] - start_[s]};
  }

  /// The most corners an outline keeps (and the most vertices of a solid that gets one).
  static constexpr std::size_t kMaxCorners = 32;

 private:
  /// The certain outline of `cs` into corners[0, m) (room for 2 kMaxCorners), m returned; 0
  /// where there is none.
  static std::size_t find_outline(const ConvexSolid& cs, const glm::dvec3& u, const glm::dvec3& v, std::uint8_t* corners) {
    const std::size_t n = cs.vertices.size();
    if (n < 3 || n > kMaxCorners) return 0;
    // Light-space points about the first vertex (small numbers: the rounding is relative to the
    // solid's size, not to the scene's).
    std::array<glm::dvec2, kMaxCorners> q;
    double reach2 = 0, height2 = 0;  // the largest |q|^2, and |y|^2 in 3D
    for (std::size_t a = 0; a < n; ++a) {
      const glm::dvec3 y = cs.vertices[a] - cs.vertices[0];
      q[a] = {glm::dot(u, y), glm::dot(v, y)};
      reach2 = std::max(reach2, q[a].x * q[a].x + q[a].y * q[a].y);
      height2 = std::max(height2, glm::dot(y, y));
    }
    // (Tiny solids get none: below some 1e-140 the squares and the cross products would leave the
    // normal doubles, where rounding is no longer relative and the margin no longer covers it.)
    if (!(reach2 > 1e-280) || !std::isfinite(height2)) return 0;
    // Each q is within some 10 eps H of the exact projection along the exact direction (H the 3D
    // reach: the products' rounding, and u and v a few ulps off the exact frame), so a cross
    // product of differences, whose factors are at most 2 reach, moves by some 1e-14 reach H.
    const double margin = 1e-9 * std::sqrt(reach2) * std::sqrt(height2);
    auto cross = [&](std::size_t o, std::size_t a, std::size_t b) {
      return (q[a].x - q[o].x) * (q[b].y - q[o].y) - (q[a].y - q[o].y) * (q[b].x - q[o].x);
    };
    // Andrew's monotone chain on the vertex indices, sorted by insertion (a handful).
    std::array<std::uint8_t, kMaxCorners> order;
    for (std::size_t i = 0; i < n; ++i) {
      std::size_t j = i;
      while (j > 0 && (q[i].x < q[order[j - 1]].x || (q[i].x == q[order[j - 1]].x && q[i].y < q[order[j - 1]].y))) {
        order[j] = order[j - 1];
        --j;
      }
      order[j] = static_cast<std::uint8_t>(i);
    }
    const std::size_t m = geometry::monotone_chain(order.data(), n, corners, [&](std::size_t o, std::size_t a, std::size_t b) {
      return cross(o, a, b) > 0;
    });
    if (m < 3) return 0;
    // Certain: every corner turns left by the margin, every other vertex is inside every edge by it.
    std::uint32_t on_outline = 0;  // (n <= 32)
    for (std::size_t c = 0; c < m; ++c) {
      const std::size_t c1 = c + 1 < m ? c + 1 : 0, c2 = c1 + 1 < m ? c1 + 1 : 0;
      on_outline |= std::uint32_t{1} << corners[c];
      if (!(cross(corners[c], corners[c1], corners[c2]) > margin)) return 0;
    }
    for (std::size_t a = 0; a < n; ++a) {
      if (on_outline >> a & 1) continue;
      for (std::size_t c = 0; c < m; ++c)
        if (!(cross(corners[c], corners[c + 1 < m ? c + 1 : 0], a) > margin)) return 0;
    }
    return m;
  }

  std::vector<std::uint32_t> start_;       ///< each solid's first corner in corners_ (compressed rows)
  std::vector<std::uint8_t> corners_;      ///< vertex indices, outline after outline
  const std::vector<ConvexSolid>* solids_ = nullptr;  ///< the solids they outline
};

}  // namespace shadow::core
