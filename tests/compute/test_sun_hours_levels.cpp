// SPDX-License-Identifier: GPL-3.0-or-later
// The sun-hours map cut into strips, and the threshold map (SunHoursOptions::strip_edges and
// levels, shadow/sun_hours.hpp): areas worked out by hand (a box under three suns), strips
// against the single arrangement (exact areas per hours, bit for bit, on a city and on seeded
// random scenes), the threshold map's level areas against the full map's areas, its cells against
// an independent ray caster, its file, and its levels parsed from the command line's text. The
// instants computed a batch at a time (SunHoursOptions::instant_batch), gathered or streamed
// (stream_levels), and the exact boundaries held in a budget (level_held_segments), against all
// at once: the same exact areas, bit for bit, at 1 and 2 threads.
#include "support/polygon_tools.hpp"
#include "support/ray_caster.hpp"
#include "support/scene_builders.hpp"

#include <shadow/error.hpp>
#include <shadow/generators.hpp>
#include <shadow/output.hpp>
#include <shadow/scene_io.hpp>
#include <shadow/shadows.hpp>
#include <shadow/sun_hours.hpp>

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace shadow {
namespace {

using test::faces_of_mesh;  // support/scene_builders.hpp

std::vector<std::size_t> all_faces(const Scene& scene) {
  std::vector<std::size_t> faces(scene.faces.size());
  for (std::size_t f = 0; f < faces.size(); ++f) faces[f] = f;
  return faces;
}

/// A 2 x 2 x 2 box on a 20 x 20 ground.
Scene box_scene() {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-10, -10, 10, 10, 0)});
  add_mesh(scene, "box", box_faces({0, 0, 0}, {2, 2, 2}));
  validate_scene(scene);
  return scene;
}

// Three suns: from +x at 45 degrees (1 h; shadow [-2, 0] x [0, 2]), from +y at 45 degrees (2 h;
// shadow [0, 2] x [-2, 0]), from +x at tan e = 2 (0.5 h; shadow [-1, 0] x [0, 2]). By hand: the
// footprint 0 h (4); [-1, 0] x [0, 2]: the second sun only, 2 h (2); [-2, -1] x [0, 2]: 2.5 h
// (2); [0, 2] x [-2, 0]: 1.5 h (4); the rest 3.5 h (400 - 12 = 388). Exact in binary.
const std::vector<SunHoursInstant>& box_suns() {
  static const std::vector<SunHoursInstant> suns{{directional_light("a", {1, 0, 1}), 1.0},
                                                 {directional_light("b", {0, 1, 1}), 2.0},
                                                 {directional_light("c", {1, 0, 2}), 0.5}};
  return suns;
}

void expect_box_areas(const SunHoursMap& map) {
  ASSERT_EQ(map.faces.size(), 1u);
  const std::vector<SunHoursArea>& areas = map.faces[0].areas;
  ASSERT_EQ(areas.size(), 5u);
  const double hours[] = {0, 1.5, 2, 2.5, 3.5}, area[] = {4, 4, 2, 2, 388};
  for (std::size_t k = 0; k < 5; ++k) {
    EXPECT_EQ(areas[k].sun_hours, hours[k]);
    EXPECT_EQ(areas[k].area, area[k]) << hours[k] << " h";
  }
}

