// SPDX-License-Identifier: GPL-3.0-or-later
// The exact sun-hours map (shadow/sun_hours.hpp): checked against the engine's exact lit areas
// (the integral), an independent ray caster (points inside cells), areas worked out by hand
// (a pole under three suns), a courtyard under a sun path, and a single instant (the map is
// that instant's fragments times its weight).
#include "support/polygon_tools.hpp"
#include "support/ray_caster.hpp"
#include "support/scene_builders.hpp"

#include <shadow/error.hpp>
#include <shadow/generators.hpp>
#include <shadow/output.hpp>  // write_sun_hours_vtp
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
#include <vector>

namespace shadow {
namespace {

using test::faces_of_mesh;  // support/scene_builders.hpp

/// Sum over cells of sun_hours x area, per face.
std::map<std::size_t, double> integral_by_face(const SunHoursMap& map) {
  std::map<std::size_t, double> out;
  for (const SunHoursCell& c : map.cells) out[c.face_id] += c.sun_hours * c.area;
  return out;
}

/// (a) The integral: for every face, sum over cells of hours x area (and the exact
/// SunHoursFace::hour_area) equals sum over instants of hours x the engine's exact lit area.
void expect_integral(const ShadowEngine& engine, const SunHoursMap& map, const std::vector<SunHoursInstant>& instants,
                     const std::vector<std::size_t>& faces) {
  std::map<std::size_t, double> expected;
  ShadowOptions options;
  options.polygons = false;
  for (std::size_t i = 0; i < instants.size(); ++i) {
    const ShadowResult r = engine.compute(instants[i].light, i, options);
    for (std::size_t f : faces) {
      const FaceLighting* l = r.find(f, i);
      ASSERT_NE(l, nullptr);
      expected[f] += instants[i].hours * l->lit_area;
    }
  }
  const std::map<std::size_t, double> cells = integral_by_face(map);
  ASSERT_EQ(map.faces.size(), faces.size());
  for (const SunHoursFace& face : map.faces) {
    const double want = expected[face.face_id];
    const double scale = std::max(1.0, map.total_hours * face.area);
    // The exact integral, rounded once, against a sum of rounded terms.
    EXPECT_NEAR(face.hour_area, want, 1e-12 * scale) << "face " << face.face_id;
    // The cells, each rounded, plus what rounding had to drop (at most total hours each).
    const auto it = cells.find(face.face_id);
    const double got = it == cells.end() ? 0.0 : it->second;
    EXPECT_NEAR(got, want, 1e-10 * scale + map.total_hours * face.dropped_area) << "face " << face.face_id;
  }
}

/// (b) Point checks: random points inside cells get the cell's hours from an independent ray
/// cast against every instant. Returns the number of points decided.
int expect_points(const Scene& scene, const SunHoursMap& map, const std::vector<SunHoursInstant>& instants,
                  int per_cell, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  int decided = 0;
  for (const SunHoursCell& cell : map.cells) {
    const double size = std::sqrt(cell.area);
    for (const glm::dvec3& p : test::sample_interior(cell.polygon, per_cell, 1e-6 * std::max(1.0, size), rng)) {
      double hours = 0.0;
      bool sure = true;
      for (const SunHoursInstant& instant : instants) {
        const test::RayVerdict v = test::cast_shadow_ray(scene, cell.face_id, p, instant.light, 1e-7);
        if (v == test::RayVerdict::Unsure) {
          sure = false;
          break;
        }
        if (v == test::RayVerdict::Lit) hours += instant.hours;
      }
      if (!sure) continue;
      ++decided;
      EXPECT_NEAR(hours, cell.sun_hours, 1e-9) << "face " << cell.face_id << " at " << p.x << " " << p.y << " "
                                               << p.z;
    }
  }
  return decided;
}

/// Sum of cell areas by rounded hours.
std::map<double, double> area_by_hours(const SunHoursMap& map) {
  std::map<double, double> out;
  for (const SunHoursCell& c : map.cells) out[c.sun_hours] += c.area;
  return out;
}

/// A pole 0.25 x 0.25 x 4 standing on a 20 x 20 ground.
Scene pole_scene() {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-10, -10, 10, 10, 0)});
  add_mesh(scene, "pole", box_faces({-0.125, -0.125, 0}, {0.125, 0.125, 4}));
  validate_scene(scene);
  return scene;
}

