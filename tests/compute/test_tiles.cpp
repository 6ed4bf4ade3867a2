// SPDX-License-Identifier: GPL-3.0-or-later
// Tiles of large receivers (ShadowOptions::tile_casters, fast_tile_casters; docs/tiles.md): a
// split receiver's exact areas must be the untiled ones bit for bit, its fast areas within their
// bounds of the exact ones, its fragments (cut at tile borders) must add up to the face and to
// the lit and shadowed areas, and nothing may depend on the thread count. Small thresholds on
// small seeded cities, so that the ground (and some walls) are cut into many tiles; the same on
// grounds that are not rectangles (a triangle, an L, a rotated rectangle, an octagon, a square
// with a courtyard, a slanted and rotated roof, two gable walls), whose tiles are cut to the
// face's outline.
#include "core/polygon_holes.hpp"
#include "core/tiles.hpp"
#include "exact/exact_faces.hpp"

#include <shadow/shadow.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace shadow {
namespace {

/// A city with a sun at `elevation` and a lamp above it.
Scene city(std::size_t boxes, double extent, double elevation, std::uint32_t seed) {
  Scene scene = make_city(boxes, extent, seed);
  scene.lights.push_back(directional_light("sun", sun_direction(elevation, 120)));
  scene.lights.push_back(point_light("lamp", {extent / 2 + 13, extent / 2 - 7, 60}));
  validate_scene(scene);
  return scene;
}

ShadowOptions options(Arithmetic arithmetic, std::size_t tile_casters, bool polygons, unsigned threads = 2) {
  ShadowOptions o;
  o.threads = threads;
  o.polygons = polygons;
  o.planes = false;
  o.arithmetic = arithmetic;
  o.tile_casters = tile_casters;
  o.fast_tile_casters = tile_casters;
  return o;
}

void expect_same_bits(const ShadowResult& a, const ShadowResult& b, const std::string& label) {
  ASSERT_EQ(a.lighting.size(), b.lighting.size()) << label;
  for (std::size_t n = 0; n < a.lighting.size(); ++n) {
    const FaceLighting& x = a.lighting[n];
    const FaceLighting& y = b.lighting[n];
    const std::string where = label + ": face " + std::to_string(x.face_id) + " light " + std::to_string(x.light_id);
    EXPECT_EQ(x.face_id, y.face_id) << where;
    EXPECT_EQ(x.light_id, y.light_id) << where;
    EXPECT_EQ(x.area, y.area) << where;
    EXPECT_EQ(x.lit_area, y.lit_area) << where;
    EXPECT_EQ(x.shadow_area, y.shadow_area) << where;
    EXPECT_EQ(x.lit_fraction, y.lit_fraction) << where;
    EXPECT_EQ(x.faces_light, y.faces_light) << where;
    EXPECT_EQ(x.lit_area_error_bound, y.lit_area_error_bound) << where;
  }
}

/// The fragments of every (face, light) add up to the face's area (with dropped_area), the lit
/// ones to lit_area and the shadowed ones to shadow_area, each within `slack(face)` (rounding,
/// or the fast path's bound).
template <class Slack>
void expect_fragments_add_up(const ShadowResult& r, const std::string& label, Slack slack) {
  std::map<std::pair<std::size_t, std::size_t>, std::pair<double, double>> sums;  // lit, shadowed
  for (const Fragment& f : r.fragments) {
    auto& s = sums[{f.face_id, f.light_id}];
    (f.lit ? s.first : s.second) += f.area;
  }
  for (const FaceLighting& l : r.lighting) {
    const auto& s = sums[{l.face_id, l.light_id}];
    const double tolerance = slack(l) + 1e-9 * (1 + l.area);
    const std::string where = label + ": face " + std::to_string(l.face_id) + " light " + std::to_string(l.light_id);
    EXPECT_NEAR(s.first + s.second + l.dropped_area, l.area, tolerance) << where;
    EXPECT_NEAR(s.first, l.lit_area, tolerance + l.dropped_area) << where;
    EXPECT_NEAR(s.second, l.shadow_area, tolerance + l.dropped_area) << where;
  }
}

/// Every fast area within its reported bound of the exact one, and the same faces facing the light.
void expect_fast_within_bounds(const ShadowResult& exact, const ShadowResult& fast, const std::string& label) {
  ASSERT_EQ(exact.lighting.size(), fast.lighting.size()) << label;
  for (std::size_t n = 0; n < exact.lighting.size(); ++n) {
    const FaceLighting& e = exact.lighting[n];
    const FaceLighting& f = fast.lighting[n];
    EXPECT_LE(std::abs(f.lit_area - e.lit_area), f.lit_area_error_bound) << label << " face " << f.face_id;
    EXPECT_LE(std::abs(f.shadow_area - e.shadow_area), f.lit_area_error_bound) << label << " face " << f.face_id;
    EXPECT_EQ(f.faces_light, e.faces_light) << label << " face " << f.face_id;
  }
}

TEST(Tiles, ExactAreasAreTheUntiledOnesBitForBit) {
  for (double elevation : {35.0, 8.0}) {
    const Scene scene = city(150, 120, elevation, 11);
    const std::string label = "sun " + std::to_string(elevation);
    const ShadowResult whole = compute_shadows(scene, options(Arithmetic::Exact, 0, false));
    const ShadowResult tiled = compute_shadows(scene, options(Arithmetic::Exact, 40, false));
    EXPECT_EQ(whole.stats.tiled_receivers, 0u);
    EXPECT_EQ(whole.stats.tiles, 0u);
    EXPECT_GT(tiled.stats.tiled_receivers, 0u) << label;
    EXPECT_GT(tiled.stats.tiles, 2 * tiled.stats.tiled_receivers) << label;
    expect_same_bits(whole, tiled, label);
    // A split receiver counts once: the per-receiver counts do not change.
    EXPECT_EQ(whole.stats.receivers, tiled.stats.receivers) << label;
    EXPECT_EQ(whole.stats.back_facing, tiled.stats.back_facing) << label;
    EXPECT_EQ(whole.stats.unshadowed, tiled.stats.unshadowed) << label;
    // The longest item is no longer than the items' total.
    EXPECT_GT(tiled.stats.item_seconds, 0.0);
    EXPECT_LE(tiled.stats.longest_item_seconds, tiled.stats.item_seconds);
  }
}

TEST(Tiles, ExactFragmentsOfTilesAddUp) {
  const Scene scene = city(120, 110, 20, 5);
  const ShadowResult whole = compute_shadows(scene, options(Arithmetic::Exact, 0, true));
  const ShadowResult tiled = compute_shadows(scene, options(Arithmetic::Exact, 30, true));
  ASSERT_GT(tiled.stats.tiled_receivers, 0u);
  expect_same_bits(whole, tiled, "polygons");
  expect_fragments_add_up(tiled, "tiled", [](const FaceLighting&) { return 0.0; });
  // The ground is cut along tile borders: more fragments than untiled, never fewer.
  std::size_t ground_whole = 0, ground_tiled = 0;
  for (const Fragment& f : whole.fragments) ground_whole += f.face_id == 0 ? 1 : 0;
  for (const Fragment& f : tiled.fragments) ground_tiled += f.face_id == 0 ? 1 : 0;
  EXPECT_GT(ground_tiled, ground_whole);
  // Fragment ids stay consecutive per (face, light) from where the previous pair's ended:
  // within a pair they never decrease and never skip one.
  for (std::size_t n = 1; n < tiled.fragments.size(); ++n) {
    const Fragment& a = tiled.fragments[n - 1];
    const Fragment& b = tiled.fragments[n];
    EXPECT_LE(b.fragment_id, a.fragment_id + 1);
    if (a.face_id == b.face_id && a.light_id == b.light_id) EXPECT_GE(b.fragment_id, a.fragment_id) << b.face_id;
  }
}

TEST(Tiles, FastTilesStayWithinTheirBounds) {
  for (double elevation : {35.0, 8.0}) {
    const Scene scene = city(150, 120, elevation, 11);
    const std::string label = "sun " + std::to_string(elevation);
    const ShadowResult exact = compute_shadows(scene, options(Arithmetic::Exact, 0, true));
    const ShadowResult fast = compute_shadows(scene, options(Arithmetic::Fast, 40, true));
    ASSERT_GT(fast.stats.tiled_receivers, 0u) << label;
    expect_fast_within_bounds(exact, fast, label);
    expect_fragments_add_up(fast, label, [](const FaceLighting& l) { return 2 * l.lit_area_error_bound; });
  }
}

TEST(Tiles, ResultsDoNotDependOnTheThreadCount) {
  const Scene scene = city(100, 100, 12, 3);
  for (Arithmetic a : {Arithmetic::Exact, Arithmetic::Fast}) {
    const ShadowResult one = compute_shadows(scene, options(a, 25, true, 1));
    const ShadowResult three = compute_shadows(scene, options(a, 25, true, 3));
    ASSERT_GT(one.stats.tiled_receivers, 0u);
    expect_same_bits(one, three, a == Arithmetic::Fast ? "fast" : "exact");
    EXPECT_EQ(one.stats.tiles, three.stats.tiles);
    EXPECT_EQ(one.stats.candidate_pairs, three.stats.candidate_pairs);
    ASSERT_EQ(one.fragments.size(), three.fragments.size());
    for (std::size_t n = 0; n < one.fragments.size(); ++n) {
      EXPECT_EQ(one.fragments[n].fragment_id, three.fragments[n].fragment_id);
      EXPECT_EQ(one.fragments[n].area, three.fragments[n].area);
      EXPECT_EQ(one.fragments[n].polygon, three.fragments[n].polygon);
    }
  }
}

/// A box face prep with chart box [0, w] x [0, h].
core::FacePrep box_prep(double w, double h) {
  core::FacePrep fp;
  fp.chart_is_box = true;
  fp.chart_min = {0, 0};
  fp.chart_max = {w, h};
  return fp;
}

/// The tiles partition the box: borders shared exactly, first and last at the box's sides.
void expect_partition(const std::vector<core::FacePrep>& tiles, double w, double h) {
  std::size_t at_origin = 0;
  for (const core::FacePrep& t : tiles) {
    EXPECT_LT(t.chart_min[0], t.chart_max[0]);
    EXPECT_LT(t.chart_min[1], t.chart_max[1]);
    EXPECT_GE(t.chart_min[0], 0.0);
    EXPECT_GE(t.chart_min[1], 0.0);
    EXPECT_LE(t.chart_max[0], w);
    EXPECT_LE(t.chart_max[1], h);
    at_origin += t.chart_min[0] == 0 && t.chart_min[1] == 0 ? 1 : 0;
  }
  if (!tiles.empty()) EXPECT_EQ(at_origin, 1u);
}

TEST(Tiles, TileCountIsBoundedOnDegenerateBoxes) {
  // Sides near 1e-162: w * h underflows to 0, which once made a million tiles.
  for (double side : {1e-162, 1e-200, 1e-300}) {
    const auto tiles = core::make_tiles(box_prep(side, side), 1000000, 1);
    EXPECT_LE(tiles.size(), 1024u) << side;
    expect_partition(tiles, side, side);
  }
  // Subnormal: h / wanted underflows to 0; no tiles rather than a division by zero.
  EXPECT_TRUE(core::make_tiles(box_prep(1, 5e-324), 1000000, 1).empty());
  // Both sides rounded up (4 x 3 for 10 wanted): the product is capped, not each side alone.
  const auto capped = core::make_tiles(box_prep(1.5, 1), 10, 1, 10);
  EXPECT_LE(capped.size(), 10u);
  EXPECT_GE(capped.size(), 2u);
  expect_partition(capped, 1.5, 1);
  // A long thin box: one row, at most max_tiles cells.
  const auto row = core::make_tiles(box_prep(1e6, 1), 5000, 1, 64);
  EXPECT_EQ(row.size(), 64u);
  expect_partition(row, 1e6, 1);
}

TEST(Tiles, ProgressCountsSplitReceiversWhenTheirTilesAreDone) {
  const Scene scene = city(100, 100, 12, 3);
  for (Arithmetic a : {Arithmetic::Exact, Arithmetic::Fast}) {
    std::vector<Progress> calls;
    ShadowOptions o = options(a, 25, false);
    o.progress = [&](const Progress& p) { calls.push_back(p); };
    const ShadowResult r = compute_shadows(scene, o);
    ASSERT_GT(r.stats.tiled_receivers, 0u);
    ASSERT_FALSE(calls.empty());
    for (std::size_t n = 1; n < calls.size(); ++n) {
      EXPECT_GE(calls[n].done, calls[n - 1].done);
      EXPECT_EQ(calls[n].total, calls[0].total);
    }
    EXPECT_EQ(calls.back().done, calls.back().total);
  }
}

TEST(Tiles, AReceiverTooSmallToCutIsComputedWhole) {
  // The tower of examples/sun under its sun of 07:00 UTC: the roof has two candidates in the
  // light-space grid, so a threshold of 1 asks for tiles, but two candidates make one cell (no
  // tiles): the roof is then computed whole, and must not ask for tiles again (it used to be
  // left unfilled: lit area 0 instead of 64).
  const Scene scene = parse_scene(R"({"meshes": [
    {"name": "ground", "polygons": [[[-20, -20, 0], [40, -20, 0], [40, 40, 0], [-20, 40, 0]]]},
    {"name": "tower", "polygons": [
      [[0, 0, 30], [8, 0, 30], [8, 8, 30], [0, 8, 30]],
      [[0, 0, 0], [8, 0, 0], [8, 0, 30], [0, 0, 30]],
      [[8, 0, 0], [8, 8, 0], [8, 8, 30], [8, 0, 30]],
      [[8, 8, 0], [0, 8, 0], [0, 8, 30], [8, 8, 30]],
      [[0, 8, 0], [0, 0, 0], [0, 0, 30], [0, 8, 30]]]}],
    "lights": [{"name": "sun", "type": "directional", "to_light": [0.8101643, -0.09933632, 0.57772493]}]})",
                                  "tower.json");
  for (bool polygons : {false, true}) {
    const ShadowResult whole = compute_shadows(scene, options(Arithmetic::Exact, 0, polygons, 1));
    const ShadowResult tiled = compute_shadows(scene, options(Arithmetic::Exact, 1, polygons, 1));
    expect_same_bits(whole, tiled, polygons ? "polygons" : "areas");
    const FaceLighting* roof = tiled.find(1, 0);
    ASSERT_NE(roof, nullptr);
    EXPECT_EQ(roof->lit_area, 64.0);
    EXPECT_EQ(whole.stats.receivers, tiled.stats.receivers);
    if (polygons) expect_fragments_add_up(tiled, "tower", [](const FaceLighting&) { return 0.0; });
  }
}