TEST(SunHoursLevels, BoxUnderThreeSunsHasTheAreasWorkedOutByHand) {
  const Scene scene = box_scene();
  const ShadowEngine engine(scene, 2);
  SunHoursOptions options;
  options.threads = 2;
  options.levels = {3, 1.5, 2, 0, 3.5, 2, 4};  // any order, repeats dropped
  for (const std::size_t strip_edges : {std::size_t{0}, std::size_t{4}}) {
    options.strip_edges = strip_edges;  // one arrangement, then strips of about 4 segments
    const SunHoursMap map = compute_sun_hours_map(engine, faces_of_mesh(scene, 0), box_suns(), options);
    expect_box_areas(map);
    ASSERT_EQ(map.levels, (std::vector<double>{0, 1.5, 2, 3, 3.5, 4}));
    const std::vector<double> want{400 - 4 + 4, 396, 392, 388, 388, 0};
    EXPECT_EQ(map.faces[0].level_areas[0], 400.0);
    for (std::size_t k = 1; k < want.size(); ++k) EXPECT_EQ(map.faces[0].level_areas[k], want[k]) << map.levels[k] << " h";
    EXPECT_EQ(sun_hours_level_areas(map)[2], 392.0);
    EXPECT_EQ(sun_hours_map_area(map), 400.0);
    // Level cells: the footprint (below 1.5: level 0), the 1.5 h square, the 2 h and 2.5 h
    // strips (one level-2 region), the rest (level 3.5).
    std::map<double, double> by_level;
    for (const SunHoursCell& c : map.level_cells) by_level[c.sun_hours] += c.area;
    ASSERT_EQ(by_level.size(), 4u);
    EXPECT_NEAR(by_level[0], 4, 1e-12);
    EXPECT_NEAR(by_level[1.5], 4, 1e-12);
    EXPECT_NEAR(by_level[2], 4, 1e-12);
    EXPECT_NEAR(by_level[3.5], 388, 1e-10);
    if (strip_edges == 0) EXPECT_EQ(map.level_regions, 4u);
    EXPECT_LE(map.level_regions, map.regions);
  }
  // The threshold map alone, the suns fed one, two and all at a time: the same areas by hand.
  options.full = false;
  for (const std::size_t batch : {std::size_t{1}, std::size_t{2}, std::size_t{0}}) {
    options.instant_batch = batch;
    const SunHoursMap only = compute_sun_hours_map(engine, faces_of_mesh(scene, 0), box_suns(), options);
    EXPECT_EQ(only.faces[0].level_areas, (std::vector<double>{400, 396, 392, 388, 388, 0})) << "batch " << batch;
    EXPECT_EQ(only.faces[0].hour_area, 4 * 1.5 + 2 * 2 + 2 * 2.5 + 388 * 3.5) << "batch " << batch;
    EXPECT_EQ(only.faces[0].instants_lit, 3u);
  }
}

// Instants of a weight a double cannot hold (a 20-minute step: 1/3 h each). Three of them make
// exactly 1 hour: the part lit under all three reaches the level 1 h, and the full map says 1 h
// there. Summed as the doubles' own values they made 1 - 2^-54 and the level had no area
// (a 10-minute step lost every region of exactly 2, 4, 6 h the same way).
TEST(SunHoursLevels, StepsOfThirdsReachTheirLevelsExactly) {
  const Scene scene = box_scene();
  const ShadowEngine engine(scene, 2);
  std::vector<SunHoursInstant> thirds = box_suns();
  for (SunHoursInstant& instant : thirds) instant.hours = 1.0 / 3.0;
  SunHoursOptions options;
  options.threads = 2;
  options.levels = {0.5, 1};
  // By hand (box_suns): every sun lights 388, two of them 2 + 4 + 2 more, one of them 2.
  const SunHoursMap map = compute_sun_hours_map(engine, faces_of_mesh(scene, 0), thirds, options);
  ASSERT_EQ(map.faces.size(), 1u);
  EXPECT_EQ(map.faces[0].level_areas, (std::vector<double>{394, 388}));
  EXPECT_EQ(map.total_hours, 1.0);
  const std::vector<SunHoursArea>& areas = map.faces[0].areas;
  ASSERT_EQ(areas.size(), 4u);
  EXPECT_EQ(areas[0].sun_hours, 0.0);
  EXPECT_EQ(areas[1].sun_hours, 1.0 / 3.0);
  EXPECT_EQ(areas[2].sun_hours, 2.0 / 3.0);
  EXPECT_EQ(areas[3].sun_hours, 1.0);
  EXPECT_EQ(areas[3].area, 388.0);
  options.full = false;
  for (const std::size_t batch : {std::size_t{1}, std::size_t{0}}) {
    options.instant_batch = batch;
    const SunHoursMap only = compute_sun_hours_map(engine, faces_of_mesh(scene, 0), thirds, options);
    EXPECT_EQ(only.faces[0].level_areas, (std::vector<double>{394, 388})) << "batch " << batch;
  }
  // A weight with no fraction of small denominator behind it is summed as the double it is.
  std::vector<SunHoursInstant> odd = box_suns();
  for (SunHoursInstant& instant : odd) instant.hours = 0.1 + 1e-12;
  options.full = true;
  options.instant_batch = 0;
  const SunHoursMap plain = compute_sun_hours_map(engine, faces_of_mesh(scene, 0), odd, options);
  const double a = 0.1 + 1e-12;
  EXPECT_EQ(plain.faces[0].areas.back().sun_hours, 2 * a + a);  // 3a rounded once (2a is exact)
}