// (c) Three suns of one hour each. From +x at 45 degrees the pole's shadow is the footprint
// swept 4 to -x; from +x at tan = 2, swept 2 to -x; from +y at 45 degrees, swept 4 to -y.
// Under the pole: 0 h (0.25^2). x in [-2.125, -0.125]: shadowed twice, 1 h (0.25 x 2).
// x in [-4.125, -2.125] and y in [-4.125, -0.125]: shadowed once, 2 h (0.25 x 2 + 0.25 x 4).
// Everything else: 3 h (400 - 0.0625 - 0.5 - 1.5). All these are exact in binary.
TEST(SunHoursMap, PoleUnderThreeSunsHasTheAreasWorkedOutByHand) {
  const Scene scene = pole_scene();
  const std::vector<SunHoursInstant> instants{{directional_light("a", {1, 0, 1}), 1.0},
                                              {directional_light("b", {1, 0, 2}), 1.0},
                                              {directional_light("c", {0, 1, 1}), 1.0}};
  const ShadowEngine engine(scene, 2);
  SunHoursOptions options;
  options.threads = 2;
  const std::vector<std::size_t> ground = faces_of_mesh(scene, 0);
  const SunHoursMap map = compute_sun_hours_map(engine, ground, instants, options);
  const std::map<double, double> areas = area_by_hours(map);
  ASSERT_EQ(areas.size(), 4u);
  EXPECT_DOUBLE_EQ(areas.at(0.0), 0.0625);
  EXPECT_DOUBLE_EQ(areas.at(1.0), 0.5);
  EXPECT_DOUBLE_EQ(areas.at(2.0), 1.5);
  EXPECT_DOUBLE_EQ(areas.at(3.0), 397.9375);
  EXPECT_DOUBLE_EQ(map.faces.at(0).hour_area, 0.5 + 2 * 1.5 + 3 * 397.9375);
  EXPECT_DOUBLE_EQ(map.total_hours, 3.0);
  // Regions: the two 2 h arms do not touch, so five regions of equal hours in all.
  std::map<std::size_t, double> region_hours;
  for (const SunHoursCell& c : map.cells) {
    EXPECT_EQ(c.face_id, 0u);
    const auto [it, inserted] = region_hours.emplace(c.region_id, c.sun_hours);
    EXPECT_EQ(it->second, c.sun_hours) << "pieces of one region share its hours";
  }
  EXPECT_EQ(region_hours.size(), 5u);
  expect_integral(engine, map, instants, ground);
  EXPECT_GT(expect_points(scene, map, instants, 40, 1), 100);
}

// Two poles 8.25 apart on the x axis, one sun from +x and one from -x, one hour each: the first
// pole's shadow under the first sun ends exactly where the second pole's shadow under the second
// sun ends (x = -4.125). Across that edge one instant's region begins and the other's ends, so
// both sides have 1 h: merged, they are one region; unmerged, two.
TEST(SunHoursMap, MergingEqualHoursChangesCellsNotHours) {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-20, -10, 10, 10, 0)});
  add_mesh(scene, "pole", box_faces({-0.125, -0.125, 0}, {0.125, 0.125, 4}));
  add_mesh(scene, "pole2", box_faces({-8.375, -0.125, 0}, {-8.125, 0.125, 4}));
  validate_scene(scene);
  const std::vector<SunHoursInstant> instants{{directional_light("a", {1, 0, 1}), 1.0},
                                              {directional_light("b", {-1, 0, 1}), 1.0}};
  const ShadowEngine engine(scene, 1);
  SunHoursOptions options;
  options.threads = 1;
  const SunHoursMap merged = compute_sun_hours_map(engine, {0}, instants, options);
  options.merge_equal = false;
  const SunHoursMap split = compute_sun_hours_map(engine, {0}, instants, options);
  EXPECT_GT(split.cells.size(), merged.cells.size());
  EXPECT_EQ(area_by_hours(split), area_by_hours(merged));
  // The 1 h strip between the poles, x from -8.125 to -0.125, is one region when merged.
  std::map<std::size_t, double> one_hour;
  for (const SunHoursCell& c : merged.cells)
    if (c.sun_hours == 1.0) one_hour[c.region_id] += c.area;
  bool strip = false;
  for (const auto& [region, area] : one_hour) strip |= area == 8.0 * 0.25;
  EXPECT_TRUE(strip);
  // Areas by hand: under the poles 0 h; the strip 1 h (2), the shadows beyond the poles (pole 1
  // under b: x in [0.125, 4.125]; pole 2 under a: x in [-12.375, -8.375]) 1 h (1 each); the rest 2 h.
  const std::map<double, double> areas = area_by_hours(merged);
  EXPECT_DOUBLE_EQ(areas.at(0.0), 2 * 0.0625);
  EXPECT_DOUBLE_EQ(areas.at(1.0), 2.0 + 1.0 + 1.0);
  EXPECT_DOUBLE_EQ(areas.at(2.0), 600.0 - 0.125 - 4.0);
  expect_integral(engine, merged, instants, {0});
  EXPECT_EQ(split.faces.at(0).hour_area, merged.faces.at(0).hour_area);
}

