// SPDX-License-Identifier: GPL-3.0-or-later
// Convex polygons that share an edge run both ways, united where the result is convex: the step
// before ConvexUnionArea (exact) and the fast path's boundary measure take a union
// (docs/algorithm.md, "Neighbouring casts merged"). It sees only vertex slots: the caller tells
// it how to hash an edge, whether two slots are the same point and how a turn goes.
//
// The casts of two faces of one mesh that meet along an edge and lie on either side of it meet
// along that edge's cast, run one way by each. Their union is one convex polygon when the turns
// where they meet are to the left (or straight on): the same point set, so the same area and the
// same canonical boundary, with two polygons fewer to test every edge against, and the shared
// edge (covered by neither, measured twice and cancelled) gone. A triangulated terrain casting
// on a road merges into a few large pieces.
#pragma once

#include "geometry/point_hash.hpp"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <vector>

namespace shadow::geometry {

/// Merges polygons along shared edges; keeps its scratch between calls (one per thread).
class SharedEdgeMerge {
 public:
  /// The polygons of slots first[i]..first[i + 1] (`nxt`: each slot's next around its
  /// polygon), counter-clockwise and convex: every pair that shares an edge run both ways is
  /// united where both turns where they meet pass `left_or_straight(p, q, r)` (to the left, or
  /// straight on and not back), repeatedly. `point_hash(v)`: a hash of slot v's point, equal for
  /// equal points (point_hash(x, y) below); `equal(a, b)`: slots a and b are the same point.
  /// Returns the number of merges; when some, `nxt` and `first` describe the merged polygons
  /// over new slots k whose old slot is order()[k] (polygons in the order of their union-find
  /// roots): the caller permutes its points the same way.
  template <class PointHash, class Equal, class LeftOrStraight>
  std::size_t run(std::vector<std::size_t>& nxt, std::vector<std::size_t>& first, PointHash&& point_hash, Equal&& equal,
                  LeftOrStraight&& left_or_straight) {
    const std::size_t n = nxt.size(), polygons = first.size() - 1;
    prv_.resize(n);
    owner_.resize(n);
    moved_.resize(n);
    for (std::size_t i = 0; i < polygons; ++i)
      for (std::size_t v = first[i]; v < first[i + 1]; ++v) {
        prv_[nxt[v]] = v;
        owner_[v] = i;
        moved_[v] = v;
      }
    root_.resize(polygons);
    std::iota(root_.begin(), root_.end(), std::size_t{0});
    // Every edge hashed by its ends' point hashes (a collision is told apart by `equal`), under
    // the slot that carried it then.
    point_hashes_.resize(n);
    for (std::size_t v = 0; v < n; ++v) point_hashes_[v] = point_hash(v);
    const auto edge_hash = [&](std::size_t a, std::size_t b) { return edge_hash_of(point_hashes_[a], point_hashes_[b]); };
    std::size_t size = 16;
    while (size < 2 * n) size *= 2;
    const std::size_t mask = size - 1;
    table_.assign(size, kEmpty);
    hashes_.resize(n);
    for (std::size_t v = 0; v < n; ++v) {
      hashes_[v] = edge_hash(v, nxt[v]);
      std::size_t h = hashes_[v] & mask;
      while (table_[h] != kEmpty) h = (h + 1) & mask;
      table_[h] = v;
    }
    std::size_t merges = 0;
    work_.resize(n);
    std::iota(work_.begin(), work_.end(), std::size_t{0});
    while (!work_.empty()) {
      const std::size_t a = work_.back();
      work_.pop_back();
      if (moved_[a] != a) continue;  // dropped by a merge
      const std::size_t b = nxt[a];
      if (equal(a, b)) continue;  // a repeated point: no edge
      // The edge b -> a in another polygon: a hashed slot whose carrier now runs from b to a.
      const std::uint64_t want = edge_hash(b, a);
      std::size_t bj = kEmpty;
      for (std::size_t h = want & mask; table_[h] != kEmpty; h = (h + 1) & mask) {
        if (hashes_[table_[h]] != want) continue;
        const std::size_t t = carrier(table_[h]);
        if (root(owner_[t]) == root(owner_[a]) || !equal(t, b) || !equal(nxt[t], a)) continue;
        bj = t;
        break;
      }
      if (bj == kEmpty) continue;
      const std::size_t aj = nxt[bj];  // polygon j runs b -> a
      // The merged cycle: ... prv(a) -> a -> (j after a) ... (j before b) -> b -> (i after b) ...
      const std::size_t after_a = nxt[aj], after_b = nxt[b];
      if (!left_or_straight(prv_[a], a, after_a) || !left_or_straight(prv_[bj], bj, after_b)) continue;
      nxt[a] = after_a;
      prv_[after_a] = a;
      nxt[bj] = after_b;
      prv_[after_b] = bj;
      moved_[aj] = a;  // aj carried a -> after_a: now a does
      moved_[b] = bj;  // i's b carried b -> after_b: now bj does
      root_[root(owner_[bj])] = root(owner_[a]);
      ++merges;
      work_.push_back(a);  // their new edges may meet others
      work_.push_back(bj);
    }
    if (merges > 0) compact(nxt, first);
    return merges;
  }