/// Exact areas per hours, face by face.
void expect_same_areas(const SunHoursMap& a, const SunHoursMap& b) {
  ASSERT_EQ(a.faces.size(), b.faces.size());
  for (std::size_t k = 0; k < a.faces.size(); ++k) {
    const SunHoursFace &fa = a.faces[k], &fb = b.faces[k];
    EXPECT_EQ(fa.face_id, fb.face_id);
    EXPECT_EQ(fa.hour_area, fb.hour_area);
    EXPECT_EQ(fa.level_areas, fb.level_areas) << "face " << fa.face_id;
    ASSERT_EQ(fa.areas.size(), fb.areas.size()) << "face " << fa.face_id;
    for (std::size_t h = 0; h < fa.areas.size(); ++h) {
      EXPECT_EQ(fa.areas[h].sun_hours, fb.areas[h].sun_hours) << "face " << fa.face_id;
      EXPECT_EQ(fa.areas[h].area, fb.areas[h].area) << "face " << fa.face_id << ", " << fa.areas[h].sun_hours << " h";
    }
  }
}

/// The threshold map against the full map: the area at level h is the full map's area with at
/// least h hours (exactly when one hours value reaches h; else to the rounding of the terms).
void expect_levels_match_full(const SunHoursMap& map) {
  for (const SunHoursFace& f : map.faces) {
    for (std::size_t k = 0; k < map.levels.size(); ++k) {
      double sum = 0;
      std::size_t terms = 0;
      for (const SunHoursArea& a : f.areas)
        if (a.sun_hours >= map.levels[k]) sum += a.area, ++terms;
      if (terms <= 1)
        EXPECT_EQ(f.level_areas[k], sum) << "face " << f.face_id << " level " << map.levels[k];
      else
        EXPECT_NEAR(f.level_areas[k], sum, 1e-14 * static_cast<double>(terms) * f.area);
    }
  }
}

/// Random points inside the threshold map's cells reach the cell's level and not the next
/// (rays against every instant, as test_sun_hours_map does for the full map).
int expect_level_points(const Scene& scene, const SunHoursMap& map, const std::vector<SunHoursInstant>& instants,
                        std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  int decided = 0;
  for (const SunHoursCell& cell : map.level_cells) {
    for (const glm::dvec3& p : test::sample_interior(cell.polygon, 3, 1e-6 * std::max(1.0, std::sqrt(cell.area)), rng)) {
      double hours = 0.0;
      bool sure = true;
      for (const SunHoursInstant& instant : instants) {
        const test::RayVerdict v = test::cast_shadow_ray(scene, cell.face_id, p, instant.light, 1e-7);
        if (v == test::RayVerdict::Unsure) sure = false;
        if (v == test::RayVerdict::Lit) hours += instant.hours;
      }
      if (!sure) continue;
      ++decided;
      double level = 0;
      for (double h : map.levels)
        if (hours >= h - 1e-9) level = h;
      EXPECT_EQ(level, cell.sun_hours) << "face " << cell.face_id << ": " << hours << " h";
    }
  }
  return decided;
}