// (d) A courtyard: four wings around an open square, under a sun path of nine instants from
// morning to evening (elevations 10..60 degrees), weights of half an hour to two hours. Ground,
// courtyard walls and roofs are mapped.
TEST(SunHoursMap, CourtyardUnderASunPathMatchesRaysAndTheEngine) {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-20, -20, 20, 20, 0)});
  std::vector<Polygon3> wings;
  for (const auto& [lo, hi] : std::vector<std::pair<glm::dvec3, glm::dvec3>>{
           {{-10, -10, 0}, {10, -6, 9}}, {{-10, 6, 0}, {10, 10, 12}}, {{-10, -6, 0}, {-6, 6, 6}}, {{6, -6, 0}, {10, 6, 15}}})
    for (Polygon3& face : box_faces(lo, hi)) wings.push_back(std::move(face));
  add_mesh(scene, "wings", wings);
  validate_scene(scene);
  std::vector<SunHoursInstant> instants;
  const double elevation[] = {10, 25, 38, 50, 60, 52, 40, 27, 12};
  for (int k = 0; k < 9; ++k) {
    const double azimuth = 90 + 22.5 * k;  // east, through south, to west
    instants.push_back({directional_light("t" + std::to_string(k), sun_direction(elevation[k], azimuth)),
                        0.5 + 0.25 * (k % 7)});
  }
  const ShadowEngine engine(scene, 2);
  SunHoursOptions options;
  options.threads = 2;
  std::size_t progress_calls = 0, last_done = 0, total = 0;
  options.progress = [&](const Progress& p) {
    ++progress_calls;
    EXPECT_GE(p.done, last_done);
    last_done = p.done;
    total = p.total;
  };
  std::vector<std::size_t> faces;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) faces.push_back(f);
  const SunHoursMap map = compute_sun_hours_map(engine, faces, instants, options);
  EXPECT_GT(progress_calls, 0u);
  EXPECT_EQ(last_done, total);
  EXPECT_EQ(total, faces.size() * (instants.size() + 1));
  // Every face is covered once: cell areas add up to the face's area.
  std::map<std::size_t, double> covered;
  for (const SunHoursCell& c : map.cells) {
    covered[c.face_id] += c.area;
    EXPECT_GE(c.sun_hours, 0.0);
    EXPECT_LE(c.sun_hours, map.total_hours);
  }
  for (const SunHoursFace& f : map.faces) EXPECT_NEAR(covered[f.face_id] + f.dropped_area, f.area, 1e-12 * f.area);
  // The courtyard's ground sees fewer hours than the open ground around it, and some of it
  // more than nothing.
  double court_min = 1e9, court_max = 0;
  for (const SunHoursCell& c : map.cells) {
    if (c.face_id != 0) continue;
    glm::dvec3 centre(0.0);
    for (const glm::dvec3& p : c.polygon) centre += p;
    centre /= static_cast<double>(c.polygon.size());
    if (std::abs(centre.x) < 6 && std::abs(centre.y) < 6) {
      court_min = std::min(court_min, c.sun_hours);
      court_max = std::max(court_max, c.sun_hours);
    }
  }
  EXPECT_LT(court_min, map.total_hours);
  EXPECT_GT(court_max, 0.0);
  expect_integral(engine, map, instants, faces);
  EXPECT_GT(expect_points(scene, map, instants, 6, 2), 300);
}

// (e) One instant: the map is that instant's lit fragments, with its weight, and its shadowed
// fragments with 0 hours, on a random small city.
TEST(SunHoursMap, OneInstantIsThatInstantsFragmentsTimesItsWeight) {
  Scene scene = make_city(10, 60, 7);
  validate_scene(scene);
  const Light sun = directional_light("sun", sun_direction(35, 200));
  const ShadowEngine engine(scene, 2);
  std::vector<std::size_t> faces;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) faces.push_back(f);
  SunHoursOptions options;
  options.threads = 2;
  const SunHoursMap map = compute_sun_hours_map(engine, faces, {{sun, 2.5}}, options);
  const ShadowResult result = engine.compute(sun, 0);
  std::map<std::size_t, double> lit, dark, lit_map, dark_map;
  for (const Fragment& f : result.fragments) (f.lit ? lit : dark)[f.face_id] += f.area;
  for (const SunHoursCell& c : map.cells) {
    ASSERT_TRUE(c.sun_hours == 2.5 || c.sun_hours == 0.0) << c.sun_hours;
    (c.sun_hours > 0 ? lit_map : dark_map)[c.face_id] += c.area;
  }
  for (std::size_t f : faces) {
    const FaceLighting* l = result.find(f, 0);
    ASSERT_NE(l, nullptr);
    const double tol = 1e-11 * std::max(1.0, l->area) + l->dropped_area + map.faces[f].dropped_area;
    EXPECT_NEAR(lit_map[f], l->lit_area, tol) << "face " << f;
    EXPECT_NEAR(lit_map[f], lit[f], tol) << "face " << f;
    EXPECT_NEAR(dark_map[f], dark[f], tol) << "face " << f;
    EXPECT_NEAR(map.faces[f].hour_area, 2.5 * l->lit_area, 1e-12 * std::max(1.0, l->area)) << "face " << f;
  }
}

