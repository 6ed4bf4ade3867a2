// SPDX-License-Identifier: GPL-3.0-or-later
// One face's exact boundary curves, every instant's, packed while they wait for the face's
// strips, in the full map and in the threshold map alone (docs/sun-hours-map.md, step 7): each distinct end point's exact
// rational coordinates as GMP limbs, each segment two point indices, its tag and its direction.
// A Curve holds its points (and, once asked, its supporting line) as lazy CGAL objects, each
// with an interval, a reference count and GMP numbers of its own: several hundred bytes a
// segment (about 575 when curves were made through a lazy segment). Packed, a segment costs its
// numbers' limbs and 40 bytes, some 120-200 in all, so the budget of segments held
// (SunHoursOptions::level_held_segments) holds a third of the memory it did. A strip unpacks the
// curves entering it when its job (full map) or its rounds (threshold map) take them: the same
// exact points, the same tags.
#pragma once

#include "sunmap/face_overlay.hpp"
#include "sunmap/rough_segments.hpp"

#include <gmp.h>

#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <vector>

namespace shadow::sunmap {

class PackedBoundaries {
  struct Segment {
    std::uint64_t from, to;  ///< point indices: the curve's source and target
    long tag;
    bool forward;  ///< the source is the lexicographically smaller end
  };

 public:
  /// One call's curves packed on their own, in exactly sized vectors: a work item packs its
  /// curves as soon as it makes them (face-instant pairs in parallel), and they are added to
  /// the face's in order later, the same numbers as add(curves) would pack.
  class Chunk {
   public:
    std::size_t size() const { return segments_.size(); }

   private:
    friend class PackedBoundaries;
    std::vector<std::uint64_t> at_;  ///< as Store's, from 0
    std::vector<mp_limb_t> limbs_;
    std::vector<Segment> segments_;
  };
  /// `curves` (boundary curves tagged as face_overlay.hpp tags them: one instant's, a few, or
  /// the chart's outline) packed; a point that several of them end at is packed once.
  static Chunk pack(const std::vector<Curve>& curves);
  /// Appends a chunk's curves (taken).
  void add(Chunk&& chunk);
  /// Appends `curves`: add(pack(curves)).
  void add(const std::vector<Curve>& curves) { add(pack(curves)); }

  std::size_t size() const { return store_ ? store_->segments.size() : 0; }
  bool empty() const { return size() == 0; }
  /// The instant segment `k` belongs to (the number of instants for the outline's).
  std::size_t instant(std::size_t k) const {
    return tag_instant(store_->segments[k].tag);
  }

  /// The curves `which` (indices into this), unpacked in that order into `out` (cleared); each
  /// point unpacked once and shared by the curves ending at it.
  void unpack(const std::vector<std::size_t>& which, std::vector<Curve>& out) const;
  /// Every segment's rough form (rough_segment of its curve: the same doubles), in order.
  std::vector<RoughSegment> rough(unsigned threads) const;

  /// The bytes held (the deques' elements; their blocks hold a little more).
  std::size_t bytes() const;

 private:
  // Deques, not vectors: they grow a block at a time, where a vector's doubling would hold up to
  // twice the memory, and three times while it moves. Made on the first add: an empty deque
  // still holds a block (some 600 bytes), and a map has one of these per face.
  struct Store {
    /// Point p's limbs start at limbs[at[p]]: four sizes (x's numerator, signed, and
    /// denominator; y's), two to a limb, then the four numbers' limbs in that order.
    std::deque<std::uint64_t> at;
    std::deque<mp_limb_t> limbs;
    std::deque<Segment> segments;
  };
  std::unique_ptr<Store> store_;

  exact::Point2 unpack_point(std::uint64_t p) const;
};

}  // namespace shadow::sunmap