TEST(SunHoursLevels, StripsGiveTheSingleArrangementsAreasOnACity) {
  Scene scene = make_city(10, 60, 11);
  validate_scene(scene);
  std::vector<SunHoursInstant> instants;
  for (int k = 0; k < 8; ++k)
    instants.push_back({directional_light("s" + std::to_string(k), sun_direction(15 + 8 * k, 80 + 28 * k)),
                        0.25 * (k + 1)});
  const ShadowEngine engine(scene, 2);
  SunHoursOptions options;
  options.threads = 2;
  options.levels = {1, 2.5, 4, 6};
  options.strip_edges = 0;  // the map as it was: one arrangement per face
  const SunHoursMap one = compute_sun_hours_map(engine, all_faces(scene), instants, options);
  for (const std::size_t strip_edges : {std::size_t{40}, std::size_t{300}}) {
    options.strip_edges = strip_edges;
    const SunHoursMap strips = compute_sun_hours_map(engine, all_faces(scene), instants, options);
    expect_same_areas(one, strips);
    EXPECT_GT(strips.regions, one.regions);  // the ground's regions are cut at the strips' sides
  }
  expect_levels_match_full(one);
  EXPECT_GT(expect_level_points(scene, one, instants, 5), 100);
  // Only the threshold map (instant by instant, merging decided cells on the way): the same
  // exact level areas, the same regions' areas per level, no full cells; with strips and without.
  options.strip_edges = 40;
  const SunHoursMap with_full = compute_sun_hours_map(engine, all_faces(scene), instants, options);
  EXPECT_GT(expect_level_points(scene, with_full, instants, 6), 100);
  options.full = false;
  // Rounds of about 8 segments (many rounds, decided cells merged between them) and of 1,000
  // (one or two): the same areas.
  for (const auto [strip_edges, round_edges] : {std::pair<std::size_t, std::size_t>{0, 8}, {40, 1000}, {0, 1000}}) {
    options.strip_edges = strip_edges;
    options.level_round_edges = round_edges;
    const SunHoursMap only = compute_sun_hours_map(engine, all_faces(scene), instants, options);
    EXPECT_TRUE(only.cells.empty());
    for (std::size_t k = 0; k < only.faces.size(); ++k)
      EXPECT_EQ(only.faces[k].level_areas, with_full.faces[k].level_areas) << "face " << only.faces[k].face_id;
    std::map<std::pair<std::size_t, double>, double> a, b;  // (face, level): area of its cells
    for (const SunHoursCell& c : only.level_cells) a[{c.face_id, c.sun_hours}] += c.area;
    for (const SunHoursCell& c : with_full.level_cells) b[{c.face_id, c.sun_hours}] += c.area;
    ASSERT_EQ(a.size(), b.size());
    for (const auto& [key, area] : a) EXPECT_NEAR(area, b[key], 1e-9 * (1 + area));
    EXPECT_GT(expect_level_points(scene, only, instants, 7), 100);
  }
  // add_sun_hours_levels (how the CLI adds levels to a map gathered from several processes).
  options.levels.clear();
  options.full = true;
  SunHoursMap added = compute_sun_hours_map(engine, all_faces(scene), instants, options);
  add_sun_hours_levels(added, engine, all_faces(scene), instants, {1, 2.5, 4, 6}, 2);
  EXPECT_FALSE(added.level_cells.empty());
  EXPECT_EQ(added.levels, one.levels);
  for (std::size_t k = 0; k < added.faces.size(); ++k) EXPECT_EQ(added.faces[k].level_areas, one.faces[k].level_areas);
}

// A low top level under a day of many small suns, in many small rounds: most cells reach the top
// level long before the end, many of them settled there from below by the tiles (the instants
// sure to light every tile under them), rounds before their hours get there. The threshold map
// alone has the full map's exact level areas all the same, and sampled points their levels.
TEST(SunHoursLevels, CellsSettledAtTheTopLevelKeepTheAreas) {
  Scene scene = make_city(10, 60, 11);
  validate_scene(scene);
  std::vector<SunHoursInstant> instants;
  for (int k = 0; k < 40; ++k)
    instants.push_back({directional_light("s" + std::to_string(k), sun_direction(10 + 40 * std::sin(k * 0.0785), 70 + 5.5 * k)),
                        0.125});
  const ShadowEngine engine(scene, 2);
  SunHoursOptions options;
  options.threads = 2;
  options.levels = {0.5, 1.5};
  const SunHoursMap full = compute_sun_hours_map(engine, all_faces(scene), instants, options);
  options.full = false;
  for (const std::size_t round_edges : {std::size_t{8}, std::size_t{60}}) {
    options.level_round_edges = round_edges;
    const SunHoursMap only = compute_sun_hours_map(engine, all_faces(scene), instants, options);
    for (std::size_t k = 0; k < only.faces.size(); ++k)
      EXPECT_EQ(only.faces[k].level_areas, full.faces[k].level_areas) << "face " << only.faces[k].face_id;
    EXPECT_GT(expect_level_points(scene, only, instants, 8 + round_edges), 100);
  }
}