// (a) and (b) on a city of ten boxes under six suns with unequal weights, every face mapped.
TEST(SunHoursMap, CityIntegralAndRaysAgree) {
  Scene scene = make_city(10, 60, 11);
  validate_scene(scene);
  std::vector<SunHoursInstant> instants;
  for (int k = 0; k < 6; ++k)
    instants.push_back({directional_light("s" + std::to_string(k), sun_direction(15 + 9 * k, 80 + 40 * k)),
                        0.25 * (k + 1)});
  const ShadowEngine engine(scene, 2);
  std::vector<std::size_t> faces;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) faces.push_back(f);
  SunHoursOptions options;
  options.threads = 2;
  const SunHoursMap map = compute_sun_hours_map(engine, faces, instants, options);
  expect_integral(engine, map, instants, faces);
  EXPECT_GT(expect_points(scene, map, instants, 2, 3), 200);
  // Threads do not change the result.
  options.threads = 1;
  const SunHoursMap one = compute_sun_hours_map(engine, faces, instants, options);
  ASSERT_EQ(one.cells.size(), map.cells.size());
  for (std::size_t c = 0; c < map.cells.size(); ++c) {
    EXPECT_EQ(one.cells[c].polygon, map.cells[c].polygon);
    EXPECT_EQ(one.cells[c].sun_hours, map.cells[c].sun_hours);
    EXPECT_EQ(one.cells[c].region_id, map.cells[c].region_id);
  }
}

// SunHoursMap::regions: maps of consecutive blocks of the faces, concatenated with each block's
// region ids shifted by the regions before it, are the map of all the faces (how `mpirun shadow
// series` gathers the ranks' blocks, docs/cluster.md).
TEST(SunHoursMap, BlocksOfFacesConcatenateToTheWholeMap) {
  Scene scene = make_city(6, 40, 5);
  validate_scene(scene);
  std::vector<SunHoursInstant> instants;
  for (int k = 0; k < 4; ++k)
    instants.push_back({directional_light("s" + std::to_string(k), sun_direction(20 + 12 * k, 100 + 45 * k)), 0.5});
  const ShadowEngine engine(scene, 1);
  std::vector<std::size_t> faces;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) faces.push_back(f);
  SunHoursOptions options;
  options.threads = 1;
  const SunHoursMap whole = compute_sun_hours_map(engine, faces, instants, options);
  ASSERT_GT(whole.regions, 0u);
  for (const SunHoursCell& c : whole.cells) EXPECT_LT(c.region_id, whole.regions);
  for (std::size_t cut : {std::size_t{1}, faces.size() / 3, faces.size() - 1}) {
    const std::vector<std::size_t> first(faces.begin(), faces.begin() + static_cast<std::ptrdiff_t>(cut));
    const std::vector<std::size_t> second(faces.begin() + static_cast<std::ptrdiff_t>(cut), faces.end());
    const SunHoursMap a = compute_sun_hours_map(engine, first, instants, options);
    const SunHoursMap b = compute_sun_hours_map(engine, second, instants, options);
    EXPECT_EQ(a.regions + b.regions, whole.regions) << "cut " << cut;
    ASSERT_EQ(a.cells.size() + b.cells.size(), whole.cells.size()) << "cut " << cut;
    ASSERT_EQ(a.faces.size() + b.faces.size(), whole.faces.size());
    for (std::size_t i = 0; i < whole.cells.size(); ++i) {
      const bool in_a = i < a.cells.size();
      const SunHoursCell& c = in_a ? a.cells[i] : b.cells[i - a.cells.size()];
      EXPECT_EQ(c.face_id, whole.cells[i].face_id);
      EXPECT_EQ(c.region_id + (in_a ? 0 : a.regions), whole.cells[i].region_id);
      EXPECT_EQ(c.sun_hours, whole.cells[i].sun_hours);
      EXPECT_EQ(c.area, whole.cells[i].area);
      EXPECT_EQ(c.polygon, whole.cells[i].polygon);
    }
    for (std::size_t i = 0; i < whole.faces.size(); ++i) {
      const SunHoursFace& f = i < a.faces.size() ? a.faces[i] : b.faces[i - a.faces.size()];
      EXPECT_EQ(f.face_id, whole.faces[i].face_id);
      EXPECT_EQ(f.hour_area, whole.faces[i].hour_area);
      EXPECT_EQ(f.instants_lit, whole.faces[i].instants_lit);
    }
  }
}

