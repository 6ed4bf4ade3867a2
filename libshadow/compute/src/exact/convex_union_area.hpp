// SPDX-License-Identifier: GPL-3.0-or-later
// The exact area of a union of convex polygons without an arrangement (docs/algorithm.md, "The
// union's area without a Boolean operation"). Include only from src/exact/*.cpp or tests (CGAL).
//
// Twice the area is the sum over every edge e = (s, s + d) of cross(s, d) L_e, L_e the part of
// e that no other polygon covers (its interior, or the same line the same way with a smaller
// index). Exact: filtered signs, exact ends of the uncovered pieces only, plain rational points
// (exact/rational_points.hpp), no lazy number.
#pragma once

#include "exact/boundary_chain.hpp"
#include "exact/kernel.hpp"
#include "exact/rational_points.hpp"
#include "exact/union_across.hpp"
#include "geometry/box_sweep.hpp"
#include "geometry/shared_edge_merge.hpp"
#include "geometry/winds_once.hpp"

#include <algorithm>
#include <cstddef>
#include <deque>
#include <utility>
#include <vector>

namespace shadow::exact {

/// Twice the exact area of a union of convex polygons; one per thread, its scratch reused.
class ConvexUnionArea {
 public:
  using EQ = shadow::exact::EQ;

  /// Counts of the last call (for tests and the benchmark's notes).
  struct Counts {
    std::size_t polygons = 0;       ///< input polygons
    std::size_t pairs = 0;          ///< polygon pairs whose boxes meet, not apart across
    std::size_t edges_partial = 0;  ///< edges partly covered (those need exact parameters)
    std::size_t exact_params = 0;   ///< parameters t made exactly
    std::size_t merged = 0;         ///< polygons merged into a neighbour along a shared edge
    std::size_t inside = 0;         ///< polygons left out, inside another (areas only)
  };

  /// Twice the exact area of the union of the polygons points[first[k], first[k + 1]) (each
  /// counter-clockwise with positive area) into `out`. False (and `out` unchanged) when some
  /// polygon is not convex: the caller unites them with a Boolean operation instead.
  bool twice_area(const std::vector<QPoint2>& points, const std::vector<std::size_t>& first, EQ& out,
                  BoundaryChain* boundary = nullptr) {
    return twice_area(points.data(), first, out, boundary);
  }
  bool twice_area(const QPointList& points, const std::vector<std::size_t>& first, EQ& out,
                  BoundaryChain* boundary = nullptr) {
    return twice_area(points.data(), first, out, boundary);
  }
  /// The same for the points points[first[k], first[k + 1]). `boundary`, when given, also gets
  /// the union's boundary reversed (every uncovered piece of every edge, run backwards: the
  /// chain of the union's complement), whatever it held before: a window minus the union when
  /// the caller put the window's boundary in it first. Nothing is added when false is returned.
  bool twice_area(const QPoint2* points, const std::vector<std::size_t>& first, EQ& out,
                  BoundaryChain* boundary = nullptr) {
    bool convex_polygons = false;
    {
      CGAL::Protect_FPU_rounding<true> guard;  // the loading's equality and convexity tests
      convex_polygons = load(points, first);
    }
    if (!convex_polygons) return false;
    boundary_ = boundary;
    find_pairs();
    terms_.clear();
    integer_terms_ = 0;
    {
      // Rounding upward for every interval filter of the sweep, set once (the exact fallbacks
      // are GMP integer arithmetic; nothing below rounds a plain double).
      CGAL::Protect_FPU_rounding<true> guard;
      for (std::size_t i = 0; i + 1 < first_.size(); ++i)
        if (!inside_[i]) measure_polygon(i);
    }
    boundary_ = nullptr;
    out = sum_terms();
    return true;
  }

  /// Twice the exact area of (the union of the polygons) n W, W the convex counter-clockwise
  /// polygon window[0, m), without clipping a polygon to W: a polygon edge counts the part of it
  /// inside W that no other polygon covers (a stretch along an edge of W going the same way is
  /// inside), a window edge the part that the interior of some polygon covers (so a stretch that
  /// a polygon's edge shares with W's, going the same way, counts once, as the polygon's).
  /// `boundary`: as twice_area's, the boundary of (union) n W reversed. False (nothing added)
  /// when some polygon or the window is not convex.
  bool twice_area_in_window(const QPoint2* points, const std::vector<std::size_t>& first, const QPoint2* window,
                            std::size_t m, EQ& out, BoundaryChain* boundary = nullptr) {
    struct WindowCall {  // the window's mode left on the way out, even by an exception (GMP's)
      ConvexUnionArea& u;
      ~WindowCall() { u.window_ = false; }
    } call{*this};
    bool convex_polygons = false;
    {
      CGAL::Protect_FPU_rounding<true> guard;
      convex_polygons = load(points, first) && load_window(window, m);
    }
    if (!convex_polygons) return false;
    boundary_ = boundary;
    find_pairs();
    terms_.clear();
    integer_terms_ = 0;
    {
      CGAL::Protect_FPU_rounding<true> guard;
      for (std::size_t i = 0; i + 1 < first_.size(); ++i)
        if (!inside_[i] && meet(box_[i], window_box_)) measure_polygon(i);  // (a polygon apart adds nothing)
      for (std::size_t v = win_first_; v < pts_.size(); ++v) measure_window_edge(v);
    }
    boundary_ = nullptr;
    out = sum_terms();
    return true;
  }