// Seeded random scenes (boxes, floating and tilted polygons, a point or directional light) under
// that light and four random suns of random weights: strips of a few segments give the single
// arrangement's exact areas per hours and per level, bit for bit.
RC_GTEST_PROP(SunHoursLevelsProperties, StripsKeepExactAreasOnRandomScenes, ()) {
  const auto seed = *rc::gen::inRange<std::uint64_t>(0, 1u << 30);
  Scene scene = test::random_scene(seed);
  validate_scene(scene);
  std::vector<SunHoursInstant> instants{{scene.lights.at(0), 1.0}};
  for (int k = 0; k < 4; ++k) {
    const double elevation = *rc::gen::inRange(8, 85);
    const double azimuth = *rc::gen::inRange(0, 360);
    instants.push_back({directional_light("s" + std::to_string(k), sun_direction(elevation, azimuth)),
                        0.25 * *rc::gen::inRange(1, 12)});
  }
  const ShadowEngine engine(scene, 1);
  SunHoursOptions options;
  options.threads = 1;
  options.levels = {0.5, 1.25, 2, 3.5};
  options.strip_edges = 0;
  const SunHoursMap one = compute_sun_hours_map(engine, all_faces(scene), instants, options);
  options.strip_edges = *rc::gen::inRange<std::size_t>(2, 12);
  const SunHoursMap strips = compute_sun_hours_map(engine, all_faces(scene), instants, options);
  options.full = false;
  options.level_round_edges = *rc::gen::inRange<std::size_t>(1, 40);  // from one instant per round up
  const SunHoursMap only = compute_sun_hours_map(engine, all_faces(scene), instants, options);
  options.level_held_segments = *rc::gen::inRange<std::size_t>(0, 200);  // lit regions computed again
  const SunHoursMap held = compute_sun_hours_map(engine, all_faces(scene), instants, options);
  options.level_held_segments = SunHoursOptions{}.level_held_segments;
  options.instant_batch = *rc::gen::inRange<std::size_t>(1, 5);  // streamed: 1 to 4 instants at a time
  options.stream_levels = true;
  const SunHoursMap streamed = compute_sun_hours_map(engine, all_faces(scene), instants, options);
  RC_ASSERT(one.faces.size() == strips.faces.size());
  RC_ASSERT(only.faces.size() == one.faces.size());
  RC_ASSERT(held.faces.size() == one.faces.size());
  RC_ASSERT(streamed.faces.size() == one.faces.size());
  for (std::size_t k = 0; k < one.faces.size(); ++k) {
    RC_ASSERT(only.faces[k].level_areas == one.faces[k].level_areas);
    RC_ASSERT(held.faces[k].level_areas == one.faces[k].level_areas);
    RC_ASSERT(streamed.faces[k].level_areas == one.faces[k].level_areas);
    RC_ASSERT(streamed.faces[k].hour_area == one.faces[k].hour_area);
  }
  for (std::size_t k = 0; k < one.faces.size(); ++k) {
    const SunHoursFace &a = one.faces[k], &b = strips.faces[k];
    RC_ASSERT(a.level_areas == b.level_areas);
    RC_ASSERT(a.areas.size() == b.areas.size());
    for (std::size_t h = 0; h < a.areas.size(); ++h) {
      RC_ASSERT(a.areas[h].sun_hours == b.areas[h].sun_hours);
      RC_ASSERT(a.areas[h].area == b.areas[h].area);
    }
    // The level areas against the full map's.
    for (std::size_t l = 0; l < one.levels.size(); ++l) {
      double sum = 0;
      for (const SunHoursArea& x : a.areas)
        if (x.sun_hours >= one.levels[l]) sum += x.area;
      RC_ASSERT(std::abs(a.level_areas[l] - sum) <= 1e-13 * (1.0 + a.area));
    }
  }
}

/// `count` suns sweeping from east to west, low to high to low (4 to 54 degrees), of weights
/// 0.25, 0.5 and 0.75 hours in turn.
std::vector<SunHoursInstant> east_to_west(int count) {
  std::vector<SunHoursInstant> instants;
  for (int k = 0; k < count; ++k) {
    const double t = (k + 0.5) / count;
    instants.push_back({directional_light("s" + std::to_string(k), sun_direction(4 + 50 * std::sin(3.14159 * t), 75 + 210 * t)),
                        0.25 * (1 + k % 3)});
  }
  return instants;
}

/// Every exact area of two maps, bit for bit (the areas per hours only where both have them).
void expect_same_exact_areas(const SunHoursMap& a, const SunHoursMap& b, const std::string& what) {
  ASSERT_EQ(a.faces.size(), b.faces.size()) << what;
  for (std::size_t k = 0; k < a.faces.size(); ++k) {
    const SunHoursFace &fa = a.faces[k], &fb = b.faces[k];
    EXPECT_EQ(fa.face_id, fb.face_id) << what;
    EXPECT_EQ(fa.area, fb.area) << what;
    EXPECT_EQ(fa.hour_area, fb.hour_area) << what << ", face " << fa.face_id;
    EXPECT_EQ(fa.instants_lit, fb.instants_lit) << what << ", face " << fa.face_id;
    EXPECT_EQ(fa.level_areas, fb.level_areas) << what << ", face " << fa.face_id;
    EXPECT_EQ(fa.areas.size(), fb.areas.size()) << what << ", face " << fa.face_id;
    for (std::size_t h = 0; h < std::min(fa.areas.size(), fb.areas.size()); ++h) {
      EXPECT_EQ(fa.areas[h].sun_hours, fb.areas[h].sun_hours) << what << ", face " << fa.face_id;
      EXPECT_EQ(fa.areas[h].area, fb.areas[h].area) << what << ", face " << fa.face_id;
    }
  }
}

