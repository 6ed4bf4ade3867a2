// SPDX-License-Identifier: GPL-3.0-or-later
// The pending boundaries filed by tile (sunmap/pending_boundaries.hpp), which refine the tiles'
// bounds per cell in the threshold map alone: a box they call dark under an instant must hold no
// lit point of it, and one they call lit whole no unlit point (either mistake would settle a
// cell too soon and change the exact level areas). Seeded random regions, random small boxes,
// every claim checked exactly with CGAL's Boolean operations, on a whole face and in a strip.
#include "sunmap/pending_boundaries.hpp"

#include <gtest/gtest.h>

#include <CGAL/Boolean_set_operations_2.h>

#include <cstdint>
#include <random>
#include <vector>

namespace shadow::sunmap {
namespace {

using exact::FT;
using exact::Point2;
using exact::Polygon2;

Polygon2 rectangle(double x0, double y0, double x1, double y1) {
  Polygon2 p;
  p.push_back(Point2(x0, y0));
  p.push_back(Point2(x1, y0));
  p.push_back(Point2(x1, y1));
  p.push_back(Point2(x0, y1));
  return p;
}

/// A random region of one instant, as the lit regions are: a rectangle with a hole within
/// [0, 11]^2, and a triangle within [12, 19.5] x [1, 19], apart (their boundaries are then the
/// region's).
struct Region {
  exact::PolygonSet2 set;
  std::vector<Curve> curves;
};

Region random_region(std::mt19937& rng, long tag, double ox = 0, double oy = 0) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto jitter = [&](double scale) { return scale * u(rng); };
  Region out;
  const double ax = ox + jitter(5), ay = oy + jitter(5), aw = 3 + jitter(3), ah = 3 + jitter(3);
  exact::PolygonWithHoles2 ring(rectangle(ax, ay, ax + aw, ay + ah));
  Polygon2 hole = rectangle(ax + 0.3 * aw, ay + 0.3 * ah, ax + 0.6 * aw, ay + 0.7 * ah);
  hole.reverse_orientation();
  ring.add_hole(hole);
  Polygon2 triangle;
  triangle.push_back(Point2(ox + 12 + jitter(2), oy + 1 + jitter(6)));
  triangle.push_back(Point2(ox + 19.5 - jitter(1), oy + 3 + jitter(6)));
  triangle.push_back(Point2(ox + 13 + jitter(3), oy + 19 - jitter(6)));
  add_boundary(ring.outer_boundary(), tag, out.curves);
  add_boundary(*ring.holes_begin(), tag, out.curves);
  add_boundary(triangle, tag, out.curves);
  out.set = exact::PolygonSet2(ring);
  out.set.join(triangle);
  return out;
}

/// `c` cut to x0 <= x <= x1 (exactly), or nothing.
bool clip(const Curve& c, const FT& x0, const FT& x1, XCurve& out) {
  Point2 p = c.source(), q = c.target();
  if (CGAL::compare_xy(p, q) == CGAL::LARGER) std::swap(p, q);
  if (q.x() <= x0 || p.x() >= x1) return false;
  const auto at = [&](const FT& x) { return Point2(x, p.y() + (q.y() - p.y()) * (x - p.x()) / (q.x() - p.x())); };
  const Point2 a = p.x() < x0 ? at(x0) : p, b = q.x() > x1 ? at(x1) : q;
  out = XCurve(Curve(exact::Kernel::Segment_2(a, b), c.data()), Traits::Data_container(c.data()));
  return true;
}

/// `count` random regions (random_region) as a face's instants in time order: their tiles on an
/// n x n grid of [ox, ox + 20] x [oy, oy + 20], and their curves, whole.
struct Instants {
  Instants(std::mt19937& rng, std::size_t count, std::size_t n, double ox = 0, double oy = 0) : curves(count) {
    tiles.grid.n = n;
    tiles.grid.x0 = ox, tiles.grid.y0 = oy;
    tiles.grid.dx = tiles.grid.dy = 20.0 / static_cast<double>(n);
    const std::size_t words = tiles.grid.words();
    tiles.masks.resize(count * words);
    tiles.whole_masks.resize(count * words);
    for (std::size_t i = 0; i < count; ++i) {
      regions.push_back(random_region(rng, static_cast<long>(i), ox, oy));
      tiles.instants.push_back(i);
      const auto& c = regions[i].curves;
      mark_lit_tiles(tiles.grid, c.data(), c.data() + c.size(), tiles.masks.data() + i * words,
                     tiles.whole_masks.data() + i * words);
      for (const Curve& k : c) curves[i].emplace_back(k, Traits::Data_container(k.data()));
      order.emplace_back(i, &curves[i]);
    }
  }
  FaceTiles tiles;
  std::vector<Region> regions;
  std::vector<std::vector<XCurve>> curves;
  std::vector<std::pair<std::size_t, const std::vector<XCurve>*>> order;
};

TEST(PendingBoundaries, ClaimsHoldExactly) {
  std::mt19937 rng(20261202);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::size_t claims = 0, asked = 0, decidable = 0;
  for (int trial = 0; trial < 24; ++trial) {
    const bool whole_strip = trial % 2 == 0;
    FaceTiles tiles;
    tiles.grid.n = 8 + static_cast<std::size_t>(trial) % 17;
    tiles.grid.dx = tiles.grid.dy = 20.0 / static_cast<double>(tiles.grid.n);
    const std::size_t instants = 3, words = tiles.grid.words();
    std::vector<Region> regions;
    std::vector<double> hours(instants, 1.0);
    for (std::size_t i = 0; i < instants; ++i) {
      regions.push_back(random_region(rng, static_cast<long>(i)));
      tiles.instants.push_back(i);
    }
    tiles.masks.resize(instants * words);
    tiles.whole_masks.resize(instants * words);
    // The strip: every column, or the curves cut to a band of x between two tile columns' middles.
    const double x0 = whole_strip ? 0 : 2.0 + 6.0 * u(rng), x1 = whole_strip ? 20 : x0 + 3.0 + 6.0 * u(rng);
    std::vector<std::vector<XCurve>> strip_curves(instants);
    for (std::size_t i = 0; i < instants; ++i) {
      const auto& curves = regions[i].curves;
      mark_lit_tiles(tiles.grid, curves.data(), curves.data() + curves.size(), tiles.masks.data() + i * words,
                     tiles.whole_masks.data() + i * words);
      for (const Curve& c : curves) {
        XCurve x;
        if (whole_strip)
          strip_curves[i].emplace_back(c, Traits::Data_container(c.data()));
        else if (clip(c, FT(x0), FT(x1), x))
          strip_curves[i].push_back(x);
      }
    }
    const std::size_t c0 = whole_strip ? 0 : tiles.grid.column(x0), c1 = whole_strip ? tiles.grid.n - 1 : tiles.grid.column(x1);
    // Each instant alone, so that a count of one is a claim about it.
    for (std::size_t i = 0; i < instants; ++i) {
      PendingBoundaries pending;
      pending.build(tiles, c0, c1, whole_strip, x0, x1, {{i, &strip_curves[i]}}, hours);
      ASSERT_FALSE(pending.empty());
      for (int b = 0; b < 300; ++b) {
        const double w = 0.02 + 0.3 * u(rng), h = 0.02 + 0.3 * u(rng);
        const double bx = x0 + (x1 - x0 - w) * u(rng), by = (20 - h) * u(rng);
        const std::size_t c = tiles.grid.column(bx), r = tiles.grid.row(by);
        if (c < c0 || c > c1 || pending.undecided(c, r) == 0) continue;
        ++asked;
        const PendingBoundaries::Refined found = pending.refine(c, r, bx, bx + w, by, by + h, 1, 1);
        EXPECT_LE(found.dark + found.lit, 1u);
        // The box's part under the tile, exactly.
        const double tx0 = std::max(bx, static_cast<double>(c) * tiles.grid.dx);
        const double tx1 = std::min(bx + w, static_cast<double>(c + 1) * tiles.grid.dx);
        const double ty0 = std::max(by, static_cast<double>(r) * tiles.grid.dy);
        const double ty1 = std::min(by + h, static_cast<double>(r + 1) * tiles.grid.dy);
        const Polygon2 part = rectangle(tx0, ty0, tx1, ty1);
        {
          exact::PolygonSet2 outside(part), inside(part);
          outside.difference(regions[i].set);
          inside.intersection(regions[i].set);
          if (outside.is_empty() || inside.is_empty()) ++decidable;
        }
        if (found.dark + found.lit == 0) continue;
        ++claims;
        if (found.lit == 1) {
          exact::PolygonSet2 outside(part);
          outside.difference(regions[i].set);
          EXPECT_TRUE(outside.is_empty()) << "trial " << trial << " instant " << i << " box " << bx << ", " << by;
        } else {
          exact::PolygonSet2 inside(part);
          inside.intersection(regions[i].set);
          EXPECT_TRUE(inside.is_empty()) << "trial " << trial << " instant " << i << " box " << bx << ", " << by;
        }
      }
      // Walked, an instant counts no more.
      pending.walked(1);
      for (std::size_t c = c0; c <= c1; ++c)
        for (std::size_t r = 0; r < tiles.grid.n; ++r) EXPECT_EQ(pending.undecided(c, r), 0u);
    }
  }
  // Not vacuous: most boxes under a tile the masks leave open lie wholly on one side of the
  // instant's boundary, and most of those are found so (the others lie near a corner of it, or
  // have no segment in the tiles around them).
  EXPECT_GT(asked, 1000u);
  EXPECT_GT(decidable, asked / 2);
  EXPECT_GT(claims, decidable / 2);  // 3,647 of 4,641 when written
}

// Several instants in one strip's boundaries, walked one by one, on a grid far from the origin
// (the margin follows the coordinates): for every box, the instants found dark (lit whole) are
// never more than those exactly dark (lit whole) on its part under the tile among the instants
// not yet walked that the tile's masks leave open, and a search asked for one stops at one.
TEST(PendingBoundaries, CountsOfSeveralInstantsNeverExceedTheExactOnes) {
  std::mt19937 rng(20261203);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::size_t found_total = 0;
  for (int trial = 0; trial < 8; ++trial) {
    const double ox = trial % 2 == 0 ? 0.0 : 41000.5, oy = trial % 2 == 0 ? 0.0 : -27000.25;
    Instants in(rng, 4, 10 + static_cast<std::size_t>(trial) * 3, ox, oy);
    const FaceTiles& tiles = in.tiles;
    const std::vector<Region>& regions = in.regions;
    const std::size_t instants = regions.size();
    std::vector<double> hours(instants, 1.0);
    const auto& order = in.order;
    PendingBoundaries pending;
    pending.build(tiles, 0, tiles.grid.n - 1, true, ox, ox + 20, order, hours);
    for (std::size_t walked = 0; walked < instants; ++walked) {
      pending.walked(walked);
      for (int b = 0; b < 150; ++b) {
        const double w = 0.02 + 0.4 * u(rng), h = 0.02 + 0.4 * u(rng);
        const double bx = ox + (20 - w) * u(rng), by = oy + (20 - h) * u(rng);
        const std::size_t c = tiles.grid.column(bx), r = tiles.grid.row(by), t = r * tiles.grid.n + c;
        const double tx0 = std::max(bx, ox + static_cast<double>(c) * tiles.grid.dx);
        const double tx1 = std::min(bx + w, ox + static_cast<double>(c + 1) * tiles.grid.dx);
        const double ty0 = std::max(by, oy + static_cast<double>(r) * tiles.grid.dy);
        const double ty1 = std::min(by + h, oy + static_cast<double>(r + 1) * tiles.grid.dy);
        const Polygon2 part = rectangle(tx0, ty0, tx1, ty1);
        std::uint32_t open = 0, dark = 0, lit = 0;
        for (std::size_t i = walked; i < instants; ++i) {
          if (!tiles.lit(i, t) || tiles.lit_whole(i, t)) continue;
          ++open;
          exact::PolygonSet2 outside(part), inside(part);
          outside.difference(regions[i].set);
          inside.intersection(regions[i].set);
          dark += inside.is_empty() ? 1 : 0;
          lit += outside.is_empty() ? 1 : 0;
        }
        EXPECT_EQ(pending.undecided(c, r), open) << trial;
        const PendingBoundaries::Refined all = pending.refine(c, r, bx, bx + w, by, by + h, UINT32_MAX, UINT32_MAX);
        EXPECT_LE(all.dark, dark) << "trial " << trial << " walked " << walked << " box " << bx << ", " << by;
        EXPECT_LE(all.lit, lit) << "trial " << trial << " walked " << walked << " box " << bx << ", " << by;
        found_total += all.dark + all.lit;
        const PendingBoundaries::Refined one = pending.refine(c, r, bx, bx + w, by, by + h, 1, 1);
        EXPECT_LE(one.dark + one.lit, 1u);
        if (all.dark + all.lit > 0) EXPECT_EQ(one.dark + one.lit, 1u);
      }
    }
  }
  EXPECT_GT(found_total, 200u);
}

// settled_level, the tiles' counts and the pending boundaries together: a cell it settles ends
// at that level at every point of its box, checked exactly on a lattice of points in the box
// (the hours a point gets: its value, and the weight of every instant not yet walked whose
// region holds it).
TEST(PendingBoundaries, SettledLevelsHoldAtEveryPointOfTheBox) {
  std::mt19937 rng(20261204);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::vector<mpq_class> levels{mpq_class(3, 2), mpq_class(5, 2)};
  std::size_t settled = 0, asked = 0;
  for (int trial = 0; trial < 6; ++trial) {
    Instants in(rng, 4, 12 + static_cast<std::size_t>(trial) * 4);
    const FaceTiles& tiles = in.tiles;
    const std::vector<Region>& regions = in.regions;
    const std::size_t instants = regions.size();
    const std::vector<double> hours{1.0, 0.5, 1.0, 0.75};
    const auto& order = in.order;
    StripTileCounts counts;
    counts.begin(tiles, true, 0, 20, hours, {mpq_class(1), mpq_class(1, 2), mpq_class(1), mpq_class(3, 4)});
    counts.recount({0, 1, 2, 3});
    PendingBoundaries pending;
    pending.build(tiles, 0, tiles.grid.n - 1, true, 0, 20, order, hours);
    for (std::size_t walked = 0; walked < instants; ++walked) {
      if (walked > 0) counts.count(walked - 1, false);
      pending.walked(walked);
      for (int b = 0; b < 120; ++b) {
        const double w = 0.05 + 1.5 * u(rng) * tiles.grid.dx, h = 0.05 + 1.5 * u(rng) * tiles.grid.dy;
        const double bx = (20 - w) * u(rng), by = (20 - h) * u(rng);
        const mpq_class value(static_cast<int>(u(rng) * 12), 4);  // 0 to 2.75 hours
        const std::size_t now = value >= levels[1] ? 2 : value >= levels[0] ? 1 : 0;
        if (now == levels.size()) continue;  // at the top: nothing to settle
        ++asked;
        const std::size_t got = settled_level(counts, pending, bx, bx + w, by, by + h, value, 0, levels, now);
        if (got == SIZE_MAX) continue;
        ++settled;
        for (int i = 0; i <= 4; ++i)
          for (int j = 0; j <= 4; ++j) {
            const Point2 p(bx + w * i / 4.0, by + h * j / 4.0);
            mpq_class hours_at = value;
            bool on_a_boundary = false;  // (no area: a boundary point's level is no claim)
            for (std::size_t k = walked; k < instants; ++k) {
              const CGAL::Oriented_side side = regions[k].set.oriented_side(p);
              on_a_boundary = on_a_boundary || side == CGAL::ON_ORIENTED_BOUNDARY;
              if (side == CGAL::ON_POSITIVE_SIDE) hours_at += mpq_class(hours[k]);
            }
            if (on_a_boundary) continue;
            const std::size_t level = hours_at >= levels[1] ? 2 : hours_at >= levels[0] ? 1 : 0;
            EXPECT_EQ(level, got) << "trial " << trial << " walked " << walked << " box " << bx << ", " << by
                                  << " value " << value;
          }
      }
    }
  }
  EXPECT_GT(asked, 1000u);
  EXPECT_GT(settled, asked / 4);
}

}  // namespace
}  // namespace shadow::sunmap