// SunHoursOptions::series_table: the map's pass gives its faces' series entries bit for bit as
// compute_series (exact) does, whatever route a pair takes there (the ground cut into tiles, a
// point light, faces turned away, a zero-area face), for the full map and the threshold map
// alone, over several batches of instants; a mapped face that is no receiver is no row and
// counts nothing; compute_series with those faces given leaves their rows 0 and every other
// row as it was. How `shadow series` computes the map's faces once (SeriesJob).
TEST(SunHoursMap, SeriesTableIsComputeSeriesBitForBit) {
  Scene scene = make_city(12, 60, 7);
  add_mesh(scene, "sliver", {{{5, 5, 0.5}, {6, 6, 0.5}, {7, 7, 0.5}}});  // collinear: zero area
  add_mesh(scene, "screen", {rectangle_z(10, 10, 14, 14, 3)});
  scene.meshes.back().receiver = false;  // casts, receives nothing
  validate_scene(scene);
  const std::size_t sliver = scene.faces.size() - 2;
  ASSERT_EQ(scene.meshes[scene.faces.back().mesh].name, "screen");
  ASSERT_TRUE(scene.faces[sliver].degenerate);
  std::vector<SunHoursInstant> instants;
  for (int k = 0; k < 5; ++k)
    instants.push_back({directional_light("s" + std::to_string(k), sun_direction(12 + 11 * k, 70 + 50 * k)), 0.5});
  instants.push_back({point_light("lamp", {30, 30, 40}), 1.0});
  std::vector<Light> lights;
  for (const SunHoursInstant& instant : instants) lights.push_back(instant.light);
  const ShadowEngine engine(scene, 2);
  std::vector<std::size_t> faces{sliver, 0, scene.faces.size() - 1};  // any order, a repeat
  for (std::size_t f = 1; f + 2 < scene.faces.size(); f += 3) faces.push_back(f);
  faces.push_back(0);
  std::vector<std::size_t> rows = faces;  // the receiving ones, sorted
  std::sort(rows.begin(), rows.end());
  rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  rows.pop_back();  // the screen's face

  SeriesOptions series_options;
  series_options.threads = 2;
  series_options.tile_casters = 6;  // the ground in tiles: the map's pass never cuts it
  const SeriesResult series = engine.compute_series(lights, series_options);
  ASSERT_GT(series.stats.tiled_receivers, 0u);
  std::vector<std::size_t> row_of(scene.faces.size(), SIZE_MAX);
  for (std::size_t r = 0; r < series.faces.size(); ++r) row_of[series.faces[r]] = r;

  for (const bool full : {true, false}) {
    SeriesResult table;
    SunHoursOptions options;
    options.threads = 2;
    options.full = full;
    options.levels = {1.0};
    options.instant_batch = 4;  // two batches
    options.series_table = &table;
    compute_sun_hours_map(engine, faces, instants, options);
    ASSERT_EQ(table.faces, rows);
    ASSERT_EQ(table.instants, instants.size());
    int partial = 0, turned_away = 0;
    for (std::size_t m = 0; m < rows.size(); ++m) {
      const std::size_t r = row_of[rows[m]];
      ASSERT_NE(r, SIZE_MAX);
      EXPECT_EQ(table.area[m], series.area[r]);
      for (std::size_t i = 0; i < instants.size(); ++i) {
        const std::size_t a = table.at(m, i), b = series.at(r, i);
        EXPECT_EQ(table.lit_area[a], series.lit_area[b]) << "face " << rows[m] << " instant " << i;
        EXPECT_EQ(table.lit_fraction[a], series.lit_fraction[b]) << "face " << rows[m] << " instant " << i;
        EXPECT_EQ(table.faces_light[a], series.faces_light[b]) << "face " << rows[m] << " instant " << i;
        EXPECT_EQ(table.lit_area_error_bound[a], 0.0);
        partial += table.lit_fraction[a] > 0 && table.lit_fraction[a] < 1;
        turned_away += table.faces_light[a] == 0;
      }
    }
    EXPECT_GT(partial, 10);
    EXPECT_GT(turned_away, 20);
    EXPECT_EQ(table.stats.receivers, rows.size() * instants.size());
  }

  series_options.given_faces = faces;
  const SeriesResult rest = engine.compute_series(lights, series_options);
  ASSERT_EQ(rest.faces, series.faces);
  EXPECT_EQ(rest.stats.receivers + rows.size() * instants.size(), series.stats.receivers);  // the rest's pairs only
  for (std::size_t r = 0; r < series.faces.size(); ++r) {
    const bool given = std::binary_search(rows.begin(), rows.end(), series.faces[r]);
    for (std::size_t i = 0; i < instants.size(); ++i) {
      const std::size_t at = series.at(r, i);
      EXPECT_EQ(rest.lit_area[at], given ? 0.0 : series.lit_area[at]);
      EXPECT_EQ(rest.lit_fraction[at], given ? 0.0 : series.lit_fraction[at]);
      EXPECT_EQ(rest.faces_light[at], given ? 0 : series.faces_light[at]);
    }
  }
  // Every row given: the table's shape, nothing computed.
  series_options.given_faces = series.faces;
  const SeriesResult none = engine.compute_series(lights, series_options);
  EXPECT_EQ(none.faces, series.faces);
  EXPECT_EQ(none.area, series.area);
  EXPECT_EQ(none.instants, instants.size());
  EXPECT_EQ(none.lit_area, std::vector<double>(series.lit_area.size(), 0.0));
  EXPECT_EQ(none.lit_fraction, std::vector<double>(series.lit_area.size(), 0.0));
  EXPECT_EQ(none.lit_area_error_bound, std::vector<double>(series.lit_area.size(), 0.0));
  EXPECT_EQ(none.faces_light, std::vector<unsigned char>(series.faces_light.size(), 0));
  EXPECT_EQ(none.stats.receivers, 0u);
}