// ---- receivers that are not their own chart box ------------------------------------------------

/// A polygon in the plane z = z0 + sx x + sy y (counter-clockwise from above) from plan points.
Polygon3 plan(const std::vector<glm::dvec2>& points, double z0 = 0, double sx = 0, double sy = 0) {
  Polygon3 p;
  for (const glm::dvec2& q : points) p.emplace_back(q.x, q.y, z0 + sx * q.x + sy * q.y);
  return p;
}

/// `points` turned by `degrees` about `c`.
std::vector<glm::dvec2> turned(std::vector<glm::dvec2> points, glm::dvec2 c, double degrees) {
  const double a = degrees * M_PI / 180, cs = std::cos(a), sn = std::sin(a);
  for (glm::dvec2& p : points) {
    const glm::dvec2 d = p - c;
    p = c + glm::dvec2(cs * d.x - sn * d.y, sn * d.x + cs * d.y);
  }
  return points;
}

/// Grounds that are not rectangles under a city of extent e, by name: each one or more faces.
std::vector<std::pair<std::string, std::vector<Polygon3>>> odd_grounds(double e) {
  const glm::dvec2 c(e / 2, e / 2);
  std::vector<std::pair<std::string, std::vector<Polygon3>>> grounds;
  grounds.push_back({"triangle", {plan({{-10, -10}, {e + 10, -5}, {e / 3, e + 10}})}});
  grounds.push_back({"L", {plan({{-10, -10}, {e + 10, -10}, {e + 10, e / 2}, {e / 2, e / 2}, {e / 2, e + 10}, {-10, e + 10}})}});
  grounds.push_back({"rotated", {plan(turned({{-0.1 * e, 0.05 * e}, {1.1 * e, 0.05 * e}, {1.1 * e, 0.95 * e}, {-0.1 * e, 0.95 * e}}, c, 30))}});
  std::vector<glm::dvec2> octagon;
  for (int k = 0; k < 8; ++k)
    octagon.push_back(c + 0.72 * e * glm::dvec2(std::cos((k + 0.5) * M_PI / 4), std::sin((k + 0.5) * M_PI / 4)));
  grounds.push_back({"octagon", {plan(octagon)}});
  // A square with a courtyard: the pieces of a polygon with a hole (none of them a rectangle).
  const Polygon3 outer = plan({{-10, -10}, {e + 10, -10}, {e + 10, e + 10}, {-10, e + 10}});
  const Polygon3 hole = plan({{e / 3, e / 3}, {e / 3, 0.6 * e}, {0.6 * e, 0.6 * e}, {0.6 * e, e / 3}});
  grounds.push_back({"courtyard", core::split_polygon_with_holes(outer, {hole})});
  // A roof below the city, slanted both ways and turned 20 degrees: its chart is no box either.
  grounds.push_back({"slanted", {plan(turned({{-10, -10}, {e + 10, -10}, {e + 10, e + 10}, {-10, e + 10}}, c, 20),
                                      -30, 0.0625, 0.03125)}});
  // A gable wall west of the city, facing east (+x) toward the suns of these tests (azimuth
  // 120) and the lamp; and one north of it facing south (-y: its chart drops y and sees it
  // clockwise, flipped).
  grounds.push_back({"west gable", {{{-12, -10, 0}, {-12, e + 10, 0}, {-12, e + 10, 20}, {-12, e / 2, 45}, {-12, -10, 20}}}});
  grounds.push_back({"north gable", {{{-10, e + 11, 0}, {e + 10, e + 11, 0}, {e + 10, e + 11, 20}, {e / 2, e + 11, 45},
                                      {-10, e + 11, 20}}}});
  return grounds;
}