  /// Where only doubles rounded from the area are wanted (exact_faces.hpp, EnclosedMeasure), the
  /// partly covered edges of integer points (fractions of large denominators) are each divided
  /// out to kEnclosureBits binary places (rounded down, counting those not exact): no gcd. Twice
  /// the area is then enclosed: lo <= twice the area <= lo + slack 2^-kEnclosureBits.
  static constexpr int kEnclosureBits = 128;
  struct Enclosure {
    EQ lo;
    std::size_t slack = 0;
  };
  static_assert(sizeof(unsigned long) >= sizeof(std::size_t), "slacks pass through unsigned long (GMP, MPFR)");

  /// twice_area_in_window and twice_area, enclosed (no boundary); false (nothing set) as they.
  bool twice_area_in_window_enclosed(const QPoint2* points, const std::vector<std::size_t>& first,
                                     const QPoint2* window, std::size_t m, Enclosure& out) {
    const EnclosedCall call(*this);
    return finish_enclosure(twice_area_in_window(points, first, window, m, out.lo, nullptr), out);
  }
  bool twice_area_enclosed(const QPointList& points, const std::vector<std::size_t>& first, Enclosure& out) {
    const EnclosedCall call(*this);
    return finish_enclosure(twice_area(points.data(), first, out.lo, nullptr), out);
  }

  /// The same for Epeck polygons (their exact values are copied first).
  bool twice_area(const std::vector<Polygon2>& polygons, EQ& out) {
    copy_.clear();
    copy_first_.assign(1, 0);
    for (const Polygon2& polygon : polygons) {
      for (auto v = polygon.vertices_begin(); v != polygon.vertices_end(); ++v) {
        const auto& e = CGAL::exact(*v);
        copy_.push_back(QPoint2{e.x(), e.y()});
      }
      copy_first_.push_back(copy_.size());
    }
    return twice_area(copy_, copy_first_, out);
  }

  [[nodiscard]] const Counts& counts() const { return counts_; }
  /// Frees the scratch, sized by the largest union met, once it has room for over `pairs` pairs
  /// or polygons (a large union whose polygons lie apart across keeps few pairs).
  void shed(std::size_t pairs) {
    if (pair_a_.capacity() > pairs || box_.capacity() > pairs) *this = ConvexUnionArea();
  }

  /// From this many polygons on, those sharing an edge run both ways are merged where convex
  /// (merge_shared_edges); below it the hashing would cost more than it saves.
  static constexpr std::size_t kMergeFrom = 16;

 private:
  struct Box {
    double x0, y0, x1, y1;
  };
  [[nodiscard]] static bool meet(const Box& a, const Box& b) { return a.x0 <= b.x1 && b.x0 <= a.x1 && a.y0 <= b.y1 && b.y0 <= a.y1; }

  /// A parameter t on the current edge: 0, 1, or where the line of edge f (a vertex index)
  /// crosses the edge (exact value made on demand, in exact_[cache]).
  struct Param {
    int kind = 0;  ///< 0: t = 0; 1: t = 1; 2: crossing with edge f
    std::size_t f = 0;
    IA approx{0};
    int cache = -1;
  };
  struct Cover {
    Param lo, hi;
  };

  /// An enclosed call's mode, left on the way out even by an exception (an exact call after it
  /// must not enclose); and its end: lo (the exact terms' sum) += the enclosed terms' floors 2^-k.
  struct EnclosedCall {
    explicit EnclosedCall(ConvexUnionArea& u) : u_(u) {
      u_.enclose_ = true;
      u_.slack_ = 0;
      u_.enclosed_ = 0;
    }
    ~EnclosedCall() { u_.enclose_ = false; }
    ConvexUnionArea& u_;  // (a reference member: neither copied nor assigned)
  };
  bool finish_enclosure(bool done, Enclosure& out) {
    if (!done) return false;
    if (slack_ > 0 || sgn(enclosed_) != 0) {
      mpq_set_z(scratch_.a.get_mpq_t(), enclosed_.get_mpz_t());
      mpq_div_2exp(scratch_.a.get_mpq_t(), scratch_.a.get_mpq_t(), kEnclosureBits);
      out.lo += scratch_.a;
      scratch_.a = 0;
    }
    out.slack = slack_;
    return true;
  }

  // ---- loading: vertices without repeats, convexity checked exactly -----------------------------
  bool equal(std::size_t a, std::size_t b) const {
    const IPoint2& p = ip_[a];
    const IPoint2& q = ip_[b];
    if (compare(pts_[a]->x, p.x, pts_[b]->x, q.x) != 0) return false;
    return compare(pts_[a]->y, p.y, pts_[b]->y, q.y) == 0;
  }

