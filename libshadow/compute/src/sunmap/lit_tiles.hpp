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

/// The most bits one face's tiles may take (8 MiB: a 256 x 256 grid for about 500 instants
/// cutting the face; the masks in whole 64-bit words and each instant's index), and all faces'
/// together (64 MiB), shared evenly by the faces cut.
constexpr double kMaxTileBits = 64.0 * 1024 * 1024;
constexpr double kMaxTileBitsAll = 512.0 * 1024 * 1024;

/// A grid of n x n tiles over a chart's bounding box; n 0: no grid (the face's bound is global).
struct TileGrid {
  double x0 = 0, y0 = 0, dx = 1, dy = 1;
  std::size_t n = 0;
  std::size_t words() const { return (n * n + 63) / 64; }
  /// The tile column of x and row of y, clamped to the grid.
  std::size_t column(double x) const;
  std::size_t row(double y) const;
};

/// The grid for a face cut by `instants` instants whose boundaries hold about `segments`
/// segments each: finer for more (up to 256 x 256), none below 16 segments, and coarser where
/// their masks (two bits per tile and instant, in whole words, and the instant's index) would
/// pass `max_bits`; none below 4 x 4.
TileGrid tile_grid(const exact::Polygon2& chart, std::size_t segments, std::size_t instants,
                   double max_bits = kMaxTileBits);

/// Sets in `mask` (grid.words() words, cleared first) the tiles the region bounded by the curves
/// [first, last) (an instant's lit region's whole boundary on the face) may meet: those the
/// boundary passes through (found from points along it, with a margin of an eighth of a tile
/// and one far beyond the rounding of doubles, so that none is missed) and those whose centre
/// lies inside it. When `whole` is given (as many words,
/// cleared first), sets there the tiles the region surely covers, closed tile and all: inside
/// it, and not marked as passed through by the boundary.
void mark_lit_tiles(const TileGrid& grid, const Curve* first, const Curve* last, std::uint64_t* mask,
                    std::uint64_t* whole = nullptr);

/// What the threshold map alone knows in advance of one face: its grid, the instants that cut it
/// (ascending) and, per such instant (its slot: its index there), the tiles it may light and
/// those it surely lights whole (slot s's words at s x grid.words()), and the hours of the
/// instants that light the face whole.
struct FaceTiles {
  TileGrid grid;
  std::vector<std::size_t> instants;
  std::vector<std::uint64_t> masks;
  std::vector<std::uint64_t> whole_masks;
  mpq_class whole{0};
  bool lit(std::size_t slot, std::size_t tile) const {
    return (masks[slot * grid.words() + tile / 64] >> (tile % 64)) & 1U;
  }
  bool lit_whole(std::size_t slot, std::size_t tile) const {
    return (whole_masks[slot * grid.words() + tile / 64] >> (tile % 64)) & 1U;
  }
};

}  // namespace shadow::sunmap