/// The seeded city's buildings on `ground`, with a sun at `elevation` and a lamp above it; the
/// buildings receive light too unless `buildings_receive` is false (then only the ground's
/// faces are receivers, and the tile counts are theirs).
Scene city_on(const std::vector<Polygon3>& ground, std::size_t boxes, double extent, double elevation,
              std::uint32_t seed, bool buildings_receive = true) {
  const Scene source = make_city(boxes, extent, seed);
  Scene scene;
  add_mesh(scene, "ground", ground);
  std::vector<Polygon3> buildings;
  for (const Face& f : source.faces)
    if (f.mesh == 1) buildings.push_back(f.vertices);
  add_mesh(scene, "buildings", buildings, buildings_receive);
  scene.lights.push_back(directional_light("sun", sun_direction(elevation, 120)));
  scene.lights.push_back(point_light("lamp", {extent / 2 + 13, extent / 2 - 7, 60}));
  validate_scene(scene);
  return scene;
}

/// How many fragments the faces of mesh 0 (the ground) have.
std::size_t ground_fragments(const Scene& scene, const ShadowResult& r) {
  std::size_t n = 0;
  for (const Fragment& f : r.fragments) n += scene.faces[f.face_id].mesh == 0 ? 1 : 0;
  return n;
}

TEST(Tiles, CellsArePlacedExactlyAgainstTheOutline) {
  // The triangle (0, 0), (10, 0), (0, 10) in the plane z = 0.
  const Polygon3 triangle = plan({{0, 0}, {10, 0}, {0, 10}});
  const core::FacePrep fp = exact::prepare_face(triangle);
  ASSERT_FALSE(fp.chart_is_box);
  auto place = [&](double x0, double y0, double x1, double y1) {
    return exact::place_cell(triangle, fp, {x0, y0}, {x1, y1});
  };
  EXPECT_EQ(place(1, 1, 2, 2), core::CellPlace::Inside);
  EXPECT_EQ(place(6, 6, 7, 7), core::CellPlace::Outside);
  EXPECT_EQ(place(4, 4, 6, 6), core::CellPlace::Crossing);
  EXPECT_EQ(place(5, 5, 6, 6), core::CellPlace::Crossing);  // touches the hypotenuse at a corner
  EXPECT_EQ(place(0, 0, 1, 1), core::CellPlace::Crossing);  // on two sides
  EXPECT_EQ(place(-3, 2, -1, 3), core::CellPlace::Outside);
  // An exact call on doubles: the cell whose corner is the hypotenuse's point (5, 5) nudged
  // inwards by one ulp is Inside only when the nudge is below the line x + y = 10.
  const double below = std::nextafter(5.0, 0.0);
  EXPECT_EQ(place(1, 1, below, 5), core::CellPlace::Inside);
  EXPECT_EQ(place(1, 1, 5, 5), core::CellPlace::Crossing);
  // make_tiles with the placement: no Outside cell, Inside ones are boxes, the rest cut.
  const auto tiles = core::make_tiles(fp, 10000, 100, core::kMaxTiles,
                                      [&](const std::array<double, 2>& lo, const std::array<double, 2>& hi) {
                                        return exact::place_cell(triangle, fp, lo, hi);
                                      });
  // Unit cells [a, a + 1] x [b, b + 1] of a 10 x 10 grid: those with a + b >= 11 miss the
  // triangle (36 dropped); Inside are those whose closed cell stays off the outline (a, b >= 1,
  // a + b <= 7: 21); the other 43 meet it, if only at a corner or along a side, and are cut
  // into quarters, placed again: the 15 along the legs (a + b <= 7) and the 9 with a + b = 8
  // keep 4 quarters each, the 10 with a + b = 9 too, the 9 with a + b = 10 one (the quarter at
  // their lower left corner, which touches the hypotenuse). Inside quarters: 1 of cell (0, 0),
  // 2 of each other leg cell (28), 3 of each a + b = 8 cell off the legs (21), 1 of (0, 8) and
  // of (8, 0).
  ASSERT_EQ(tiles.size(), 21u + 15 * 4 + 9 * 4 + 10 * 4 + 9);
  std::size_t inside = 0;
  double cells = 0;
  for (const core::FacePrep& t : tiles) {
    inside += t.chart_is_box ? 1 : 0;
    cells += (t.chart_max[0] - t.chart_min[0]) * (t.chart_max[1] - t.chart_min[1]);
    EXPECT_LT(t.chart_min[0] + t.chart_min[1], 10.0 + 1e-12);  // (== 10: touches the hypotenuse)
    EXPECT_EQ(exact::place_cell(triangle, fp, t.chart_min, t.chart_max),
              t.chart_is_box ? core::CellPlace::Inside : core::CellPlace::Crossing);
  }
  EXPECT_EQ(inside, 21u + 1 + 28 + 21 + 2);
  EXPECT_EQ(cells, 21 + 15 + 9 + 10 + 9 * 0.25);  // the kept cells' areas (dyadic: exact)
}

