// SPDX-License-Identifier: GPL-3.0-or-later
// Convex polygons that share an edge run both ways, united where the result is convex: the step
// before ConvexUnionArea measures a union (docs/algorithm.md, "Neighbouring casts merged").
// Include only from src/exact/*.cpp or tests (GMP points).
//
// The casts of two faces of one mesh that meet along an edge and lie on either side of it meet
// along that edge's cast, run one way by each. Their union is one convex polygon when the turns
// where they meet are to the left (or straight on): the same point set, so the same area and the
// same canonical boundary, with two polygons fewer to test every edge against, and the shared
// edge (covered by neither, measured twice and cancelled) gone. A triangulated terrain casting
// on a road merges into a few large pieces.
#pragma once

#include "exact/rational_points.hpp"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <vector>

namespace shadow::exact {

/// Merges polygons along shared edges; keeps its scratch between calls (one per thread).
class SharedEdgeMerge {
 public:
  /// The polygons first[i]..first[i + 1] of `pts` (their points), `ip` (intervals) and `nxt` (each
  /// vertex's next around its polygon), counter-clockwise and convex: every pair that shares an
  /// edge run both ways is united where both turns where they meet pass `left_or_straight(p, q,
  /// r)` (to the left, or straight on and not back), repeatedly, and the arrays are rewritten
  /// with the merged polygons (in the order of their union-find roots). `equal(a, b)`: vertices
  /// a and b are the same point (exactly). Returns the number of merges (0: nothing rewritten).
  template <class Equal, class LeftOrStraight>
  std::size_t run(std::vector<const QPoint2*>& pts, std::vector<IPoint2>& ip, std::vector<std::size_t>& nxt,
                  std::vector<std::size_t>& first, Equal&& equal, LeftOrStraight&& left_or_straight) {
    const std::size_t n = pts.size(), polygons = first.size() - 1;
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
    // Every edge hashed by its ends' intervals (equal points have equal intervals; a rare
    // collision is told apart by `equal`), under the slot that carried it then.
    std::size_t size = 16;
    while (size < 2 * n) size *= 2;
    const std::size_t mask = size - 1;
    table_.assign(size, kEmpty);
    hashes_.resize(n);
    for (std::size_t v = 0; v < n; ++v) {
      hashes_[v] = edge_hash(ip[v], ip[nxt[v]]);
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
      // The edge b -> a in another polygon: a hashed slot whose carrier now runs from b to a.
      const std::uint64_t want = edge_hash(ip[b], ip[a]);
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
    if (merges > 0) compact(pts, ip, nxt, first);
    return merges;
  }

 private:
  static constexpr std::size_t kEmpty = static_cast<std::size_t>(-1);

  std::size_t root(std::size_t i) {
    while (root_[i] != i) i = root_[i] = root_[root_[i]];
    return i;
  }

  /// The live slot that now carries the edge slot s carried when it was hashed.
  std::size_t carrier(std::size_t s) const {
    while (moved_[s] != s) s = moved_[s];
    return s;
  }

  static std::uint64_t point_hash(const IPoint2& p) {
    std::uint64_t a, b;
    const double x = p.x.inf(), y = p.y.inf();
    std::memcpy(&a, &x, sizeof a);
    std::memcpy(&b, &y, sizeof b);
    return (a * 0x9E3779B97F4A7C15ull) ^ (b + 0x632BE59BD9B4E019ull + (a << 6) + (a >> 2));
  }
  static std::uint64_t edge_hash(const IPoint2& from, const IPoint2& to) {
    return (point_hash(from) * 0xBF58476D1CE4E5B9ull) ^ (point_hash(to) + 0x94D049BB133111EBull);
  }

  /// The merged polygons written back in the order of their roots. A root's own slots may all
  /// have been dropped (each merge drops one slot of either side): each starts from any live slot.
  void compact(std::vector<const QPoint2*>& pts, std::vector<IPoint2>& ip, std::vector<std::size_t>& nxt,
               std::vector<std::size_t>& first) {
    const std::size_t n = pts.size(), polygons = first.size() - 1;
    std::vector<std::size_t>& start_of = work_;
    start_of.assign(polygons, kEmpty);
    for (std::size_t v = 0; v < n; ++v)
      if (moved_[v] == v && start_of[root(owner_[v])] == kEmpty) start_of[root(owner_[v])] = v;
    old_pts_.assign(pts.begin(), pts.end());
    old_ip_.assign(ip.begin(), ip.end());
    old_nxt_.assign(nxt.begin(), nxt.end());
    pts.clear();
    ip.clear();
    nxt.clear();
    first.assign(1, 0);
    for (std::size_t i = 0; i < polygons; ++i) {
      const std::size_t start = start_of[i];
      if (start == kEmpty) continue;  // not a root
      const std::size_t begin = pts.size();
      std::size_t v = start;
      do {
        pts.push_back(old_pts_[v]);
        ip.push_back(old_ip_[v]);
        v = old_nxt_[v];
      } while (v != start);
      for (std::size_t k = begin; k < pts.size(); ++k) nxt.push_back(k + 1 == pts.size() ? begin : k + 1);
      first.push_back(pts.size());
    }
  }

  std::vector<std::size_t> prv_, owner_, moved_, root_, table_, work_;
  std::vector<std::uint64_t> hashes_;
  std::vector<const QPoint2*> old_pts_;
  std::vector<IPoint2> old_ip_;
  std::vector<std::size_t> old_nxt_;
};

}  // namespace shadow::exact
