// SPDX-License-Identifier: GPL-3.0-or-later
// Where on a face each instant may light it, coarsely: a grid of tiles over the face's chart and,
// per instant, the tiles its lit region may meet (a superset: every tile a boundary passes
// through, and every tile inside the region) and the tiles it surely lights whole (a subset: the
// tiles inside it that no boundary comes near). The threshold map alone uses them to bound the
// sun a cell can still get by the instants still to come, from above (those that may light the
// tiles under the cell) and from below (those that light every tile under it whole), not by every
// instant still to come (docs/sun-hours-map.md, step 7), so that cells in shade, and cells sure to
// reach the top level, are settled long before the end of a long period.
#pragma once

#include "sunmap/face_overlay.hpp"

#include <gmpxx.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace shadow::sunmap {

/// A grid of n x n tiles over a chart's bounding box; n 0: no grid (the face's bound is global).
struct TileGrid {
  double x0 = 0, y0 = 0, dx = 1, dy = 1;
  std::size_t n = 0;
  std::size_t words() const { return (n * n + 63) / 64; }
  /// The tile column of x and row of y, clamped to the grid.
  std::size_t column(double x) const;
  std::size_t row(double y) const;
};

/// The grid for a face whose instants' boundaries hold about `segments` segments each: finer for
/// more (up to 256 x 256), none below 16, and coarser where `instants` masks of it (two bits
/// per tile and instant) would pass kMaxTileBits.
TileGrid tile_grid(const exact::Polygon2& chart, std::size_t segments, std::size_t instants);

/// The most bits of masks one face's tiles may take (8 MiB: a 256 x 256 grid for 512 instants).
constexpr double kMaxTileBits = 64.0 * 1024 * 1024;

/// Sets in `mask` (grid.words() words, cleared first) the tiles the region bounded by the curves
/// [first, last) (an instant's lit region's whole boundary on the face) may meet: those the
/// boundary passes through (with a margin of up to a quarter tile, so that rounding to doubles
/// cannot miss one) and those whose centre lies inside it. When `whole` is given (as many words,
/// cleared first), sets there the tiles the region surely covers, closed tile and all: inside
/// it, and not marked as passed through by the boundary.
void mark_lit_tiles(const TileGrid& grid, const Curve* first, const Curve* last, std::uint64_t* mask,
                    std::uint64_t* whole = nullptr);

/// What the threshold map alone knows in advance of one face: its grid, per instant the tiles it
/// may light and those it surely lights whole (instant i's words at i x grid.words(); all clear
/// when it does not cut the face), and the hours of the instants that light the face whole.
struct FaceTiles {
  TileGrid grid;
  std::vector<std::uint64_t> masks;
  std::vector<std::uint64_t> whole_masks;
  mpq_class whole{0};
  bool lit(std::size_t instant, std::size_t tile) const {
    return (masks[instant * grid.words() + tile / 64] >> (tile % 64)) & 1U;
  }
  bool lit_whole(std::size_t instant, std::size_t tile) const {
    return (whole_masks[instant * grid.words() + tile / 64] >> (tile % 64)) & 1U;
  }
};

}  // namespace shadow::sunmap