  bool load(const QPoint2* points, const std::vector<std::size_t>& first) {
    pts_.clear();
    ip_.clear();
    nxt_.clear();
    first_.assign(1, 0);
    box_.clear();
    counts_ = Counts{};
    counts_.polygons = first.empty() ? 0 : first.size() - 1;
    for (std::size_t k = 0; k + 1 < first.size(); ++k) {
      Box b{};
      if (!append_ring(points + first[k], first[k + 1] - first[k], b)) return false;
      first_.push_back(pts_.size());
      box_.push_back(b);
    }
    if (first_.size() > kMergeFrom) merge_shared_edges();
    return true;
  }

  // ---- polygons sharing an edge run both ways, united where convex (geometry/shared_edge_merge.hpp)
  void merge_shared_edges() {
    CGAL::Protect_FPU_rounding<true> guard;  // turn()'s filters
    const std::size_t merges = merge_.run(
        nxt_, first_,
        [&](std::size_t v) { return geometry::SharedEdgeMerge::point_hash(ip_[v].x.inf(), ip_[v].y.inf()); },
        [&](std::size_t a, std::size_t b) { return equal(a, b); },
        [&](std::size_t p, std::size_t q, std::size_t r) { return left_or_straight(p, q, r); });
    if (merges == 0) return;
    counts_.merged = merges;
    // The points in the merged polygons' order.
    merged_pts_.clear();
    merged_ip_.clear();
    for (std::size_t v : merge_.order()) {
      merged_pts_.push_back(pts_[v]);
      merged_ip_.push_back(ip_[v]);
    }
    pts_.swap(merged_pts_);
    ip_.swap(merged_ip_);
    box_.clear();
    for (std::size_t i = 0; i + 1 < first_.size(); ++i) box_.push_back(ring_box(first_[i], first_[i + 1]));
  }

  /// The bounding box of vertices [begin, end) (their intervals).
  Box ring_box(std::size_t begin, std::size_t end) const {
    Box b{ip_[begin].x.inf(), ip_[begin].y.inf(), ip_[begin].x.sup(), ip_[begin].y.sup()};
    for (std::size_t v = begin + 1; v < end; ++v) {
      b.x0 = std::min(b.x0, ip_[v].x.inf());
      b.y0 = std::min(b.y0, ip_[v].y.inf());
      b.x1 = std::max(b.x1, ip_[v].x.sup());
      b.y1 = std::max(b.y1, ip_[v].y.sup());
    }
    return b;
  }

  /// Appends a polygon's n vertices (repeats dropped) with their next vertices, and sets its
  /// box; false when it is not convex.
  bool append_ring(const QPoint2* points, std::size_t n, Box& b) {
    const std::size_t start = pts_.size();
    for (std::size_t v = 0; v < n; ++v) {
      pts_.push_back(&points[v]);
      ip_.push_back(points[v].i);
      if (pts_.size() > start + 1 && equal(pts_.size() - 1, pts_.size() - 2)) {
        pts_.pop_back();
        ip_.pop_back();
      }
    }
    while (pts_.size() - start > 1 && equal(pts_.size() - 1, start)) {
      pts_.pop_back();
      ip_.pop_back();
    }
    if (!convex(start, pts_.size())) return false;
    for (std::size_t v = start; v < pts_.size(); ++v) nxt_.push_back(v + 1 == pts_.size() ? start : v + 1);
    b = ring_box(start, pts_.size());
    return true;
  }

  /// Appends the window's vertices after the polygons' (repeats dropped; not a polygon of
  /// first_ or box_), with its box; false when it is not convex.
  bool load_window(const QPoint2* window, std::size_t m) {
    win_first_ = pts_.size();
    if (!append_ring(window, m, window_box_)) return false;
    window_ = true;
    return true;
  }

  /// Only under one of twice_area's rounding guards (every caller is: load and the sweep).
  CGAL::Sign turn(std::size_t a, std::size_t b, std::size_t c) {
    return orientation<false>(*pts_[a], ip_[a], *pts_[b], ip_[b], *pts_[c], ip_[c], scratch_);
  }

  /// Whether p -> q -> r turns to the left or goes straight on (not back): convexity and the
  /// merge's junctions. Under a rounding guard, as turn.
  bool left_or_straight(std::size_t p, std::size_t q, std::size_t r) {
    const CGAL::Sign o = turn(p, q, r);
    if (o != CGAL::ZERO) return o == CGAL::POSITIVE;
    return dot_sign<false>(*pts_[p], ip_[p], *pts_[q], ip_[q], *pts_[q], ip_[q], *pts_[r], ip_[r], scratch_) ==
           CGAL::POSITIVE;
  }

  /// Whether vertices [a, b) (no two consecutive equal) make a convex polygon that winds once:
  /// every turn to the left or straight on, and the boundary winding once
  /// (geometry::XSignChanges: a pentagram turns left everywhere but winds twice). Exact predicates.
  bool convex(std::size_t a, std::size_t b) {
    const std::size_t n = b - a;
    if (n < 3) return false;
    geometry::XSignChanges winding;
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t p = a + k, q = a + (k + 1) % n, r = a + (k + 2) % n;
      if (!left_or_straight(p, q, r)) return false;  // a right turn, or a spike back
      winding.add(compare(pts_[q]->x, ip_[q].x, pts_[p]->x, ip_[p].x));
    }
    return winding.winds_once();
  }

