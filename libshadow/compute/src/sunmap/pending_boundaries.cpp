// SPDX-License-Identifier: GPL-3.0-or-later
// A strip's pending boundaries filed by tile (pending_boundaries.hpp). Everything is in doubles
// with a margin far beyond their rounding, and every doubt answers "not known", which leaves the
// tiles' own bound as it was: a box counts as dark or lit whole under an instant only when no
// segment of that instant comes within the margin of it, and the segment nearest its centre is
// certainly the nearest of them all and is met at a point well inside it.
#include "sunmap/pending_boundaries.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace shadow::sunmap {
namespace {

constexpr double kRound = 4.0 * std::numeric_limits<double>::epsilon();

/// Whether segment a-b meets the box [x0, x1] x [y0, y1] (closed).
bool meets_box(double xa, double ya, double xb, double yb, double x0, double x1, double y0, double y1) {
  if (std::max(xa, xb) < x0 || std::min(xa, xb) > x1 || std::max(ya, yb) < y0 || std::min(ya, yb) > y1) return false;
  // Within the box's bounds on both axes: it meets the box unless all four corners lie strictly
  // on one side of its line.
  const double dx = xb - xa, dy = yb - ya;
  const auto side = [&](double x, double y) { return dx * (y - ya) - dy * (x - xa); };
  const double s[4] = {side(x0, y0), side(x1, y0), side(x1, y1), side(x0, y1)};
  const bool all_left = s[0] > 0 && s[1] > 0 && s[2] > 0 && s[3] > 0;
  const bool all_right = s[0] < 0 && s[1] < 0 && s[2] < 0 && s[3] < 0;
  return !all_left && !all_right;
}

/// `filed` (tile, value) pairs as per-tile lists: `start` (tiles + 1 offsets) into `values`,
/// each tile's values in the order filed.
void file_by_tile(const std::vector<std::pair<std::uint32_t, std::uint32_t>>& filed, std::size_t tiles,
                  std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& values) {
  start.assign(tiles + 1, 0);
  for (const auto& [t, v] : filed) ++start[t + 1];
  for (std::size_t t = 0; t < tiles; ++t) start[t + 1] += start[t];
  values.resize(filed.size());
  std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
  for (const auto& [t, v] : filed) values[next[t]++] = v;
}

}  // namespace

void PendingBoundaries::build(const FaceTiles& tiles, std::size_t c0, std::size_t c1, bool whole_strip, double x0,
                              double x1, const std::vector<std::pair<std::size_t, const std::vector<XCurve>*>>& order,
                              const std::vector<double>& hours) {
  std::vector<std::size_t> instants;
  std::vector<RoughSegment> segments;
  for (const auto& [instant, curves] : order) {
    instants.push_back(instant);
    for (const XCurve& c : *curves) {
      segments.push_back(rough_segment(c));
      segments.back().instant = static_cast<std::uint32_t>(instant);  // the order's, whatever the tag
    }
  }
  std::vector<std::size_t> which(segments.size());
  for (std::size_t k = 0; k < which.size(); ++k) which[k] = k;
  build(tiles, c0, c1, whole_strip, x0, x1, instants, segments, which, hours);
}