TEST(Tiles, BoxFillIsTheFaceShareOfItsChartBoxFarFromTheOrigin) {
  // core::box_fill and the exact engine's cover test share core::twice_area_about_box_corner:
  // twice the ring's signed area in doubles, about the chart box's lower corner, so that a
  // georeferenced face (coordinates of 1e6) keeps the digits of a face near the origin.
  for (const double x0 : {0.0, 1e6 + 0.25}) {
    const double y0 = x0 == 0.0 ? 0.0 : 2e6 + 0.5;
    const Polygon3 triangle = plan({{x0, y0}, {x0 + 10, y0}, {x0, y0 + 10}});
    const core::FacePrep t = exact::prepare_face(triangle);
    ASSERT_FALSE(t.chart_is_box);
    EXPECT_EQ(core::chart_box_area(t), 100.0);
    EXPECT_EQ(core::box_fill(triangle, t), 0.5) << "at x " << x0;
    auto point = [&](std::size_t a) { return std::array<double, 2>{triangle[a].x, triangle[a].y}; };
    EXPECT_EQ(core::twice_area_about_box_corner(t, 3, point), 100.0);  // counter-clockwise
    EXPECT_EQ(core::twice_area_about_box_corner(t, 3, [&](std::size_t a) { return point(2 - a); }), -100.0);
    const Polygon3 ell = plan({{x0, y0}, {x0 + 4, y0}, {x0 + 4, y0 + 2}, {x0 + 2, y0 + 2}, {x0 + 2, y0 + 4}, {x0, y0 + 4}});
    EXPECT_EQ(core::box_fill(ell, exact::prepare_face(ell)), 0.75) << "at x " << x0;
    const Polygon3 box = plan({{x0, y0}, {x0 + 3, y0}, {x0 + 3, y0 + 1}, {x0, y0 + 1}});
    const core::FacePrep b = exact::prepare_face(box);
    ASSERT_TRUE(b.chart_is_box);
    EXPECT_EQ(core::box_fill(box, b), 1.0);
  }
}