// Streamed over more suns than a face's strips are chosen from (16), rounds run before the last
// batch, while instants are still to come, and some faces (walls facing east) get no boundary
// from the later suns: their rounds then end with cells still open, which the last round must
// settle. East to west, 24 suns; the level areas those of every instant at once, exactly.
TEST(SunHoursLevels, StreamedRoundsBeforeTheLastBatchSettleEveryCell) {
  Scene scene = make_city(10, 60, 11);
  validate_scene(scene);
  const std::vector<SunHoursInstant> instants = east_to_west(24);
  const ShadowEngine engine(scene, 2);
  SunHoursOptions options;
  options.threads = 2;
  options.levels = {1, 2.5, 4, 6};
  options.full = false;
  const SunHoursMap all = compute_sun_hours_map(engine, all_faces(scene), instants, options);
  options.stream_levels = true;
  for (const auto [strip_edges, round_edges] : {std::pair<std::size_t, std::size_t>{0, 8}, {40, 8}, {40, 1000}})
    for (const std::size_t batch : {std::size_t{1}, std::size_t{3}}) {
      options.strip_edges = strip_edges;
      options.level_round_edges = round_edges;
      options.instant_batch = batch;
      const SunHoursMap streamed = compute_sun_hours_map(engine, all_faces(scene), instants, options);
      expect_same_exact_areas(all, streamed, "strips " + std::to_string(strip_edges) + ", rounds " +
                                                 std::to_string(round_edges) + ", batch " + std::to_string(batch));
    }
}

// A city under 16 suns sweeping from east to west, low to high to low, of unequal weights: walls
// dark under the first suns and cut by later ones, roofs lit whole. The instants' lit regions
// computed all at once (instant_batch 0) and 1, 3 and 7 at a time, gathered (the default: the
// same cells, bit for bit) and streamed (stream_levels): the threshold map alone has the same
// exact level areas, integral and lit instants, face by face, at 1 and 2 threads, with strips
// and without, small rounds and large; its cells cover each level with the same area; the full
// map is the same cell for cell.
TEST(SunHoursLevels, StreamedInstantsGiveTheAreasOfAllAtOnce) {
  Scene scene = make_city(10, 60, 11);
  validate_scene(scene);
  const std::vector<SunHoursInstant> instants = east_to_west(16);
  for (const unsigned threads : {1u, 2u}) {
    const ShadowEngine engine(scene, threads);
    SunHoursOptions options;
    options.threads = threads;
    options.levels = {1, 2.5, 4, 6};
    options.full = false;
    for (const auto [strip_edges, round_edges] : {std::pair<std::size_t, std::size_t>{0, 8}, {40, 1000}}) {
      options.strip_edges = strip_edges;
      options.level_round_edges = round_edges;
      options.instant_batch = 0;
      const SunHoursMap all = compute_sun_hours_map(engine, all_faces(scene), instants, options);
      std::map<std::pair<std::size_t, double>, double> want;  // (face, level): area of its cells
      for (const SunHoursCell& c : all.level_cells) want[{c.face_id, c.sun_hours}] += c.area;
      for (const std::size_t batch : {std::size_t{1}, std::size_t{3}, std::size_t{7}}) {
        options.instant_batch = batch;
        // Gathered (the default): the batches' boundaries held until the last, then the rounds
        // of all at once, so the same cells, bit for bit.
        options.stream_levels = false;
        const SunHoursMap gathered = compute_sun_hours_map(engine, all_faces(scene), instants, options);
        const std::string what = std::to_string(threads) + " threads, strips " + std::to_string(strip_edges) +
                                 ", rounds " + std::to_string(round_edges) + ", batch " + std::to_string(batch);
        expect_same_exact_areas(all, gathered, what + ", gathered");
        ASSERT_EQ(all.level_cells.size(), gathered.level_cells.size()) << what;
        for (std::size_t c = 0; c < all.level_cells.size(); ++c) {
          EXPECT_EQ(all.level_cells[c].polygon, gathered.level_cells[c].polygon) << what;
          EXPECT_EQ(all.level_cells[c].area, gathered.level_cells[c].area) << what;
          EXPECT_EQ(all.level_cells[c].sun_hours, gathered.level_cells[c].sun_hours) << what;
          EXPECT_EQ(all.level_cells[c].region_id, gathered.level_cells[c].region_id) << what;
        }
        // Streamed: the same exact areas; the cells cover each level with the same area.
        options.stream_levels = true;
        const SunHoursMap streamed = compute_sun_hours_map(engine, all_faces(scene), instants, options);
        options.stream_levels = false;
        expect_same_exact_areas(all, streamed, what);
        std::map<std::pair<std::size_t, double>, double> got;
        for (const SunHoursCell& c : streamed.level_cells) got[{c.face_id, c.sun_hours}] += c.area;
        ASSERT_EQ(got.size(), want.size()) << what;
        for (const auto& [key, area] : got) EXPECT_NEAR(area, want[key], 1e-9 * (1 + area)) << what;
        if (threads == 2 && batch == 3 && strip_edges == 40) EXPECT_GT(expect_level_points(scene, streamed, instants, 9), 100);
      }
    }
    // The full map gathers every boundary whatever the batch: the same cells, bit for bit.
    options.full = true;
    options.strip_edges = 40;
    options.instant_batch = 0;
    const SunHoursMap all = compute_sun_hours_map(engine, all_faces(scene), instants, options);
    options.instant_batch = 3;
    const SunHoursMap streamed = compute_sun_hours_map(engine, all_faces(scene), instants, options);
    expect_same_exact_areas(all, streamed, "full map");
    ASSERT_EQ(all.cells.size(), streamed.cells.size());
    for (std::size_t c = 0; c < all.cells.size(); ++c) {
      EXPECT_EQ(all.cells[c].polygon, streamed.cells[c].polygon);
      EXPECT_EQ(all.cells[c].area, streamed.cells[c].area);
      EXPECT_EQ(all.cells[c].sun_hours, streamed.cells[c].sun_hours);
      EXPECT_EQ(all.cells[c].region_id, streamed.cells[c].region_id);
    }
    EXPECT_EQ(all.level_cells.size(), streamed.level_cells.size());
  }
}