void PendingBoundaries::build(const FaceTiles& tiles, std::size_t c0, std::size_t c1, bool whole_strip, double x0,
                              double x1, const std::vector<std::size_t>& order,
                              const std::vector<RoughSegment>& segments, const std::vector<std::size_t>& which,
                              const std::vector<double>& hours) {
  const TileGrid& g = tiles.grid;
  if (g.n == 0 || c1 < c0) return;
  tiles_ = &tiles;
  c0_ = c0, c1_ = c1, whole_strip_ = whole_strip, x0_ = x0, x1_ = x1, walked_ = 0;
  const std::size_t n = g.n, count = (c1 - c0 + 1) * n;
  margin_ = 1e-9 * (std::fabs(g.x0) + std::fabs(g.y0) + static_cast<double>(n) * (g.dx + g.dy));
  const double m = margin_;

  // The segments, and the tiles each passes through: row by row, the part of the segment in the
  // row's band (widened by the margin) gives its columns (widened again). Where the band's y
  // meets a segment that is nearly horizontal, the x found there is off by the rounding of the
  // y difference over the segment's slope: that is added to the width.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> filed;  // (tile, segment)
  segments_.clear();
  // The segments by the position of their instant in the order (ids then ascend by position);
  // those of instants not in it, or of no weight (never counted), are left out.
  std::vector<std::uint32_t> position_of(hours.size(), UINT32_MAX);
  for (std::size_t p = 0; p < order.size(); ++p)
    if (hours[order[p]] > 0) position_of[order[p]] = static_cast<std::uint32_t>(p);
  std::vector<std::pair<std::uint32_t, std::size_t>> by_position;  // (position, segment)
  by_position.reserve(which.size());
  for (std::size_t k : which)
    if (position_of[segments[k].instant] != UINT32_MAX) by_position.emplace_back(position_of[segments[k].instant], k);
  std::stable_sort(by_position.begin(), by_position.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  segments_.reserve(by_position.size());
  for (const auto& [position, k] : by_position) {
    const RoughSegment& rough = segments[k];
    Segment s;
    s.xa = rough.xa, s.ya = rough.ya, s.xb = rough.xb, s.yb = rough.yb;
    s.position = position;
    s.left = rough.left;
    const auto id = static_cast<std::uint32_t>(segments_.size());
    segments_.push_back(s);
    const double ylo = std::min(s.ya, s.yb), yhi = std::max(s.ya, s.yb), dy = s.yb - s.ya, dx = s.xb - s.xa;
    const double slack = dy == 0 ? 0 : kRound * (std::fabs(s.ya) + std::fabs(s.yb) + yhi - ylo + m) / std::fabs(dy);
    for (std::size_t r = g.row(ylo - m), r1 = g.row(yhi + m); r <= r1; ++r) {
      double ua = 0, ub = 1;  // the part of the segment in the row's band, as parameters
      if (dy != 0) {
        const double lo = r == 0 ? -HUGE_VAL : g.y0 + static_cast<double>(r) * g.dy - m;
        const double hi = r + 1 == n ? HUGE_VAL : g.y0 + static_cast<double>(r + 1) * g.dy + m;
        double u0 = (lo - s.ya) / dy, u1 = (hi - s.ya) / dy;
        if (u0 > u1) std::swap(u0, u1);
        ua = std::max(0.0, u0 - slack), ub = std::min(1.0, u1 + slack);
        if (ua > ub) continue;
      }
      const double xu = s.xa + ua * dx, xv = s.xa + ub * dx;
      const double reach = m + kRound * (std::fabs(s.xa) + std::fabs(dx));
      const std::size_t ca = std::max(c0, g.column(std::min(xu, xv) - reach));
      const std::size_t cb = std::min(c1, g.column(std::max(xu, xv) + reach));
      for (std::size_t c = ca; c <= cb; ++c) filed.emplace_back(static_cast<std::uint32_t>(at(c, r)), id);
    }
  }
  file_by_tile(filed, count, segment_start_, segment_ids_);  // ids ascend within a tile

  // Per tile, the positions its masks leave undecided: may light it, not surely whole.
  filed.clear();
  for (std::size_t p = 0; p < order.size(); ++p) {
    const std::size_t slot = tiles.slot(order[p]);
    if (slot == SIZE_MAX || !(hours[order[p]] > 0)) continue;
    for (std::size_t c = c0; c <= c1; ++c)
      for (std::size_t r = 0; r < n; ++r)
        if (tiles.lit(slot, r * n + c) && !tiles.lit_whole(slot, r * n + c))
          filed.emplace_back(static_cast<std::uint32_t>(at(c, r)), static_cast<std::uint32_t>(p));
  }
  file_by_tile(filed, count, undecided_start_, undecided_positions_);  // positions ascend within a tile
}

std::uint32_t PendingBoundaries::undecided(std::size_t c, std::size_t r) const {
  const std::size_t t = at(c, r);
  const auto first = undecided_positions_.begin() + undecided_start_[t];
  const auto last = undecided_positions_.begin() + undecided_start_[t + 1];
  return static_cast<std::uint32_t>(last - std::lower_bound(first, last, static_cast<std::uint32_t>(walked_)));
}

PendingBoundaries::Refined PendingBoundaries::refine(std::size_t c, std::size_t r, double xmin, double xmax,
                                                     double ymin, double ymax, std::uint32_t want_dark,
                                                     std::uint32_t want_lit) const {
  Refined out;
  const TileGrid& g = tiles_->grid;
  const std::size_t n = g.n, t = at(c, r);
  const double m = margin_;
  // The sides of tiles [ca, cb] x [ra, rb]: a tile on the grid's edge reaches beyond it (segments
  // there are filed under it), and a strip's curves end at its sides.
  const auto sides = [&](std::size_t ca, std::size_t cb, std::size_t ra, std::size_t rb) {
    std::array<double, 4> b{ca == 0 ? -HUGE_VAL : g.x0 + static_cast<double>(ca) * g.dx,
                            cb + 1 == n ? HUGE_VAL : g.x0 + static_cast<double>(cb + 1) * g.dx,
                            ra == 0 ? -HUGE_VAL : g.y0 + static_cast<double>(ra) * g.dy,
                            rb + 1 == n ? HUGE_VAL : g.y0 + static_cast<double>(rb + 1) * g.dy};
    if (!whole_strip_) b[0] = std::max(b[0], x0_), b[1] = std::min(b[1], x1_);
    return b;
  };
  const std::array<double, 4> tile = sides(c, c, r, r);
  // The part of the box under the tile (widened by the margin for the test of meeting it).
  const double bx0 = std::max(xmin, tile[0]), bx1 = std::min(xmax, tile[1]), by0 = std::max(ymin, tile[2]),
               by1 = std::min(ymax, tile[3]);
  if (!(bx0 <= bx1) || !(by0 <= by1)) return out;
  const double cx = 0.5 * (bx0 + bx1), cy = 0.5 * (by0 + by1);
  // A disc about the centre within `room` lies in the tile (or within `block_room` in the tiles
  // around it, and the strip): every segment meeting it is filed there.
  const auto room_in = [&](const std::array<double, 4>& b) {
    return std::min({cx - b[0], b[1] - cx, cy - b[2], b[3] - cy});
  };
  const double room = room_in(tile);
  const std::size_t ca = c == c0_ ? c : c - 1, cb = c == c1_ ? c : c + 1, ra = r == 0 ? r : r - 1,
                    rb = r + 1 == n ? r : r + 1;
  const double block_room = room_in(sides(ca, cb, ra, rb));

  const auto walked = static_cast<std::uint32_t>(walked_);
  const auto by_position = [&](std::uint32_t id, std::uint32_t p) { return segments_[id].position < p; };
  const std::uint32_t* seg = segment_ids_.data() + segment_start_[t];
  const std::uint32_t* seg_last = segment_ids_.data() + segment_start_[t + 1];
  const std::uint32_t* pos = undecided_positions_.data() + undecided_start_[t];
  const std::uint32_t* pos_last = undecided_positions_.data() + undecided_start_[t + 1];
  pos = std::lower_bound(pos, pos_last, walked);
  seg = std::lower_bound(seg, seg_last, walked, by_position);
  for (; pos != pos_last; ++pos) {
    const std::uint32_t p = *pos;
    while (seg != seg_last && segments_[*seg].position < p) ++seg;
    const std::uint32_t* own = seg;
    while (seg != seg_last && segments_[*seg].position == p) ++seg;
    // The nearest segment to the centre (and the distance of the next other one).
    double best = HUGE_VAL, second = HUGE_VAL, best_u = 0;
    std::uint32_t best_id = UINT32_MAX;
    const auto look = [&](std::uint32_t id) {
      if (id == best_id) return;
      const Segment& s = segments_[id];
      const double dx = s.xb - s.xa, dy = s.yb - s.ya, len2 = dx * dx + dy * dy;
      const double u = len2 > 0 ? std::clamp(((cx - s.xa) * dx + (cy - s.ya) * dy) / len2, 0.0, 1.0) : 0.0;
      const double ex = s.xa + u * dx - cx, ey = s.ya + u * dy - cy, d = std::sqrt(ex * ex + ey * ey);
      if (d < best) {
        second = best, best = d, best_id = id, best_u = u;
      } else {
        second = std::min(second, d);
      }
    };
    bool crossed = false;
    for (const std::uint32_t* k = own; k != seg && !crossed; ++k) {
      const Segment& s = segments_[*k];
      crossed = meets_box(s.xa, s.ya, s.xb, s.yb, bx0 - m, bx1 + m, by0 - m, by1 + m);
      look(*k);
    }
    if (crossed) continue;  // the instant's boundary may cross the box
    // The region is known from the nearest segment met well inside it, nearer by the margin than
    // any other and than the sides of the tiles searched. The tile first, then those around it.
    const bool near = best_id != UINT32_MAX && best + m < room && second > best + m;
    if (!near) {
      for (std::size_t cc = ca; cc <= cb; ++cc)
        for (std::size_t rr = ra; rr <= rb; ++rr) {
          if (cc == c && rr == r) continue;
          const std::size_t a = at(cc, rr);
          const std::uint32_t* k = std::lower_bound(segment_ids_.data() + segment_start_[a],
                                                    segment_ids_.data() + segment_start_[a + 1], p, by_position);
          for (; k != segment_ids_.data() + segment_start_[a + 1] && segments_[*k].position == p; ++k) look(*k);
        }
      if (best_id == UINT32_MAX || !(best + m < block_room) || !(second > best + m)) continue;
    }
    const Segment& s = segments_[best_id];
    const double dx = s.xb - s.xa, dy = s.yb - s.ya, len = std::sqrt(dx * dx + dy * dy);
    if (!(best_u * len > m) || !((1 - best_u) * len > m)) continue;  // met near an end
    const double cross = dx * (cy - s.ya) - dy * (cx - s.xa);
    if ((cross > 0) == s.left) {
      if (++out.lit >= want_lit) break;
    } else {
      if (++out.dark >= want_dark) break;
    }
  }
  return out;
}

std::size_t settled_level(const StripTileCounts& counts, const PendingBoundaries& pending, double xmin, double xmax,
                          double ymin, double ymax, const mpq_class& value, const mpq_class& whole,
                          const std::vector<mpq_class>& levels, std::size_t now) {
  const TileGrid& g = pending.grid();
  const std::size_t c0 = std::max(counts.first_column(), g.column(xmin));
  const std::size_t c1 = std::min(counts.last_column(), g.column(xmax));
  const std::size_t r0 = g.row(ymin), r1 = g.row(ymax), top = levels.size();
  if (c1 < c0 || now >= top || (c1 - c0 + 1) * (r1 - r0 + 1) > 4) return SIZE_MAX;
  constexpr std::uint64_t kNever = UINT32_MAX;
  // The fewest instants of weight w that bring `need` (> 0): ceil(need / w), kNever at most.
  const auto fewest = [kNever](const mpq_class& need, const mpq_class& w) -> std::uint64_t {
    const mpq_class q = need / w;
    mpz_class k;
    mpz_cdiv_q(k.get_mpz_t(), q.get_num_mpz_t(), q.get_den_mpz_t());
    return k.fits_ulong_p() ? std::min<std::uint64_t>(k.get_ui(), kNever) : kNever;
  };
  const mpq_class base = value + whole, most(counts.most_weight()), least(counts.least_weight());
  const mpq_class room = levels[now] - base, need = levels[top - 1] - base;
  // A point leaves level `now` once `rise` of the instants that may light it do (the largest
  // weight each; none rises it when that is 0, and it has left already when there is no room),
  // and reaches the top once `reach` of those lighting it whole do (the smallest weight each).
  const std::uint64_t rise = sgn(room) <= 0 ? 0 : sgn(most) <= 0 ? UINT64_MAX : fewest(room, most);
  if (sgn(least) > 0 && sgn(need) <= 0) return top;
  const std::uint64_t reach = sgn(least) > 0 ? fewest(need, least) : kNever;
  enum { kNone, kStay, kTop } outcome = kNone;
  for (std::size_t c = c0; c <= c1; ++c)
    for (std::size_t r = r0; r <= r1; ++r) {
      const StripTileCounts::Range range = counts.at(c, r);
      // How many of the tile's instants must be found dark on the box (for it to stay) or lit
      // whole (for it to reach the top).
      const std::uint32_t want_dark = rise == 0             ? UINT32_MAX
                                      : range.most < rise   ? 0
                                                            : static_cast<std::uint32_t>(range.most - rise + 1);
      const std::uint32_t want_lit = reach == kNever        ? UINT32_MAX
                                     : range.least >= reach ? 0
                                                            : static_cast<std::uint32_t>(reach - range.least);
      auto tile = kNone;
      if (want_dark == 0) {
        tile = kStay;
      } else if (want_lit == 0) {
        tile = kTop;
      } else {
        const std::uint32_t open = pending.undecided(c, r);
        if (want_dark > open && want_lit > open) return SIZE_MAX;
        const PendingBoundaries::Refined found = pending.refine(c, r, xmin, xmax, ymin, ymax, want_dark, want_lit);
        tile = found.dark >= want_dark ? kStay : found.lit >= want_lit ? kTop : kNone;
      }
      if (tile == kNone || (outcome != kNone && tile != outcome)) return SIZE_MAX;
      outcome = tile;
    }
  return outcome == kStay ? now : outcome == kTop ? top : SIZE_MAX;
}

}  // namespace shadow::sunmap