  // ---- neighbours: polygon pairs whose boxes meet, not apart across (exact/union_across.hpp) ----
  void find_pairs() {
    const std::size_t n = box_.size();
    pair_a_.clear();
    pair_b_.clear();
    across_extents(ip_, nxt_, first_, across_);
    geometry::sweep_across<true>(box_, across_, sorted_, [&](std::size_t later, std::size_t earlier) {
      pair_a_.push_back(later);
      pair_b_.push_back(earlier);
    });
    counts_.pairs = pair_a_.size();
    geometry::neighbour_lists(pair_a_, pair_b_, n, nstart_, nlist_, fill_);
    separator_.resize(nlist_.size());
    for (std::size_t k = 0; k < nlist_.size(); ++k) separator_[k] = first_[nlist_[k]];
    inside_.assign(n, 0);
    if (!boundary_) find_inside();
  }

  /// Areas only (no boundary asked for; it would be split at other vertices): a polygon inside
  /// another (in a window, its part in the window) adds nothing to the union, so it is neither
  /// measured nor a cover. Each is left out by a pair with one that is not (yet): it lies in one
  /// that stays, and the union is the same point set, so twice its area is the same rational.
  void find_inside() {
    CGAL::Protect_FPU_rounding<true> guard;  // the filters of turn() and of the corners' sides
    // Boxes first (the interval boxes: where they do not nest, a polygon is only left in), then
    // every vertex of `inner` on the left of, or on, every edge of `outer`. In a window, else,
    // the corners of the box where inner's and the window's boxes meet (it holds inner's part
    // in the window), certainly by the intervals alone (the exact points may be scaled).
    auto lies_in = [&](std::size_t inner, std::size_t outer) {
      const Box &i = box_[inner], &o = box_[outer], &w = window_box_;
      bool in = o.x0 <= i.x0 && i.x1 <= o.x1 && o.y0 <= i.y0 && i.y1 <= o.y1;
      for (std::size_t f = first_[outer]; in && f < first_[outer + 1]; ++f)
        for (std::size_t v = first_[inner]; in && v < first_[inner + 1]; ++v) in = turn(f, nxt_[f], v) != CGAL::NEGATIVE;
      if (in || !window_) return in;
      const Box c{std::max(i.x0, w.x0), std::max(i.y0, w.y0), std::min(i.x1, w.x1), std::min(i.y1, w.y1)};
      if (!(c.x0 <= c.x1 && c.y0 <= c.y1) || c.x0 < o.x0 || o.x1 < c.x1 || c.y0 < o.y0 || o.y1 < c.y1) return false;
      for (std::size_t f = first_[outer]; f < first_[outer + 1]; ++f)
        for (int corner = 0; corner < 4; ++corner) {
          const IPoint2 &p = ip_[f], &q = ip_[nxt_[f]];
          const IA x(corner & 1 ? c.x1 : c.x0), y(corner & 2 ? c.y1 : c.y0);
          const CGAL::Uncertain<CGAL::Sign> side = CGAL::sign((q.x - p.x) * (y - p.y) - (q.y - p.y) * (x - p.x));
          if (!CGAL::is_certain(side) || CGAL::get_certain(side) == CGAL::NEGATIVE) return false;
        }
      return true;
    };
    for (std::size_t k = 0; k < pair_a_.size(); ++k) {
      const std::size_t a = pair_a_[k], b = pair_b_[k];
      if (inside_[a] || inside_[b]) continue;
      const bool a_in_b = lies_in(a, b), b_in_a = lies_in(b, a);
      if (a_in_b || b_in_a) {
        inside_[a_in_b && b_in_a ? std::max(a, b) : a_in_b ? a : b] = 1;
        ++counts_.inside;
      }
    }
  }