TEST(SunHoursMap, PointLightsAndBackFacingFacesWork) {
  const Scene scene = pole_scene();
  const ShadowEngine engine(scene, 1);
  SunHoursOptions options;
  options.threads = 1;
  // The pole's faces: the top is lit by both, the bottom by neither; a point light above it.
  const std::vector<SunHoursInstant> instants{{point_light("lamp", {3, 1, 6}), 1.0},
                                              {directional_light("sun", {0, 0, 1}), 2.0}};
  std::vector<std::size_t> faces{0, 1, 2, 3, 4, 5, 6};
  const SunHoursMap map = compute_sun_hours_map(engine, faces, instants, options);
  expect_integral(engine, map, instants, faces);
  EXPECT_GT(expect_points(scene, map, instants, 20, 4), 50);
  const std::map<std::size_t, double> by_face = integral_by_face(map);
  EXPECT_DOUBLE_EQ(by_face.at(1), 3.0 * 0.0625);  // the top: lit by both
  EXPECT_EQ(by_face.at(2), 0.0);                    // the bottom: 0 hours everywhere
}

// Random scenes (boxes, floating and tilted polygons that are not exactly planar in doubles, a
// point or directional light) under that light and three random suns of random weights: on
// every face the cells cover the face once, their hours x area add up to the engine's exact lit
// areas, and sampled points agree with the ray caster.
RC_GTEST_PROP(SunHoursMapProperties, CellsMatchTheEngineAndRaysOnRandomScenes, ()) {
  const auto seed = *rc::gen::inRange<std::uint64_t>(0, 1u << 30);
  Scene scene = test::random_scene(seed);
  validate_scene(scene);
  std::vector<SunHoursInstant> instants{{scene.lights.at(0), 1.0}};
  for (int k = 0; k < 3; ++k) {
    const double elevation = *rc::gen::inRange(8, 85);
    const double azimuth = *rc::gen::inRange(0, 360);
    const double hours = 0.25 * *rc::gen::inRange(1, 12);
    instants.push_back({directional_light("s" + std::to_string(k), sun_direction(elevation, azimuth)), hours});
  }
  const ShadowEngine engine(scene, 1);
  std::vector<std::size_t> faces;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) faces.push_back(f);
  SunHoursOptions options;
  options.threads = 1;
  const SunHoursMap map = compute_sun_hours_map(engine, faces, instants, options);
  std::map<std::size_t, double> want, got, covered;
  ShadowOptions areas;
  areas.polygons = false;
  for (std::size_t i = 0; i < instants.size(); ++i) {
    const ShadowResult r = engine.compute(instants[i].light, i, areas);
    for (const FaceLighting& l : r.lighting) want[l.face_id] += instants[i].hours * l.lit_area;
  }
  double total = 0;
  for (const SunHoursInstant& instant : instants) total += instant.hours;
  for (const SunHoursCell& c : map.cells) {
    got[c.face_id] += c.sun_hours * c.area;
    covered[c.face_id] += c.area;
    RC_ASSERT(c.sun_hours >= 0.0);
    RC_ASSERT(c.sun_hours <= total * (1 + 1e-15));
  }
  for (const SunHoursFace& f : map.faces) {
    const double scale = 1.0 + total * f.area;
    RC_ASSERT(std::abs(f.hour_area - want[f.face_id]) <= 1e-12 * scale);
    RC_ASSERT(std::abs(got[f.face_id] - want[f.face_id]) <= 1e-10 * scale + total * f.dropped_area);
    RC_ASSERT(std::abs(covered[f.face_id] + f.dropped_area - f.area) <= 1e-10 * (1.0 + f.area));
  }
  std::mt19937_64 rng(seed);
  for (const SunHoursCell& cell : map.cells) {
    for (const glm::dvec3& p : test::sample_interior(cell.polygon, 2, 1e-6, rng)) {
      double hours = 0.0;
      bool sure = true;
      for (const SunHoursInstant& instant : instants) {
        const test::RayVerdict v = test::cast_shadow_ray(scene, cell.face_id, p, instant.light, 1e-7);
        if (v == test::RayVerdict::Unsure) sure = false;
        if (v == test::RayVerdict::Lit) hours += instant.hours;
      }
      if (sure) RC_ASSERT(std::abs(hours - cell.sun_hours) <= 1e-9);
    }
  }
}