// The threshold map alone holding few exact boundary segments (SunHoursOptions::
// level_held_segments): faces past the budget have their lit regions computed again, a wave of
// strips and a band of instants at a time (0: one strip and four instants). The same exact level
// areas, integral and lit instants, face by face, as holding every boundary; its cells cover each
// level with the same area, hold under the ray caster, and do not depend on the threads nor on
// the batches the instants were first computed in.
TEST(SunHoursLevels, HeldSegmentsBoundMemoryNotAreas) {
  Scene scene = make_city(10, 60, 11);
  validate_scene(scene);
  const std::vector<SunHoursInstant> instants = east_to_west(16);
  SunHoursOptions options;
  options.levels = {1, 2.5, 4, 6};
  options.full = false;
  for (const auto [strip_edges, round_edges] : {std::pair<std::size_t, std::size_t>{0, 8}, {40, 8}, {40, 1000}}) {
    options.strip_edges = strip_edges;
    options.level_round_edges = round_edges;
    options.threads = 2;
    options.instant_batch = 16;
    options.level_held_segments = SunHoursOptions{}.level_held_segments;
    const ShadowEngine engine(scene, 2);
    const SunHoursMap all = compute_sun_hours_map(engine, all_faces(scene), instants, options);
    std::map<std::pair<std::size_t, double>, double> want;  // (face, level): area of its cells
    for (const SunHoursCell& c : all.level_cells) want[{c.face_id, c.sun_hours}] += c.area;
    for (const std::size_t held : {std::size_t{0}, std::size_t{40}, std::size_t{400}, std::size_t{4000}}) {
      const std::string what = "strips " + std::to_string(strip_edges) + ", rounds " + std::to_string(round_edges) +
                               ", held " + std::to_string(held);
      options.level_held_segments = held;
      options.threads = 2;
      options.instant_batch = 16;
      // The progress counts the face-instant pairs computed again: some are, below 4000.
      std::size_t total = 0;
      options.progress = [&total](const Progress& p) { total = std::max(total, p.total); };
      const SunHoursMap bounded = compute_sun_hours_map(engine, all_faces(scene), instants, options);
      options.progress = nullptr;
      if (held < 4000) EXPECT_GT(total, scene.faces.size() * (instants.size() + 1)) << what;
      expect_same_exact_areas(all, bounded, what);
      std::map<std::pair<std::size_t, double>, double> got;
      for (const SunHoursCell& c : bounded.level_cells) got[{c.face_id, c.sun_hours}] += c.area;
      ASSERT_EQ(got.size(), want.size()) << what;
      for (const auto& [key, area] : got) EXPECT_NEAR(area, want[key], 1e-9 * (1 + area)) << what;
      if (held == 40 && strip_edges == 40 && round_edges == 8)
        EXPECT_GT(expect_level_points(scene, bounded, instants, 9), 100) << what;
      // One thread, and the instants first computed 3 at a time: the same cells, bit for bit.
      const ShadowEngine one(scene, 1);
      options.threads = 1;
      options.instant_batch = 3;
      const SunHoursMap again = compute_sun_hours_map(one, all_faces(scene), instants, options);
      ASSERT_EQ(again.level_cells.size(), bounded.level_cells.size()) << what;
      for (std::size_t c = 0; c < again.level_cells.size(); ++c) {
        EXPECT_EQ(again.level_cells[c].polygon, bounded.level_cells[c].polygon) << what;
        EXPECT_EQ(again.level_cells[c].area, bounded.level_cells[c].area) << what;
        EXPECT_EQ(again.level_cells[c].sun_hours, bounded.level_cells[c].sun_hours) << what;
      }
    }
  }
}