  // ---- one polygon's edges ----------------------------------------------------------------------
  void measure_polygon(std::size_t i) {
    if (nstart_[i] == nstart_[i + 1] && !window_) {  // alone: its own area
      twice_polygon_area(pts_.data() + first_[i], first_[i + 1] - first_[i]);
      if (boundary_)
        for (std::size_t v = first_[i]; v < first_[i + 1]; ++v) add_reversed(*pts_[v], *pts_[nxt_[v]]);
      return;
    }
    constexpr std::size_t kNone = ~std::size_t{0};
    std::size_t coverer = kNone;  // the nlist_ entry that covered an earlier edge whole
    for (std::size_t v = first_[i]; v < first_[i + 1]; ++v) {
      const std::size_t w = nxt_[v];
      const Box eb{std::min(ip_[v].x.inf(), ip_[w].x.inf()), std::min(ip_[v].y.inf(), ip_[w].y.inf()),
                   std::max(ip_[v].x.sup(), ip_[w].x.sup()), std::max(ip_[v].y.sup(), ip_[w].y.sup())};
      covers_.clear();
      bool full = false;
      exact_used_ = 0;  // parameters are per edge
      cur_v_ = v;
      cur_w_ = w;
      if (window_) {  // the parts outside the window count as covered
        Cover inside;
        const int in = window_interval(inside);
        if (in == 0) continue;
        if (in == 2) {
          if (inside.lo.kind == 2) covers_.push_back(Cover{Param{}, inside.lo});
          if (inside.hi.kind == 2) {
            Cover after{inside.hi, Param{}};
            after.hi.kind = 1;
            after.hi.approx = IA(1);
            covers_.push_back(after);
          }
        }
      }
      // First the neighbour that covered the last edge whole, then those whose boxes hold the
      // edge's box, then the rest (a third of the edges are covered whole by one neighbour).
      // The outcome does not depend on the order (equal ends are the same values).
      const auto holds = [&](const Box& c) { return c.x0 <= eb.x0 && c.y0 <= eb.y0 && eb.x1 <= c.x1 && eb.y1 <= c.y1; };
      const auto test = [&](std::size_t k) {
        const std::size_t j = nlist_[k];
        if (inside_[j] || !meet(eb, box_[j])) return;
        Cover c;
        if (!cover_by(i, j, c, separator_[k])) return;
        if (c.lo.kind == 0 && c.hi.kind == 1) {
          full = true;
          coverer = k;
        } else {
          covers_.push_back(c);
        }
      };
      const std::size_t first_tested = coverer;
      if (first_tested != kNone) test(first_tested);
      bool any_held = false;
      for (std::size_t k = nstart_[i]; k < nstart_[i + 1] && !full; ++k)
        if (k != first_tested && holds(box_[nlist_[k]])) {
          any_held = true;
          test(k);
        }
      for (std::size_t k = nstart_[i]; k < nstart_[i + 1] && !full; ++k)
        if (k != first_tested && !(any_held && holds(box_[nlist_[k]]))) test(k);
      if (full) continue;
      if (covers_.empty()) {
        add_cross(v, w, nullptr);
        if (boundary_) add_reversed(*pts_[v], *pts_[w]);
        continue;
      }
      ++counts_.edges_partial;
      uncovered_measure(v, w);
    }
  }

  /// The part of the current (polygon) edge inside the window: 0 none (up to points), 1 all of
  /// it, 2 the interval from `c.lo` to `c.hi` (either may be an end of the edge). A stretch on a
  /// window edge's line going the same way is inside, the other way outside.
  int window_interval(Cover& c) {
    const std::size_t v = cur_v_, w = cur_w_;
    c.lo = Param{};
    c.hi = Param{};
    c.hi.kind = 1;
    c.hi.approx = IA(1);
    for (std::size_t f = win_first_; f < pts_.size(); ++f) {
      const std::size_t f2 = nxt_[f];
      const CGAL::Sign a = turn(f, f2, v), b = turn(f, f2, w);
      if (a != CGAL::NEGATIVE && b != CGAL::NEGATIVE) {
        if (a != CGAL::ZERO || b != CGAL::ZERO) continue;
        // On the edge's line: inside when going the same way.
        if (dot_sign<false>(*pts_[v], ip_[v], *pts_[w], ip_[w], *pts_[f], ip_[f], *pts_[f2], ip_[f2], scratch_) ==
            CGAL::POSITIVE)
          continue;
        return 0;
      }
      if (a != CGAL::POSITIVE && b != CGAL::POSITIVE) return 0;  // outside but for an end
      if (a == CGAL::POSITIVE) {  // inside for t < tau
        Param p = crossing(f);
        if (c.hi.kind == 1 || less(p, c.hi)) c.hi = p;
      } else {  // inside for t > tau
        Param p = crossing(f);
        if (c.lo.kind == 0 || less(c.lo, p)) c.lo = p;
      }
    }
    if (c.lo.kind == 0 && c.hi.kind == 1) return 1;
    if (c.lo.kind == 2 && c.hi.kind == 2 && !less(c.lo, c.hi)) return 0;
    return 2;
  }

  /// A window edge: the part that the polygons' interiors cover (the union's boundary along the
  /// window), reversed into the boundary chain.
  void measure_window_edge(std::size_t v) {
    const std::size_t w = nxt_[v];
    const Box eb{std::min(ip_[v].x.inf(), ip_[w].x.inf()), std::min(ip_[v].y.inf(), ip_[w].y.inf()),
                 std::max(ip_[v].x.sup(), ip_[w].x.sup()), std::max(ip_[v].y.sup(), ip_[w].y.sup())};
    covers_.clear();
    exact_used_ = 0;
    cur_v_ = v;
    cur_w_ = w;
    for (std::size_t j = 0; j + 1 < first_.size(); ++j) {
      if (inside_[j] || !meet(eb, box_[j])) continue;
      Cover c;
      std::size_t from = first_[j];
      if (!cover_by(0, j, c, from)) continue;  // (i = 0: a collinear edge going the same way does not cover)
      if (c.lo.kind == 0 && c.hi.kind == 1) {
        add_cross(v, w, nullptr);
        if (boundary_) add_reversed(*pts_[v], *pts_[w]);
        return;
      }
      covers_.push_back(c);
    }
    if (covers_.empty()) return;
    ++counts_.edges_partial;
    uncovered_measure(v, w, true);
  }