TEST(SunHoursMap, BadInputIsAnInputError) {
  const Scene scene = pole_scene();
  const ShadowEngine engine(scene, 1);
  EXPECT_THROW((void)compute_sun_hours_map(engine, {99}, {}), InputError);
  EXPECT_THROW((void)compute_sun_hours_map(engine, {0}, {{directional_light("z", {0, 0, 0}), 1.0}}), InputError);
  EXPECT_THROW((void)compute_sun_hours_map(engine, {0}, {{directional_light("s", {0, 0, 1}), -1.0}}), InputError);
  EXPECT_THROW((void)compute_sun_hours_map(engine, {0}, {{directional_light("s", {0, 0, 1}), NAN}}), InputError);
  try {
    (void)compute_sun_hours_map(engine, {0}, {{directional_light("s", {0, 0, 1}), 1.0}, {directional_light("s", {0, 0, 1}), -2.0}});
    FAIL() << "negative hours accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().place, "instants[1].hours");
  }
  // No instants: every cell has 0 hours and the faces are covered.
  const SunHoursMap empty = compute_sun_hours_map(engine, {0}, {});
  ASSERT_EQ(empty.cells.size(), 1u);
  EXPECT_EQ(empty.cells[0].sun_hours, 0.0);
  EXPECT_DOUBLE_EQ(empty.cells[0].area, 400.0);
}

TEST(SunHoursMap, SceneKeyAndMeshNamesChooseFaces) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "libshadow_sun_hours_scene";
  std::filesystem::create_directories(dir);
  const std::string meshes = R"("meshes": [
      {"name": "ground", "polygons": [[[0,0,0],[4,0,0],[4,4,0],[0,4,0]]]},
      {"name": "roof", "polygons": [[[1,1,2],[2,1,2],[2,2,2],[1,2,2]], [[1,1,3],[2,1,3],[2,2,3],[1,2,3]]]}],
    "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}])";
  const Scene scene = parse_scene("{" + meshes + R"(, "sun_hours_map": ["roof", "ground", "roof"]})", dir / "s.json");
  EXPECT_EQ(scene.sun_hours_map, (std::vector<std::size_t>{1, 0}));
  EXPECT_EQ(sun_hours_map_faces(scene), (std::vector<std::size_t>{0, 1, 2}));
  EXPECT_EQ(sun_hours_map_faces(scene, {"roof"}), (std::vector<std::size_t>{1, 2}));
  try {
    (void)sun_hours_map_faces(scene, {"roof", "gorund"});
    FAIL() << "unknown mesh accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().place, "--sun-hours-map");
    EXPECT_NE(std::string(e.what()).find("gorund"), std::string::npos);
  }
  try {
    (void)parse_scene("{" + meshes + R"(, "sun_hours_map": ["ground", "gorund"]})", dir / "s.json");
    FAIL() << "unknown mesh accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().place, "sun_hours_map[1]");
    EXPECT_NE(std::string(e.what()).find("ground"), std::string::npos) << "suggests the near name";
  }
  EXPECT_THROW((void)parse_scene("{" + meshes + R"(, "sun_hours_map": "ground"})", dir / "s.json"), InputError);
  EXPECT_THROW((void)parse_scene("{" + meshes + R"(, "sun_hours_map": [3]})", dir / "s.json"), InputError);
  Scene bad = scene;
  bad.sun_hours_map = {0, 7};
  EXPECT_THROW((void)sun_hours_map_faces(bad), InputError);
  // Without a sun block there are no instants.
  EXPECT_TRUE(sun_hours_instants(scene).empty());
  std::filesystem::remove_all(dir);
}

