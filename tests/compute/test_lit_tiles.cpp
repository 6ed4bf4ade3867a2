// SPDX-License-Identifier: GPL-3.0-or-later
// The tiles an instant may light on a face (sunmap/lit_tiles.hpp), which the threshold map alone
// uses to settle cells early: they must never miss a lit point, and the tiles said to be lit whole
// must hold no unlit point (either mistake would settle a cell too soon and change the exact level
// areas). A square worked out by hand, then seeded random regions with holes against the exact
// point-in-region test on a lattice finer than the tiles.
#include "sunmap/lit_tiles.hpp"

#include <gtest/gtest.h>

#include <CGAL/Boolean_set_operations_2.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace shadow::sunmap {
namespace {

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

bool marked(const std::vector<std::uint64_t>& mask, std::size_t tile) { return (mask[tile / 64] >> (tile % 64)) & 1U; }

TileGrid unit_grid(std::size_t n) {
  TileGrid g;
  g.n = n;
  return g;  // tiles [c, c + 1] x [r, r + 1]
}

// The region [2, 5] x [2, 5] on a 10 x 10 grid of unit tiles: its inside tiles and the tiles
// touching its sides are marked; tiles two away from it are not. Lit whole: only the middle tile
// [3, 4] x [3, 4] (the others inside touch a side).
TEST(LitTiles, SquareByHand) {
  const TileGrid g = unit_grid(10);
  std::vector<Curve> curves;
  add_boundary(rectangle(2, 2, 5, 5), 0, curves);
  std::vector<std::uint64_t> mask(g.words(), ~std::uint64_t{0}), whole(g.words(), ~std::uint64_t{0});
  mark_lit_tiles(g, curves.data(), curves.data() + curves.size(), mask.data(), whole.data());
  for (std::size_t r = 2; r < 5; ++r)
    for (std::size_t c = 2; c < 5; ++c) EXPECT_TRUE(marked(mask, r * 10 + c)) << r << " " << c;
  for (std::size_t r = 0; r < 10; ++r)
    for (std::size_t c = 0; c < 10; ++c) {
      const bool far = r >= 6 || c >= 6 || r == 0 || c == 0;  // more than a quarter tile away
      if (far) EXPECT_FALSE(marked(mask, r * 10 + c)) << r << " " << c;
      EXPECT_EQ(marked(whole, r * 10 + c), r == 3 && c == 3) << r << " " << c;
    }
  // The grid's helpers clamp to it.
  EXPECT_EQ(g.column(-3.0), 0u);
  EXPECT_EQ(g.column(42.0), 9u);
  EXPECT_EQ(g.row(4.5), 4u);
}

// Seeded random regions: a rectangle minus a smaller one (a hole), a second rectangle and a
// triangle (edges at slopes that clip tile corners between the marking's points), apart, on grids
// of 7 to 40 tiles a side over [0, 20]^2. Every lattice point of step 0.1 inside the region or on
// its boundary (exact test) lies in a marked tile, and not every tile is marked; exactly, with
// CGAL's Boolean operations, every tile marked lit whole lies in the region and every unmarked
// tile meets no interior point of it.
TEST(LitTiles, NeverMissALitPoint) {
  std::mt19937 rng(20261129);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto jitter = [&](double scale) { return scale * u(rng); };
  for (int trial = 0; trial < 40; ++trial) {
    TileGrid g;
    g.n = 7 + static_cast<std::size_t>(trial) % 34;
    g.dx = g.dy = 20.0 / static_cast<double>(g.n);
    // The ring within [0, 11]^2, the rectangle within [12, 16.2] x [12, 14.2], the triangle
    // within [12, 19.5] x [1, 10]: apart.
    const double ax = jitter(5), ay = jitter(5), aw = 2 + jitter(4), ah = 2 + jitter(4);
    exact::PolygonWithHoles2 ring(rectangle(ax, ay, ax + aw, ay + ah));
    Polygon2 hole = rectangle(ax + 0.3 * aw, ay + 0.3 * ah, ax + 0.6 * aw, ay + 0.7 * ah);
    hole.reverse_orientation();  // clockwise, as the lit regions' holes
    ring.add_hole(hole);
    const Polygon2 second = rectangle(12 + jitter(0.2), 12 + jitter(0.2), 16 + jitter(0.2), 14 + jitter(0.2));
    Polygon2 triangle;  // counter-clockwise
    triangle.push_back(Point2(12 + jitter(1), 1 + jitter(1)));
    triangle.push_back(Point2(19.5 - jitter(1), 3 + jitter(1)));
    triangle.push_back(Point2(14 + jitter(1), 10 - jitter(1)));
    std::vector<Curve> curves;
    add_boundary(ring.outer_boundary(), 3, curves);
    add_boundary(*ring.holes_begin(), 3, curves);
    add_boundary(second, 3, curves);
    add_boundary(triangle, 3, curves);
    std::vector<std::uint64_t> mask(g.words(), 0), whole(g.words(), 0);
    mark_lit_tiles(g, curves.data(), curves.data() + curves.size(), mask.data(), whole.data());
    std::size_t count = 0, whole_count = 0;
    for (std::size_t t = 0; t < g.n * g.n; ++t) {
      count += marked(mask, t) ? 1 : 0;
      whole_count += marked(whole, t) ? 1 : 0;
      if (marked(whole, t)) EXPECT_TRUE(marked(mask, t)) << trial << " tile " << t;
    }
    EXPECT_LT(count, g.n * g.n) << trial;
    if (g.n >= 24) EXPECT_GT(whole_count, 0u) << trial;  // the 4 x 2 rectangle holds a tile and its margin
    for (int i = 0; i <= 200; ++i)
      for (int j = 0; j <= 200; ++j) {
        const Point2 p(0.1 * i, 0.1 * j);
        const bool in_ring = ring.outer_boundary().bounded_side(p) != CGAL::ON_UNBOUNDED_SIDE &&
                             ring.holes_begin()->bounded_side(p) != CGAL::ON_BOUNDED_SIDE;
        const bool in = in_ring || second.bounded_side(p) != CGAL::ON_UNBOUNDED_SIDE ||
                        triangle.bounded_side(p) != CGAL::ON_UNBOUNDED_SIDE;
        if (!in) continue;
        const std::size_t t = g.row(0.1 * j) * g.n + g.column(0.1 * i);
        ASSERT_TRUE(marked(mask, t)) << "trial " << trial << " point " << 0.1 * i << ", " << 0.1 * j;
      }
    exact::PolygonSet2 region(ring);
    region.join(second);
    region.join(triangle);
    for (std::size_t r = 0; r < g.n; ++r)
      for (std::size_t c = 0; c < g.n; ++c) {
        const std::size_t t = r * g.n + c;
        const Polygon2 tile = rectangle(static_cast<double>(c) * g.dx, static_cast<double>(r) * g.dy,
                                        static_cast<double>(c + 1) * g.dx, static_cast<double>(r + 1) * g.dy);
        if (marked(whole, t)) {
          exact::PolygonSet2 outside(tile);
          outside.difference(region);
          EXPECT_TRUE(outside.is_empty()) << "trial " << trial << " tile " << c << ", " << r << " marked lit whole";
        } else if (!marked(mask, t)) {
          exact::PolygonSet2 inside(tile);
          inside.intersection(region);
          EXPECT_TRUE(inside.is_empty()) << "trial " << trial << " tile " << c << ", " << r << " unmarked";
        }
      }
  }
}

// The grid's size: none for few segments, finer for more, at most 256 a side, and coarser where
// the masks of many instants would pass the budget (kMaxTileBits unless given).
TEST(LitTiles, GridSize) {
  const Polygon2 chart = rectangle(0, 0, 100, 50);
  EXPECT_EQ(tile_grid(chart, 10, 24).n, 0u);
  EXPECT_EQ(tile_grid(chart, 100, 24).n, 80u);
  EXPECT_EQ(tile_grid(chart, 10000, 24).n, 256u);
  const TileGrid year = tile_grid(chart, 10000, 4400);
  EXPECT_LT(year.n, 256u);
  EXPECT_LE((2.0 * 64.0 * static_cast<double>(year.words()) + 64.0) * 4400.0, kMaxTileBits);  // whole words
  EXPECT_GE(year.n, 80u);
  EXPECT_DOUBLE_EQ(year.dx, 100.0 / static_cast<double>(year.n));
  EXPECT_DOUBLE_EQ(year.dy, 50.0 / static_cast<double>(year.n));
  EXPECT_EQ(tile_grid(chart, 10000, 4400, 100.0).n, 0u);  // a budget below a 4 x 4 grid: none
}

}  // namespace
}  // namespace shadow::sunmap