  /// The open interval of t that P_j covers on the current edge of P_i; false when it is empty.
  /// `from`: the edge of P_j to test first, and the edge that separated P_j from the current
  /// edge where one did (not where the bounds met empty). Consecutive edges of P_i are mostly
  /// kept apart from P_j by the same edge of it, so starting there ends most empty calls (three
  /// quarters of them) at the first edge tested. The result does not depend on the order: empty
  /// when some edge separates, else the largest lower and the smallest upper bound (equal
  /// candidates are the same value).
  bool cover_by(std::size_t i, std::size_t j, Cover& c, std::size_t& from) {
    const std::size_t v = cur_v_, w = cur_w_;
    c.lo = Param{};
    c.lo.kind = 0;
    c.hi = Param{};
    c.hi.kind = 1;
    c.hi.approx = IA(1);
    for (std::size_t n = first_[j + 1] - first_[j], f = from; n > 0; --n, f = nxt_[f]) {
      const std::size_t f2 = nxt_[f];
      const CGAL::Sign a = turn(f, f2, v), b = turn(f, f2, w);
      if (a == CGAL::POSITIVE && b == CGAL::POSITIVE) continue;
      if (a != CGAL::POSITIVE && b != CGAL::POSITIVE) {
        // Both on or outside f's line: nothing covered unless the edge lies on f's line going the
        // same way, and P_j comes first (then f's closed side is the constraint, and it holds).
        if (a == CGAL::ZERO && b == CGAL::ZERO && j < i &&
            dot_sign<false>(*pts_[v], ip_[v], *pts_[w], ip_[w], *pts_[f], ip_[f], *pts_[f2], ip_[f2], scratch_) == CGAL::POSITIVE)
          continue;
        from = f;
        return false;
      }
      if (a == CGAL::POSITIVE) {  // t < tau (tau = 1 when b is zero: no constraint in (0, 1))
        if (b == CGAL::ZERO) continue;
        Param p = crossing(f);
        if (c.hi.kind == 1 || less(p, c.hi)) c.hi = p;
      } else {  // t > tau
        if (a == CGAL::ZERO) continue;
        Param p = crossing(f);
        if (c.lo.kind == 0 || less(c.lo, p)) c.lo = p;
      }
    }
    if (c.lo.kind == 0 || c.hi.kind == 1) return true;  // tau is strictly inside (0, 1)
    return less(c.lo, c.hi);
  }

  /// Where the line of edge f (f -> next) crosses the current edge s -> s2:
  /// t = cross(fd, u - s) / cross(fd, s2 - s), strictly inside (0, 1).
  Param crossing(std::size_t f) {
    Param p;
    p.kind = 2;
    p.f = f;
    const IPoint2& s = ip_[cur_v_];
    const IPoint2& s2 = ip_[cur_w_];
    const IPoint2& u = ip_[f];
    const IPoint2& u2 = ip_[nxt_[f]];  // (rounding upward: twice_area's guard)
    const IA fx = u2.x - u.x, fy = u2.y - u.y;
    const IA num = fx * (u.y - s.y) - fy * (u.x - s.x);
    const IA den = fx * (s2.y - s.y) - fy * (s2.x - s.x);
    IA t(0, 1);
    if (!CGAL::possibly(den == IA(0))) t = num / den;
    p.approx = IA(std::max(t.inf(), 0.0), std::min(t.sup(), 1.0));
    return p;
  }

  /// A parameter as a fraction n / d with d > 0, not normalised: it is compared and subtracted,
  /// and only the edge's uncovered measure is normalised (once), so no gcd is taken per
  /// parameter (mpq_canonicalize's gcds were most of the union's GMP time).
  struct Fraction {
    mpz_class n, d;
  };

  /// The exact value of a parameter (on the current edge), made once and kept in exact_.
  const Fraction& fraction(Param& p) {
    if (p.kind == 0) return zero_f_;
    if (p.kind == 1) return one_f_;
    if (p.cache >= 0) return exact_[static_cast<std::size_t>(p.cache)];
    if (exact_used_ == exact_.size()) exact_.emplace_back();
    Fraction& t = exact_[exact_used_];
    p.cache = static_cast<int>(exact_used_++);
    const QPoint2& s = *pts_[cur_v_];
    const QPoint2& s2 = *pts_[cur_w_];
    const QPoint2& u = *pts_[p.f];
    const QPoint2& u2 = *pts_[nxt_[p.f]];
    ++counts_.exact_params;
    crossing_parameter(s, s2, u, u2, t.n.get_mpz_t(), t.d.get_mpz_t(), scratch_, f_);
    return t;
  }
  /// p < q for two parameters on the current edge.
  bool less(Param& p, Param& q) {
    if (p.kind != 2 || q.kind != 2) {
      const int kp = p.kind == 2 ? 1 : (p.kind == 0 ? 0 : 2), kq = q.kind == 2 ? 1 : (q.kind == 0 ? 0 : 2);
      return kp < kq;  // 0 < (0, 1) < 1
    }
    if (p.f == q.f) return false;
    const CGAL::Uncertain<bool> r = p.approx < q.approx;  // comparisons only: no rounding
    if (CGAL::is_certain(r)) return CGAL::get_certain(r);
    const Fraction& a = fraction(p);
    const Fraction& b = fraction(q);
    mpz_mul(scratch_.za.get_mpz_t(), a.n.get_mpz_t(), b.d.get_mpz_t());
    mpz_mul(scratch_.zb.get_mpz_t(), b.n.get_mpz_t(), a.d.get_mpz_t());
    return mpz_cmp(scratch_.za.get_mpz_t(), scratch_.zb.get_mpz_t()) < 0;
  }