TEST(SunHoursLevels, WritesTheThresholdMapVtp) {
  const Scene scene = box_scene();
  const ShadowEngine engine(scene, 1);
  SunHoursOptions options;
  options.threads = 1;
  options.levels = {2, 3};
  options.full = false;
  const SunHoursMap map = compute_sun_hours_map(engine, faces_of_mesh(scene, 0), box_suns(), options);
  EXPECT_TRUE(map.cells.empty());
  EXPECT_TRUE(map.faces[0].areas.empty());
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "sun_hours_levels_test";
  std::filesystem::create_directories(dir);
  const std::filesystem::path file = dir / "sun_hours_levels.vtp";
  write_sun_hours_levels_vtp(file, map, scene);
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(file.string().c_str());
  reader->Update();
  vtkPolyData* poly = reader->GetOutput();
  ASSERT_EQ(poly->GetNumberOfCells(), static_cast<vtkIdType>(map.level_cells.size()));
  vtkDataArray* level = poly->GetCellData()->GetArray("level");
  ASSERT_NE(level, nullptr);
  double at_least_two = 0;
  for (vtkIdType c = 0; c < poly->GetNumberOfCells(); ++c) {
    EXPECT_EQ(level->GetTuple1(c), map.level_cells[static_cast<std::size_t>(c)].sun_hours);
    if (level->GetTuple1(c) >= 2) at_least_two += poly->GetCellData()->GetArray("area")->GetTuple1(c);
  }
  EXPECT_NEAR(at_least_two, 392, 1e-10);
  vtkDataArray* areas = poly->GetFieldData()->GetArray("level_areas");
  ASSERT_NE(areas, nullptr);
  EXPECT_EQ(areas->GetTuple1(0), 392.0);
  EXPECT_EQ(areas->GetTuple1(1), 388.0);
  EXPECT_EQ(poly->GetFieldData()->GetArray("levels")->GetTuple1(1), 3.0);
  EXPECT_EQ(poly->GetFieldData()->GetArray("area")->GetTuple1(0), 400.0);
  const std::string summary = sun_hours_levels_summary(map, "  ");
  EXPECT_NE(summary.find("at least 2 h of sun: area 392 of 400 (98.0%)"), std::string::npos) << summary;
  std::filesystem::remove_all(dir);
}

TEST(SunHoursLevels, LevelsAreParsedAndChecked) {
  EXPECT_EQ(parse_sun_hours_levels("2,4,6"), (std::vector<double>{2, 4, 6}));
  EXPECT_EQ(parse_sun_hours_levels("1.5"), (std::vector<double>{1.5}));
  for (const char* bad : {"", "2,,4", "two", "2,-1", "nan", "inf", "2h", ","}) {
    try {
      (void)parse_sun_hours_levels(bad);
      ADD_FAILURE() << "accepted \"" << bad << "\"";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--sun-hours-levels"), std::string::npos) << e.what();
    }
  }
  const Scene scene = box_scene();
  const ShadowEngine engine(scene, 1);
  SunHoursOptions options;
  options.levels = {2, -1};
  EXPECT_THROW((void)compute_sun_hours_map(engine, {0}, box_suns(), options), InputError);
}

}  // namespace
}  // namespace shadow
