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
#include "sunmap/rough_segments.hpp"

#include <gmpxx.h>

#include <cstddef>
#include <cstdint>
#include <utility>
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
/// mark_lit_tiles from the boundary's rough segments (the same doubles).
void mark_lit_tiles(const TileGrid& grid, const RoughSegment* first, const RoughSegment* last, std::uint64_t* mask,
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
  /// The slot of instant i (its index in `instants`), or SIZE_MAX when it does not cut the face.
  std::size_t slot(std::size_t i) const;
  bool lit(std::size_t slot, std::size_t tile) const {
    return (masks[slot * grid.words() + tile / 64] >> (tile % 64)) & 1U;
  }
  bool lit_whole(std::size_t slot, std::size_t tile) const {
    return (whole_masks[slot * grid.words() + tile / 64] >> (tile % 64)) & 1U;
  }
};

/// A face's tiles from every instant's boundaries on it: `rough` in time order, each instant's
/// together, `runs` per instant cutting it its [begin, end) there; `whole`: the hours of the
/// instants lighting it whole; the grid within `max_bits` (tile_grid); masks on `threads` threads.
FaceTiles make_face_tiles(const exact::Polygon2& chart, const std::vector<RoughSegment>& rough,
                          const std::vector<std::pair<std::size_t, std::size_t>>& runs, const mpq_class& whole,
                          double max_bits, unsigned threads);

/// The instants cutting a face (t.instants, ascending) in the order its strips sweep them: those
/// lighting the most of its tiles whole first, in time order among equals.
std::vector<std::size_t> sweep_order(const FaceTiles& t);

/// One strip's counts, per tile under it (the columns meeting x0 <= x <= x1), of the instants
/// not yet walked that may light the tile and of those that light it whole: the threshold map
/// alone's bounds on the sun still to come to a cell (docs/sun-hours-map.md, step 7).
class StripTileCounts {
 public:
  /// The tiles of `tiles` (which must outlive this) under the strip x0 <= x <= x1 of its chart
  /// (`whole_strip`: every column), no instant counted yet; `hours`: the instants', and
  /// `exact_hours` the same as the map sums them (sunmap::exact_hours).
  void begin(const FaceTiles& tiles, bool whole_strip, double x0, double x1, const std::vector<double>& hours,
             const std::vector<mpq_class>& exact_hours);
  bool empty() const { return most_.empty(); }

  /// Instant i (of any weight; those of none are never counted) leaves (or, `add`, enters) the
  /// counts. This and the other changes do nothing before begin.
  void count(std::size_t i, bool add);
  /// The counts made of `instants` alone (each once).
  void recount(const std::vector<std::size_t>& instants);
  /// The number of tiles under the strip that instant i lights whole.
  std::size_t whole_tiles(std::size_t i) const;

  /// Over the tiles under the strip that meet the box [xmin, xmax] x [ymin, ymax]: the largest
  /// count of instants that may light one, and the smallest of those lighting one whole.
  struct Range {
    std::uint32_t most = 0, least = 0;
  };
  Range under(double xmin, double xmax, double ymin, double ymax) const;
  /// The counts of tile (c, r), a tile under the strip.
  Range at(std::size_t c, std::size_t r) const {
    const std::size_t k = (c - c0_) * tiles_->grid.n + r;
    return {most_[k], least_[k]};
  }
  std::size_t first_column() const { return c0_; }  ///< the strip's tile columns, first and last
  std::size_t last_column() const { return c1_; }
  const mpq_class& most_weight() const { return most_weight_; }    ///< the largest instant's hours
  const mpq_class& least_weight() const { return least_weight_; }  ///< the smallest positive one

 private:
  void add_slot(std::size_t slot, bool add);

  const FaceTiles* tiles_ = nullptr;
  const std::vector<double>* hours_ = nullptr;
  std::size_t c0_ = 0, c1_ = 0;       ///< the strip's tile columns
  std::vector<std::uint32_t> most_, least_;  ///< per tile, column-major from c0_
  mpq_class most_weight_{0}, least_weight_{0};
};

}  // namespace shadow::sunmap