  void twice_polygon_area(const QPoint2* const* pts, std::size_t n) {
    if (std::all_of(pts, pts + n, [](const QPoint2* p) { return is_integer(*p); })) {
      for (std::size_t a = 0; a < n; ++a) add_integer_cross(integer_terms_, *pts[a], *pts[(a + 1) % n]);
      return;
    }
    terms_.emplace_back(0);
    EQ& out = terms_.back();
    for (std::size_t a = 0; a < n; ++a) {
      const QPoint2& p = *pts[a];
      const QPoint2& q = *pts[(a + 1) % n];
      scratch_.a = p.x * q.y;
      scratch_.b = p.y * q.x;
      scratch_.a -= scratch_.b;
      out += scratch_.a;
    }
  }

  /// Adds cross(s, s2) * measure to the sum (measure null: the whole edge).
  void add_cross(std::size_t v, std::size_t w, const EQ* measure) {
    const QPoint2& s = *pts_[v];
    const QPoint2& s2 = *pts_[w];
    if (!measure && is_integer(s) && is_integer(s2)) {  // a whole edge of integer points
      add_integer_cross(integer_terms_, s, s2);
      return;
    }
    terms_.emplace_back(s.x * s2.y);
    scratch_.a = s.y * s2.x;
    terms_.back() -= scratch_.a;
    if (measure) terms_.back() *= *measure;
  }

  /// The edge's uncovered measure from covers_ (sorted by lower end, merged), times cross(s, d);
  /// with `covered_part`, the covered measure instead (a window edge), its pieces to the chain.
  void uncovered_measure(std::size_t v, std::size_t w, bool covered_part = false) {
    for (std::size_t a = 1; a < covers_.size(); ++a)  // insertion sort by lower end (few)
      for (std::size_t b = a; b > 0 && less(covers_[b].lo, covers_[b - 1].lo); --b) std::swap(covers_[b], covers_[b - 1]);
    // The covered measure as a fraction cn / cd (cd > 0), normalised once at the end.
    mpz_ptr cn = mpq_numref(measure_.get_mpq_t());
    mpz_ptr cd = mpq_denref(measure_.get_mpq_t());
    mpz_set_ui(cn, 0);
    mpz_set_ui(cd, 1);
    mpz_ptr z = g_.get_mpz_t();
    merged_.clear();
    std::size_t a = 0;
    while (a < covers_.size()) {
      Param lo = covers_[a].lo, hi = covers_[a].hi;
      std::size_t b = a + 1;
      // Open intervals (lo, hi) and (lo', hi') with lo <= lo' merge when lo' < hi; when lo' ==
      // hi a single point is left out, which has no measure: merging then changes nothing.
      while (b < covers_.size() && !less(hi, covers_[b].lo)) {
        if (less(hi, covers_[b].hi)) hi = covers_[b].hi;
        ++b;
      }
      const Fraction& h = fraction(hi);
      const Fraction& l = fraction(lo);
      if (boundary_) merged_.push_back(Cover{lo, hi});  // (their exact values made: cached)
      // cn / cd += h - l = (hn ld - ln hd) / (hd ld)
      mpz_mul(z, h.n.get_mpz_t(), l.d.get_mpz_t());
      mpz_submul(z, l.n.get_mpz_t(), h.d.get_mpz_t());
      mpz_mul(z, z, cd);
      mpz_mul(cn, cn, h.d.get_mpz_t());
      mpz_mul(cn, cn, l.d.get_mpz_t());
      mpz_add(cn, cn, z);
      mpz_mul(cd, cd, h.d.get_mpz_t());
      mpz_mul(cd, cd, l.d.get_mpz_t());
      a = b;
    }
    // measure = 1 - covered = (cd - cn) / cd.
    if (!covered_part) mpz_sub(cn, cd, cn);
    if (mpz_sgn(cn) != 0) {
      const QPoint2& s = *pts_[v];
      const QPoint2& s2 = *pts_[w];
      if (is_integer(s) && is_integer(s2) && enclose_) {
        // floor(cross(s, s2) cn 2^k / cd) summed, a unit of slack unless exact: in [q, q + 1) 2^-k.
        g_ = 0;
        add_integer_cross(g_, s, s2);  // (z is g_)
        mpz_mul(z, z, cn);
        mpz_mul_2exp(z, z, kEnclosureBits);
        mpz_fdiv_qr(enclosed_q_.get_mpz_t(), z, z, cd);
        enclosed_ += enclosed_q_;
        if (mpz_sgn(z) != 0) ++slack_;
      } else if (is_integer(s) && is_integer(s2)) {
        // cross(s, s2) cn / cd made canonical once (normalising the measure first and then
        // multiplying by the cross, as below, takes two gcds).
        terms_.emplace_back();
        mpq_ptr term = terms_.back().get_mpq_t();
        g_ = 0;
        add_integer_cross(g_, s, s2);  // (z is g_)
        mpz_mul(mpq_numref(term), z, cn);
        mpz_set(mpq_denref(term), cd);
        mpq_canonicalize(term);
      } else {
        mpq_canonicalize(measure_.get_mpq_t());
        add_cross(v, w, &measure_);
      }
    }
    if (!boundary_) return;
    if (!covered_part) return add_uncovered_pieces();
    for (Cover& c : merged_)
      if (less(c.lo, c.hi)) add_piece(c.lo, c.hi);
  }

