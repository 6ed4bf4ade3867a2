// SPDX-License-Identifier: GPL-3.0-or-later
// Tiles of large receivers (ShadowOptions::tile_casters, fast_tile_casters; docs/tiles.md): a
// split receiver's exact areas must be the untiled ones bit for bit, its fast areas within their
// bounds of the exact ones, its fragments (cut at tile borders) must add up to the face and to
// the lit and shadowed areas, and nothing may depend on the thread count. Small thresholds on
// small seeded cities, so that the ground (and some walls) are cut into many tiles.
#include "core/tiles.hpp"

#include <shadow/shadow.hpp>

#include <gtest/gtest.h>

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
    ASSERT_EQ(exact.lighting.size(), fast.lighting.size());
    for (std::size_t n = 0; n < exact.lighting.size(); ++n) {
      const FaceLighting& e = exact.lighting[n];
      const FaceLighting& f = fast.lighting[n];
      EXPECT_LE(std::abs(f.lit_area - e.lit_area), f.lit_area_error_bound) << label << " face " << f.face_id;
      EXPECT_LE(std::abs(f.shadow_area - e.shadow_area), f.lit_area_error_bound) << label << " face " << f.face_id;
      EXPECT_EQ(f.faces_light, e.faces_light);
    }
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

TEST(Tiles, DefaultsLeaveSmallScenesWhole) {
  const Scene scene = city(100, 100, 12, 3);
  const ShadowResult r = compute_shadows(scene, ShadowOptions{});
  EXPECT_EQ(r.stats.tiled_receivers, 0u);
  EXPECT_EQ(r.stats.tiles, 0u);
}

}  // namespace
}  // namespace shadow
