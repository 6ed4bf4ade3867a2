// SPDX-License-Identifier: GPL-3.0-or-later
// The boundaries of the instants a strip has not yet walked, filed by tile: a per-cell refinement
// of the tiles' bounds on the sun still to come (lit_tiles.hpp). A tile's masks say only that an
// instant's boundary passes near the tile; near buildings that is so at almost every instant, so
// the tiles alone leave the small cells there undecided for most of a long period. Here, for the
// part of a cell's bounding box under one tile, each such instant is looked at closely: when none
// of its boundary segments meets the box, the box lies wholly in its lit region or wholly out of
// it, and the nearest segment's side tells which (docs/sun-hours-map.md, step 7).
#pragma once

#include "sunmap/face_overlay.hpp"
#include "sunmap/lit_tiles.hpp"

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace shadow::sunmap {

/// A strip's pending boundaries in doubles, filed under every tile of the strip's columns that
/// each segment passes through (with a margin far beyond the rounding of doubles, so that none is
/// missed), and per tile the instants the tile's masks count as possibly lighting it without
/// lighting it whole: the ones a cell under the tile may learn more about.
class PendingBoundaries {
 public:
  /// Files the boundaries of `order` (the strip's pending instants in the order they are walked,
  /// each with its curves clipped to the strip), under the tiles of `tiles` (which must outlive
  /// this) in columns [c0, c1]; `whole_strip` false: the curves are clipped to x0 <= x <= x1.
  /// Instants of no weight (`hours`) are left out, as the counts leave them.
  void build(const FaceTiles& tiles, std::size_t c0, std::size_t c1, bool whole_strip, double x0, double x1,
             const std::vector<std::pair<std::size_t, const std::vector<XCurve>*>>& order,
             const std::vector<double>& hours);
  /// The same from the instants `order` and their boundaries in doubles, `which` of `segments`
  /// (any others are left out), not clipped to the strip: a segment is filed only under the
  /// strip's columns, and within the strip it is the instant's boundary all the same.
  void build(const FaceTiles& tiles, std::size_t c0, std::size_t c1, bool whole_strip, double x0, double x1,
             const std::vector<std::size_t>& order, const std::vector<RoughSegment>& segments,
             const std::vector<std::size_t>& which, const std::vector<double>& hours);
  bool empty() const { return tiles_ == nullptr; }
  const TileGrid& grid() const { return tiles_->grid; }

  /// The first `count` instants of the order have been walked: they no longer count.
  void walked(std::size_t count) { walked_ = count; }

  /// Of the instants not yet walked that tile (c, r)'s masks count as possibly lighting it but
  /// not surely whole: how many surely leave the part of the box [xmin, xmax] x [ymin, ymax]
  /// under the tile dark (`dark`), and how many surely light it whole (`lit`). The search stops
  /// once `dark` reaches `want_dark` or `lit` reaches `want_lit`.
  struct Refined {
    std::uint32_t dark = 0, lit = 0;
  };
  Refined refine(std::size_t c, std::size_t r, double xmin, double xmax, double ymin, double ymax,
                 std::uint32_t want_dark, std::uint32_t want_lit) const;

  /// How many instants not yet walked tile (c, r)'s masks leave undecided (the most refine can find).
  std::uint32_t undecided(std::size_t c, std::size_t r) const;

 private:
  std::size_t at(std::size_t c, std::size_t r) const { return (c - c0_) * tiles_->grid.n + r; }

  const FaceTiles* tiles_ = nullptr;
  std::size_t c0_ = 0, c1_ = 0, walked_ = 0;
  bool whole_strip_ = true;
  double x0_ = 0, x1_ = 0, margin_ = 0;
  /// The segments, by the position of their instant in the order: from (xa, ya), the
  /// lexicographically smaller end, to (xb, yb); `left`: the lit region on their left.
  struct Segment {
    double xa, ya, xb, yb;
    std::uint32_t position;
    bool left;
  };
  std::vector<Segment> segments_;
  /// Per tile (column-major from c0_): the segments through it (ascending, so by position), and
  /// the positions its masks leave undecided (ascending); offsets into the two arrays.
  std::vector<std::uint32_t> segment_start_, segment_ids_;
  std::vector<std::uint32_t> undecided_start_, undecided_positions_;
};

/// Whether the sun still to come settles a cell (bounding box [xmin, xmax] x [ymin, ymax]) of
/// `value` hours, now at level `now` below the top of `levels` (ascending), with `whole` hours
/// still to come from the instants lighting the whole face, when the tiles' counts under it are
/// refined by the pending boundaries: the level it surely ends at (`now`, or the top level), or
/// SIZE_MAX. Every point of the cell lies in some tile under its box, and gets at most that
/// tile's count of instants that may light it, less those surely dark on the box, times the
/// largest weight, and at least its count of those lighting it whole, plus those surely lighting
/// the box whole, times the smallest positive one. Cells over more than four tiles are left.
std::size_t settled_level(const StripTileCounts& counts, const PendingBoundaries& pending, double xmin, double xmax,
                          double ymin, double ymax, const mpq_class& value, const mpq_class& whole,
                          const std::vector<mpq_class>& levels, std::size_t now);

}  // namespace shadow::sunmap