  /// The current edge's uncovered pieces, between the merged covers (merged_), reversed into
  /// the boundary chain. A piece of no length (a cover from t = 0, touching covers) is left out.
  void add_uncovered_pieces() {
    Param prev;  // t = 0
    for (Cover& c : merged_) {
      if (less(prev, c.lo)) add_piece(prev, c.lo);
      prev = c.hi;
    }
    Param end;
    end.kind = 1;
    if (less(prev, end)) add_piece(prev, end);
  }

  void add_piece(Param& from, Param& to) {
    point_at(from, piece_a_);
    point_at(to, piece_b_);
    boundary_->add(piece_b_, piece_a_);
  }

  /// s + t (s2 - s) on the current edge s -> s2, exactly.
  void point_at(Param& p, BoundaryChain::Point& out) {
    const QPoint2& s = *pts_[cur_v_];
    const QPoint2& s2 = *pts_[cur_w_];
    if (p.kind != 2) {
      out.x = p.kind == 0 ? s.x : s2.x;
      out.y = p.kind == 0 ? s.y : s2.y;
      return;
    }
    const Fraction& t = fraction(p);
    mpq_set_num(tq_.get_mpq_t(), t.n.get_mpz_t());
    mpq_set_den(tq_.get_mpq_t(), t.d.get_mpz_t());
    mpq_canonicalize(tq_.get_mpq_t());
    out.x = s2.x - s.x;
    out.x *= tq_;
    out.x += s.x;
    out.y = s2.y - s.y;
    out.y *= tq_;
    out.y += s.y;
  }

  void add_reversed(const QPoint2& s, const QPoint2& s2) { boundary_->add(s2.x, s2.y, s.x, s.y); }

  EQ sum_terms() {
    EQ total(integer_terms_);
    if (terms_.empty()) return total;
    for (std::size_t width = 1; width < terms_.size(); width *= 2)
      for (std::size_t a = 0; a + width < terms_.size(); a += 2 * width) terms_[a] += terms_[a + width];
    return total += terms_[0];
  }

  std::vector<const QPoint2*> pts_;
  std::vector<IPoint2> ip_;
  std::vector<std::size_t> nxt_;    ///< the next vertex around the same polygon
  std::vector<std::size_t> first_;  ///< polygon i: vertices [first_[i], first_[i + 1])
  std::vector<Box> box_;
  std::vector<std::pair<double, double>> across_;  ///< per polygon: its extent across (union_across.hpp)
  std::vector<geometry::AcrossSweepEntry<Box>> sorted_;
  std::vector<std::size_t> pair_a_, pair_b_, nstart_, nlist_, fill_;
  std::vector<char> inside_;  ///< per polygon: left out, inside another (find_inside)
  std::vector<std::size_t> separator_;  ///< per nlist_ entry: the neighbour's edge cover_by tests first
  geometry::SharedEdgeMerge merge_;
  std::vector<const QPoint2*> merged_pts_;  ///< merge_shared_edges' scratch
  std::vector<IPoint2> merged_ip_;
  std::vector<Cover> covers_;
  std::vector<Cover> merged_;  ///< the current edge's covers merged (boundary_ only)
  BoundaryChain* boundary_ = nullptr;
  bool window_ = false;         ///< twice_area_in_window: the window's vertices from win_first_
  std::size_t win_first_ = 0;
  Box window_box_{0, 0, 0, 0};
  BoundaryChain::Point piece_a_, piece_b_;
  EQ tq_;
  std::deque<Fraction> exact_;  ///< exact parameters of the current edge (references stay valid)
  std::vector<EQ> terms_;
  std::vector<QPoint2> copy_;
  std::vector<std::size_t> copy_first_;
  std::size_t exact_used_ = 0, cur_v_ = 0, cur_w_ = 0;
  EQ measure_;
  Fraction zero_f_{0, 1}, one_f_{1, 1};
  ParameterScratch f_;   ///< fraction()'s scratch
  mpz_class g_;          ///< uncovered_measure()'s
  mpz_class integer_terms_;  ///< terms of whole edges of integer points, summed as integers
  bool enclose_ = false;     ///< twice_area_in_window_enclosed's call: partly covered edges enclosed
  mpz_class enclosed_, enclosed_q_;  ///< their terms' floors times 2^kEnclosureBits, summed; scratch
  std::size_t slack_ = 0;            ///< how many of those floors were not exact
  QScratch scratch_;
  Counts counts_;
};

}  // namespace shadow::exact