TEST(SunHoursMap, InstantsOfTheSceneAndOfItsSeriesAreTheSame) {
  // A day at 90-minute steps (the night's instants have no light) and a lamp before the suns.
  const Scene scene = parse_scene(R"({
    "meshes": [{"name": "m", "polygons": [[[0, 0, 0], [1, 0, 0], [1, 1, 0]]]}],
    "lights": [{"name": "lamp", "type": "point", "position": [0, 0, 5]}],
    "sun": {"latitude": 52.5, "longitude": 13.4, "start": "2026-03-21", "end": "2026-03-21", "step_minutes": 90}
  })", "scene.json");
  const std::vector<SunHoursInstant> of_scene = sun_hours_instants(scene);
  const std::vector<SunHoursInstant> of_series = sun_hours_instants(sun_series(scene));
  ASSERT_GT(of_scene.size(), 4u);
  ASSERT_LT(of_scene.size(), scene.sun_instants.size());
  ASSERT_EQ(of_series.size(), of_scene.size());
  for (std::size_t i = 0; i < of_scene.size(); ++i) {
    EXPECT_EQ(of_series[i].light.name, of_scene[i].light.name);
    EXPECT_EQ(of_series[i].light.to_light, of_scene[i].light.to_light);
    EXPECT_EQ(of_series[i].hours, 1.5);
    EXPECT_EQ(of_scene[i].hours, 1.5);
  }
}

TEST(SunHoursMap, WritesSunHoursVtp) {
  const Scene scene = pole_scene();
  const ShadowEngine engine(scene, 1);
  const std::vector<SunHoursInstant> instants{{directional_light("a", {1, 0, 1}), 1.0},
                                              {directional_light("b", {1, 0, 2}), 1.0},
                                              {directional_light("c", {0, 1, 1}), 1.0}};
  const SunHoursMap map = compute_sun_hours_map(engine, {0, 1}, instants);
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "libshadow_sun_hours_vtp";
  std::filesystem::remove_all(dir);
  write_sun_hours_vtp(dir / "sun_hours.vtp", map);
  // Nothing but the file (the temporary was renamed).
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 1u);
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName((dir / "sun_hours.vtp").string().c_str());
  reader->Update();
  vtkPolyData* poly = reader->GetOutput();
  ASSERT_EQ(static_cast<std::size_t>(poly->GetNumberOfCells()), map.cells.size());
  EXPECT_EQ(poly->GetPoints()->GetDataType(), VTK_DOUBLE);
  vtkDataArray* hours = poly->GetCellData()->GetArray("sun_hours");
  vtkDataArray* face_id = poly->GetCellData()->GetArray("face_id");
  vtkDataArray* area = poly->GetCellData()->GetArray("area");
  ASSERT_NE(hours, nullptr);
  ASSERT_NE(face_id, nullptr);
  ASSERT_NE(area, nullptr);
  ASSERT_NE(poly->GetCellData()->GetArray("region_id"), nullptr);
  for (vtkIdType c = 0; c < poly->GetNumberOfCells(); ++c) {
    EXPECT_EQ(hours->GetTuple1(c), map.cells[static_cast<std::size_t>(c)].sun_hours);
    EXPECT_EQ(area->GetTuple1(c), map.cells[static_cast<std::size_t>(c)].area);
    EXPECT_EQ(face_id->GetTuple1(c), static_cast<double>(map.cells[static_cast<std::size_t>(c)].face_id));
  }
  vtkDataArray* total = poly->GetFieldData()->GetArray("total_hours");
  ASSERT_NE(total, nullptr);
  EXPECT_EQ(total->GetTuple1(0), 3.0);
  // An unwritable place is an OutputError, and leaves no temporary behind.
  EXPECT_THROW(write_sun_hours_vtp(dir / "sun_hours.vtp" / "x.vtp", map), std::exception);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace shadow