TEST(Tiles, NonRectangularReceiversExactBitForBit) {
  std::size_t g = 0;
  for (const auto& [name, ground] : odd_grounds(100)) {
    // A high sun and a low one, each on every other ground (and the lamp on all).
    for (double elevation : {g++ % 2 == 0 ? 35.0 : 8.0}) {
      const Scene scene = city_on(ground, 100, 100, elevation, 11, false);
      const std::string label = name + ", sun " + std::to_string(elevation);
      const ShadowResult whole = compute_shadows(scene, options(Arithmetic::Exact, 0, false));
      const ShadowResult tiled = compute_shadows(scene, options(Arithmetic::Exact, 40, false));
      // Only the ground receives: its faces are split (under the sun, the lamp or both).
      EXPECT_GE(tiled.stats.tiled_receivers, ground.size()) << label;
      EXPECT_GT(tiled.stats.tiles, 2 * tiled.stats.tiled_receivers) << label;
      expect_same_bits(whole, tiled, label);
      EXPECT_EQ(whole.stats.receivers, tiled.stats.receivers) << label;
    }
  }
}

TEST(Tiles, NonRectangularReceiversExactFragmentsAddUp) {
  for (const auto& [name, ground] : odd_grounds(90)) {
    const Scene scene = city_on(ground, 70, 90, 20, 5, false);  // only the ground receives
    const ShadowResult whole = compute_shadows(scene, options(Arithmetic::Exact, 0, true));
    const ShadowResult tiled = compute_shadows(scene, options(Arithmetic::Exact, 30, true));
    ASSERT_GE(tiled.stats.tiled_receivers, ground.size()) << name;
    expect_same_bits(whole, tiled, name);
    expect_fragments_add_up(tiled, name, [](const FaceLighting&) { return 0.0; });
    // (Tile borders cut regions, but a region with holes may then need fewer cuts of its own:
    // the counts are not ordered.)
    EXPECT_GT(ground_fragments(scene, tiled), 0u) << name;
    EXPECT_GT(ground_fragments(scene, whole), 0u) << name;
  }
}