  /// After a run with merges: the old slot of each new slot.
  [[nodiscard]] const std::vector<std::size_t>& order() const { return order_; }

  /// A hash of a point's two coordinates' bits (for run's point_hash). Every bit is mixed into the low
  /// ones the table uses: a double holding an integer (a grid point, a scaled chart's bound) has
  /// its low mantissa bits all zero.
  static std::uint64_t point_hash(double x, double y) {
    std::uint64_t a, b;
    std::memcpy(&a, &x, sizeof a);
    std::memcpy(&b, &y, sizeof b);
    return mix64(a ^ mix64(b + 0x9E3779B97F4A7C15ull));
  }

 private:
  static constexpr std::size_t kEmpty = static_cast<std::size_t>(-1);

  /// An edge's hash from its ends' point hashes (not symmetric: the edge b -> a hashes apart).
  static std::uint64_t edge_hash_of(std::uint64_t from, std::uint64_t to) {
    return mix64(from * 0x9E3779B97F4A7C15ull + to);
  }

  std::size_t root(std::size_t i) {
    while (root_[i] != i) i = root_[i] = root_[root_[i]];
    return i;
  }

  /// The live slot that now carries the edge slot s carried when it was hashed.
  std::size_t carrier(std::size_t s) const {
    while (moved_[s] != s) s = moved_[s];
    return s;
  }

  /// The merged polygons written back in the order of their roots. A root's own slots may all
  /// have been dropped (each merge drops one slot of either side): each starts from any live slot.
  void compact(std::vector<std::size_t>& nxt, std::vector<std::size_t>& first) {
    const std::size_t n = nxt.size(), polygons = first.size() - 1;
    std::vector<std::size_t>& start_of = work_;
    start_of.assign(polygons, kEmpty);
    for (std::size_t v = 0; v < n; ++v)
      if (moved_[v] == v && start_of[root(owner_[v])] == kEmpty) start_of[root(owner_[v])] = v;
    order_.clear();
    first.assign(1, 0);
    for (std::size_t i = 0; i < polygons; ++i) {
      const std::size_t start = start_of[i];
      if (start == kEmpty) continue;  // not a root
      std::size_t v = start;
      do {
        order_.push_back(v);
        v = nxt[v];
      } while (v != start);
      first.push_back(order_.size());
    }
    nxt.resize(order_.size());
    for (std::size_t i = 0; i + 1 < first.size(); ++i)
      for (std::size_t k = first[i]; k < first[i + 1]; ++k) nxt[k] = k + 1 == first[i + 1] ? first[i] : k + 1;
  }

  std::vector<std::size_t> prv_, owner_, moved_, root_, table_, work_;
  std::vector<std::uint64_t> point_hashes_, hashes_;
  std::vector<std::size_t> order_;
};

}  // namespace shadow::geometry
