// SPDX-License-Identifier: GPL-3.0-or-later
// Tiles of a large receiver (docs/tiles.md): a receiver that faces the light and has more
// candidate casters than a threshold is split into square cells of its chart bounding box, each
// a separate work item. A tile is the receiver's FacePrep with the tile's cell as its chart box:
// culling (the prism or pyramid over the box), clipping and the fast path's grid all follow
// from it, so a tile sees only the casters whose shadows reach it. A face that is not its own
// chart box (a triangle, an L, a rotated rectangle) keeps its outline: its part of a tile is the
// outline intersected with the cell; cells that miss it are dropped, and cells wholly inside it
// are boxes of their own (chart_is_box). Plain data: no CGAL here.
#pragma once

#include "core/face_prep.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <vector>

namespace shadow::core {

/// The number of candidate casters a tile is cut for (about: a tile near the receiver's edge,
/// or under long shadows, has fewer or more).
constexpr std::size_t kTileCandidates = 2000;

/// The most tiles one receiver is cut into.
constexpr std::size_t kMaxTiles = 1024;

/// What a receiver computation is asked to do about tiles.
struct TileRequest {
  /// The tile to compute (its chart box replaces the face's), or nullptr for the whole face.
  const FacePrep* tile = nullptr;
  /// Whole faces only: stop after culling when the face is tileable (front-facing, not
  /// degenerate) and has more candidate casters than this; 0: never.
  std::size_t split_above = 0;
};

/// Whether a face may be split into tiles at all: any face with an area, whatever its outline.
inline bool tileable(const FacePrep& fp) { return !fp.degenerate; }

/// Where a cell of a face's chart box lies with respect to the face's outline, decided exactly
/// (exact::place_cell).
enum class CellPlace {
  Outside,   ///< the cell and the face have no interior point in common: no tile
  Inside,    ///< the closed cell lies in the face: the tile is a box of its own
  Crossing,  ///< anything else (the outline meets the closed cell): the outline is cut to it
};

/// The share of its chart box that a face covers (its chart area over the box's, in doubles: a
/// guide for the number of tiles, not an exact value), in (0, 1]; 1 for a box face.
inline double box_fill(const std::vector<glm::dvec3>& vertices, const FacePrep& fp) {
  if (fp.chart_is_box || fp.chart_ring.size() < 3) return 1.0;
  const int i = chart_i(fp.axis), j = chart_j(fp.axis);
  const double twice = twice_area_about_box_corner(fp, fp.chart_ring.size(), [&](std::size_t a) {
    const glm::dvec3& p = vertices[static_cast<std::size_t>(fp.chart_ring[a])];
    return std::array<double, 2>{p[i], p[j]};
  });
  const double fill = 0.5 * std::abs(twice) / chart_box_area(fp);
  return std::isfinite(fill) && fill > 0 ? std::min(fill, 1.0) : 1.0;
}

/// Places a cell (its lower and upper corners) with respect to a face's outline.
using PlaceCell = std::function<CellPlace(const std::array<double, 2>& lo, const std::array<double, 2>& hi)>;

/// The tiles of face `fp`: about ceil(candidates / per_tile) square cells of its chart box (at
/// most `max_tiles` in all; none for a box too small to cut), in rows; each a copy of `fp` with
/// the cell as its chart box. Borders are doubles shared exactly by neighbouring tiles: the
/// cells partition the box. A face that is not its own chart box needs `place` (without it every
/// cell counts as Crossing): Outside cells are left out, Inside ones get chart_is_box (the tile
/// is the cell, as for a box face), Crossing ones keep chart_is_box false (the tile is the
/// face's outline intersected with the cell: the receivers intersect with the outline).
inline std::vector<FacePrep> make_tiles(const FacePrep& fp, std::size_t candidates, std::size_t per_tile,
                                        std::size_t max_tiles = kMaxTiles, const PlaceCell& place = {}) {
  std::vector<FacePrep> tiles;
  const double w = fp.chart_max[0] - fp.chart_min[0], h = fp.chart_max[1] - fp.chart_min[1];
  if (!(w > 0) || !(h > 0) || per_tile == 0) return tiles;
  const double wanted = std::clamp(std::ceil(static_cast<double>(candidates) / static_cast<double>(per_tile)), 1.0,
                                   static_cast<double>(max_tiles));
  // sqrt(w) * sqrt(h / wanted), not sqrt(w * h / wanted): w * h underflows to 0 for sides near
  // 1e-162 (validation accepts them), which would make every side count max_tiles.
  const double side = std::sqrt(w) * std::sqrt(h / wanted);
  if (!std::isfinite(side) || !(side > 0)) return tiles;
  const auto count = [&](double length) {
    return static_cast<std::size_t>(std::clamp(std::round(length / side), 1.0, static_cast<double>(max_tiles)));
  };
  std::size_t ni = count(w), nj = count(h);
  // Each side is clamped on its own; the product may not exceed max_tiles either.
  while (ni * nj > max_tiles && ni * nj > 1) (ni >= nj ? ni : nj) -= 1;
  auto border = [&](int c, std::size_t k, std::size_t n) {
    if (k == 0) return fp.chart_min[c];
    if (k == n) return fp.chart_max[c];
    const double lo = fp.chart_min[c], hi = fp.chart_max[c];
    return std::min(hi, lo + (hi - lo) * static_cast<double>(k) / static_cast<double>(n));
  };
  // Places a cell of a face that is not a box; false: it misses the face.
  auto placed = [&](FacePrep& tile) {
    if (fp.chart_is_box || !place) return true;
    const CellPlace where = place(tile.chart_min, tile.chart_max);
    tile.chart_is_box = where == CellPlace::Inside;
    return where != CellPlace::Outside;
  };
  std::size_t crossing = 0;
  for (std::size_t b = 0; b < nj; ++b)
    for (std::size_t a = 0; a < ni; ++a) {
      FacePrep tile = fp;
      tile.chart_min = {border(0, a, ni), border(1, b, nj)};
      tile.chart_max = {border(0, a + 1, ni), border(1, b + 1, nj)};
      if (!(tile.chart_min[0] < tile.chart_max[0]) || !(tile.chart_min[1] < tile.chart_max[1])) continue;
      if (!placed(tile)) continue;
      crossing += tile.chart_is_box ? 0 : 1;
      tiles.push_back(std::move(tile));
    }
  // Crossing cells of a face that is not a box cost several times an inner one (the shadow is
  // intersected with the outline: on the fast path and with polygons a Boolean operation; exact
  // and areas only, the casts clipped to each convex piece), so each is cut once more into
  // quarters, when the cap allows all of them.
  if (!fp.chart_is_box && place && crossing > 0 && tiles.size() + 3 * crossing <= max_tiles) {
    std::vector<FacePrep> cut;
    for (FacePrep& tile : tiles) {
      const double mx = tile.chart_min[0] + (tile.chart_max[0] - tile.chart_min[0]) / 2;
      const double my = tile.chart_min[1] + (tile.chart_max[1] - tile.chart_min[1]) / 2;
      if (tile.chart_is_box || !(tile.chart_min[0] < mx && mx < tile.chart_max[0]) ||
          !(tile.chart_min[1] < my && my < tile.chart_max[1])) {
        cut.push_back(std::move(tile));
        continue;
      }
      // Quarters in rows; the midpoints are shared by both halves: they partition the cell.
      const double xs[3] = {tile.chart_min[0], mx, tile.chart_max[0]}, ys[3] = {tile.chart_min[1], my, tile.chart_max[1]};
      for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a) {
          FacePrep quarter = fp;
          quarter.chart_min = {xs[a], ys[b]};
          quarter.chart_max = {xs[a + 1], ys[b + 1]};
          if (placed(quarter)) cut.push_back(std::move(quarter));
        }
    }
    tiles.swap(cut);
  }
  if (tiles.size() < 2) tiles.clear();  // not worth it: the face as one item
  return tiles;
}

}  // namespace shadow::core