TEST(Tiles, NonRectangularReceiversFastWithinTheirBounds) {
  for (const auto& [name, ground] : odd_grounds(90)) {
    const Scene scene = city_on(ground, 70, 90, 20, 5, false);  // only the ground receives
    const ShadowResult exact = compute_shadows(scene, options(Arithmetic::Exact, 0, true));
    const ShadowResult fast = compute_shadows(scene, options(Arithmetic::Fast, 30, true));
    ASSERT_GE(fast.stats.tiled_receivers, ground.size()) << name;
    // The tiles are computed on the fast path (not sent to the exact engine).
    EXPECT_LT(fast.stats.fast_exact_fallbacks, 1 + fast.stats.tiles / 10) << name;
    expect_fast_within_bounds(exact, fast, name);
    for (const FaceLighting& f : fast.lighting) {
      // The grounds are shaded, so their bounds are reported (and small).
      if (scene.faces[f.face_id].mesh == 0 && f.faces_light) {
        EXPECT_GT(f.lit_area_error_bound, 0.0) << name << " face " << f.face_id;
        EXPECT_LT(f.lit_area_error_bound, 1e-6 * f.area) << name << " face " << f.face_id;
      }
    }
    expect_fragments_add_up(fast, name, [](const FaceLighting& l) { return 2 * l.lit_area_error_bound; });
    // Areas only: the same bounds hold.
    const ShadowResult fast_areas = compute_shadows(scene, options(Arithmetic::Fast, 30, false));
    expect_fast_within_bounds(exact, fast_areas, name + ", areas only");
  }
}

TEST(Tiles, NonRectangularReceiversDoNotDependOnTheThreadCount) {
  const auto grounds = odd_grounds(100);
  for (const std::size_t g : {std::size_t{0}, std::size_t{4}, std::size_t{7}}) {  // triangle, courtyard, north gable
    const Scene scene = city_on(grounds[g].second, 80, 100, 12, 3, false);
    for (Arithmetic a : {Arithmetic::Exact, Arithmetic::Fast}) {
      const ShadowResult one = compute_shadows(scene, options(a, 25, true, 1));
      const ShadowResult three = compute_shadows(scene, options(a, 25, true, 3));
      ASSERT_GE(one.stats.tiled_receivers, grounds[g].second.size());
      expect_same_bits(one, three, grounds[g].first);
      ASSERT_EQ(one.fragments.size(), three.fragments.size());
      for (std::size_t n = 0; n < one.fragments.size(); ++n) {
        EXPECT_EQ(one.fragments[n].area, three.fragments[n].area);
        EXPECT_EQ(one.fragments[n].polygon, three.fragments[n].polygon);
      }
    }
  }
}

TEST(Tiles, NonRectangularReceiversInASeries) {
  const auto grounds = odd_grounds(100);
  const Scene scene = city_on(grounds[3].second, 100, 100, 30, 9, false);  // the octagon, alone receiving
  const ShadowEngine engine(scene, 2);
  std::vector<Light> suns;
  for (double elevation : {10.0, 25.0, 50.0}) suns.push_back(directional_light("sun", sun_direction(elevation, 200)));
  SeriesOptions o;
  o.threads = 2;
  o.tile_casters = o.fast_tile_casters = 30;
  const SeriesResult tiled = engine.compute_series(suns, o);
  EXPECT_EQ(tiled.stats.tiled_receivers, suns.size()) << "the octagon should be split at every instant";
  o.tile_casters = o.fast_tile_casters = 0;
  const SeriesResult whole = engine.compute_series(suns, o);
  EXPECT_EQ(whole.stats.tiled_receivers, 0u);
  EXPECT_EQ(tiled.lit_area, whole.lit_area);
  EXPECT_EQ(tiled.lit_fraction, whole.lit_fraction);
  EXPECT_EQ(tiled.faces_light, whole.faces_light);
  // Fast, tiled: within its bounds of the exact values.
  o.arithmetic = Arithmetic::Fast;
  o.tile_casters = o.fast_tile_casters = 30;
  const SeriesResult fast = engine.compute_series(suns, o);
  EXPECT_EQ(fast.stats.tiled_receivers, suns.size());
  for (std::size_t n = 0; n < whole.lit_area.size(); ++n)
    EXPECT_LE(std::abs(fast.lit_area[n] - whole.lit_area[n]), fast.lit_area_error_bound[n]) << n;
}

TEST(Tiles, DefaultsLeaveSmallScenesWhole) {
  const Scene scene = city(100, 100, 12, 3);
  const ShadowResult r = compute_shadows(scene, ShadowOptions{});
  EXPECT_EQ(r.stats.tiled_receivers, 0u);
  EXPECT_EQ(r.stats.tiles, 0u);
}

}  // namespace
}  // namespace shadow
