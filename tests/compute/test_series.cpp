// SPDX-License-Identifier: GPL-3.0-or-later
// The sun series: ShadowEngine::compute_series against one-light compute (bit for bit, exact and
// fast), sun hours on analytic scenes, named-surface aggregation, and the series files.
//
// The suns are made here by hand (the `sun` block's solar position is another branch's work):
// at an equinox (declination 0) the sun's direction at latitude phi and hour angle H is, in
// east/north/up, (-sin H, -cos H sin phi, cos H cos phi); H = 15 deg per hour from solar noon.
#include <shadow/shadow.hpp>
#include <shadow/series_files.hpp>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace {

namespace fs = std::filesystem;
constexpr double kPi = 3.14159265358979323846;

/// The equinox sun at latitude `lat` (degrees), `hour` hours of solar time.
glm::dvec3 equinox_sun(double lat, double hour) {
  const double h = (hour - 12.0) * 15.0 * kPi / 180.0;
  const double phi = lat * kPi / 180.0;
  return {-std::sin(h), -std::cos(h) * std::sin(phi), std::cos(h) * std::cos(phi)};
}

/// UTC seconds of a UTC calendar time (POSIX timegm).
shadow::UtcSeconds utc(int year, int month, int day, int hour = 0, int minute = 0) {
  std::tm t{};
  t.tm_year = year - 1900;
  t.tm_mon = month - 1;
  t.tm_mday = day;
  t.tm_hour = hour;
  t.tm_min = minute;
  return static_cast<shadow::UtcSeconds>(timegm(&t));
}

/// Adds a sun period to `scene`: one instant every `step` minutes from `first` (UTC, at solar
/// longitude 0 so that UTC is solar time) for `count` instants, the equinox sun at `lat` (so a
/// day repeats: enough for the file structure tests). Instants below the horizon get no light.
/// With `energyplus`, the instants are where EnergyPlus takes each step's sun
/// (SunPeriod::energyplus_times): at the step's end, or mid-step for a step of an hour.
void add_equinox_period(shadow::Scene& scene, double lat, shadow::UtcSeconds first, std::size_t count, int step,
                        const std::string& start, const std::string& end, bool energyplus = false) {
  shadow::SunPeriod period;
  period.site.latitude = lat;
  period.start = start;
  period.end = end;
  period.step_minutes = step;
  period.energyplus_times = energyplus;
  scene.sun = period;
  const shadow::UtcSeconds at = !energyplus ? 0 : step < 60 ? step * 60 : step * 30;
  for (std::size_t i = 0; i < count; ++i) {
    shadow::SunInstant instant;
    instant.time = first + at + static_cast<shadow::UtcSeconds>(i) * step * 60;
    const double hour = static_cast<double>((instant.time % 86400 + 86400) % 86400) / 3600.0;
    const glm::dvec3 d = equinox_sun(lat, hour);
    instant.position.to_light = d;
    instant.position.elevation = std::asin(std::clamp(d.z, -1.0, 1.0)) * 180.0 / kPi;
    if (d.z > 1e-9) {
      instant.light_id = scene.lights.size();
      scene.lights.push_back(shadow::directional_light("sun_" + std::to_string(i), d));
    }
    scene.sun_instants.push_back(instant);
  }
}

std::vector<shadow::Light> city_suns() {
  std::vector<shadow::Light> lights;
  for (double hour = 7; hour <= 17; hour += 1.25) lights.push_back(shadow::directional_light("s", equinox_sun(48.0, hour)));
  lights.push_back(shadow::directional_light("low", shadow::sun_direction(2.0, 250.0)));
  return lights;
}

/// The faces whose values at instant i differ in any bit (lit area, fraction and bound compared
/// with memcmp, so that even the sign of a zero must agree; facing) between a series and
/// compute(light i); `first` gets the first such face's id (for the message).
std::size_t differing_cells(const shadow::SeriesResult& series, std::size_t i, const shadow::ShadowResult& one,
                            std::size_t& first) {
  std::size_t differing = 0;
  for (std::size_t r = 0; r < series.faces.size(); ++r) {
    const shadow::FaceLighting& fl = one.lighting[r];
    const std::size_t at = series.at(r, i);
    const bool same = std::memcmp(&fl.lit_area, &series.lit_area[at], sizeof(double)) == 0 &&
                      std::memcmp(&fl.lit_fraction, &series.lit_fraction[at], sizeof(double)) == 0 &&
                      std::memcmp(&fl.lit_area_error_bound, &series.lit_area_error_bound[at], sizeof(double)) == 0 &&
                      fl.faces_light == (series.faces_light[at] != 0);
    if (!same && differing++ == 0) first = fl.face_id;
  }
  return differing;
}

/// With `tile_casters` > 0 both thresholds are set to it (small enough to split the city's
/// ground and some walls), in the series and in compute() alike.
void expect_series_equals_compute(shadow::Arithmetic arithmetic, std::size_t tile_casters = 0,
                                  const std::vector<shadow::Light>& lights = city_suns()) {
  shadow::Scene scene = shadow::make_city(25, 60.0, 7);
  shadow::validate_scene(scene);
  const shadow::ShadowEngine engine(scene, 2);
  shadow::SeriesOptions options;
  options.threads = 2;
  options.arithmetic = arithmetic;
  if (tile_casters > 0) options.tile_casters = options.fast_tile_casters = tile_casters;
  std::size_t last_done = 0;
  bool monotone = true;
  options.progress = [&](const shadow::Progress& p) {
    monotone = monotone && p.done >= last_done && p.total == lights.size();
    last_done = p.done;
  };
  const shadow::SeriesResult series = engine.compute_series(lights, options);
  EXPECT_TRUE(monotone);
  EXPECT_EQ(last_done, lights.size());
  ASSERT_EQ(series.instants, lights.size());
  ASSERT_EQ(series.faces.size(), scene.faces.size());
  std::size_t shadowed = 0;
  shadow::ShadowStats summed;  // the one-light computes' counts, added up
  for (std::size_t i = 0; i < lights.size(); ++i) {
    shadow::ShadowOptions one;
    one.threads = 1;
    one.polygons = false;
    one.arithmetic = arithmetic;
    one.tile_casters = options.tile_casters;
    one.fast_tile_casters = options.fast_tile_casters;
    const shadow::ShadowResult result = engine.compute(lights[i], i, one);
    summed += result.stats;
    ASSERT_EQ(result.lighting.size(), series.faces.size());
    for (std::size_t r = 0; r < series.faces.size(); ++r) {
      const shadow::FaceLighting& fl = result.lighting[r];
      ASSERT_EQ(fl.face_id, series.faces[r]);
      EXPECT_EQ(std::memcmp(&fl.area, &series.area[r], sizeof(double)), 0);
      if (fl.faces_light && fl.lit_fraction < 1.0) ++shadowed;
    }
    std::size_t first = 0;
    EXPECT_EQ(differing_cells(series, i, result, first), 0u) << "first face " << first << ", sun " << i;
  }
  EXPECT_GT(shadowed, 20u) << "the city should shade something";
  // The same work, counted the same way (tiles included).
  EXPECT_EQ(series.stats.receivers, summed.receivers);
  // Receivers turned away from a sun are written without a work item, and still counted.
  EXPECT_EQ(series.stats.back_facing, summed.back_facing);
  EXPECT_GT(summed.back_facing, lights.size()) << "a city's walls should look away from every sun";
  EXPECT_EQ(series.stats.unshadowed, summed.unshadowed);
  EXPECT_EQ(series.stats.tiled_receivers, summed.tiled_receivers);
  EXPECT_EQ(series.stats.tiles, summed.tiles);
  EXPECT_EQ(series.stats.candidate_pairs, summed.candidate_pairs);
  EXPECT_EQ(series.stats.casting_pairs, summed.casting_pairs);
  EXPECT_EQ(series.stats.fast_exact_fallbacks, summed.fast_exact_fallbacks);
  // The thread count changes nothing.
  options.threads = 1;
  options.progress = nullptr;
  const shadow::SeriesResult single = engine.compute_series(lights, options);
  EXPECT_EQ(single.lit_area, series.lit_area);
  EXPECT_EQ(single.lit_area_error_bound, series.lit_area_error_bound);
  if (tile_casters > 0) {
    EXPECT_GT(series.stats.tiled_receivers, lights.size()) << "the ground should be split at every instant";
    if (arithmetic == shadow::Arithmetic::Exact) {  // exact tiles change no bit
      options.tile_casters = 0;
      const shadow::SeriesResult untiled = engine.compute_series(lights, options);
      EXPECT_EQ(untiled.stats.tiled_receivers, 0u);
      EXPECT_EQ(untiled.lit_area, series.lit_area);
      EXPECT_EQ(untiled.lit_fraction, series.lit_fraction);
    }
  }
}

TEST(Series, TileDefaultsAreComputes) {
  // A series splits receivers as compute() does (docs/tiles.md), and its report writes the
  // thresholds only when they differ from SeriesOptions' defaults: the two sets of defaults are
  // one rule and must not drift apart.
  EXPECT_EQ(shadow::SeriesOptions{}.tile_casters, shadow::ShadowOptions{}.tile_casters);
  EXPECT_EQ(shadow::SeriesOptions{}.fast_tile_casters, shadow::ShadowOptions{}.fast_tile_casters);
}

TEST(Series, EqualsOneLightComputeBitForBitExact) { expect_series_equals_compute(shadow::Arithmetic::Exact); }

TEST(Series, EqualsOneLightComputeBitForBitFast) {
  expect_series_equals_compute(shadow::Arithmetic::Fast);
}

// compute_series takes the instants in the order of their suns' directions (neighbouring suns in
// one batch, each receiver under them one after another): suns of five days, hour by hour, and a
// lamp among them, whose batches are not the input's; every value lands in its own instant's
// column, bit for bit as compute(light) gives it.
std::vector<shadow::Light> days_of_suns() {
  std::vector<shadow::Light> lights;
  for (int day = 0; day < 5; ++day)
    for (double hour = 8; hour <= 16; hour += 2) {
      // The equinox path tilted a little more each day: neighbours are the same hour a day apart.
      const glm::dvec3 d = equinox_sun(48.0 - 3.0 * day, hour);
      lights.push_back(shadow::directional_light("s", d));
      if (day == 2 && hour == 12) lights.push_back(shadow::point_light("lamp", {30.0, 30.0, 80.0}));
    }
  return lights;
}
TEST(Series, InstantsInSunOrderLandInTheirColumnsExact) {
  expect_series_equals_compute(shadow::Arithmetic::Exact, 0, days_of_suns());
}
TEST(Series, InstantsInSunOrderLandInTheirColumnsFast) {
  expect_series_equals_compute(shadow::Arithmetic::Fast, 0, days_of_suns());
}

// Many instants: compute_series stages the batches' values (engine/series.cpp, StagedTable: at
// most 64 instants a stage, or one batch when a batch is larger) and puts each row in the
// lights' order at the end. 150 suns against one-light compute, bit for bit, at 1 thread (batches
// of 8: two full stages, a partial one, a partial last batch), 3 (batches of 12, stages of 60)
// and 20 (batches of 80, larger than a stage: one batch a stage, a partial last batch).
TEST(Series, ManyInstantsThroughTheStagesLandInTheirColumns) {
  shadow::Scene scene = shadow::make_city(25, 60.0, 7);
  shadow::validate_scene(scene);
  const shadow::ShadowEngine engine(scene, 2);
  std::vector<shadow::Light> lights;
  for (int day = 0; day < 30; ++day)
    for (double hour = 8; hour <= 16; hour += 2)
      lights.push_back(shadow::directional_light("s", equinox_sun(48.0 - 0.2 * day, hour)));
  ASSERT_EQ(lights.size(), 150u);
  shadow::ShadowOptions one;
  one.threads = 2;
  one.polygons = false;
  one.arithmetic = shadow::Arithmetic::Fast;
  std::vector<shadow::ShadowResult> expected;
  for (std::size_t i = 0; i < lights.size(); ++i) expected.push_back(engine.compute(lights[i], i, one));
  for (unsigned threads : {1u, 3u, 20u}) {
    shadow::SeriesOptions options;
    options.threads = threads;
    options.arithmetic = shadow::Arithmetic::Fast;
    const shadow::SeriesResult series = engine.compute_series(lights, options);
    ASSERT_EQ(series.instants, lights.size());
    ASSERT_EQ(series.lit_area.size(), series.faces.size() * lights.size());
    std::size_t differing = 0, first = 0;
    for (std::size_t i = 0; i < lights.size(); ++i) differing += differing_cells(series, i, expected[i], first);
    EXPECT_EQ(differing, 0u) << threads << " threads, face " << first;
  }
}

// Receivers above the tile threshold are split in the series as in compute(): the same bits
// (exact: also the same as untiled).
TEST(Series, TiledReceiversEqualOneLightComputeExact) { expect_series_equals_compute(shadow::Arithmetic::Exact, 6); }
TEST(Series, TiledReceiversEqualOneLightComputeFast) { expect_series_equals_compute(shadow::Arithmetic::Fast, 6); }

// Progress when receivers are split: it moves through the tile round too (each batch's end is
// reported when its tiles are done), never backwards, ending at every instant; two batches of 8
// instants, the ground split at each, on one and two threads.
TEST(Series, ProgressCountsInstantsWhenTheirTilesAreDone) {
  shadow::Scene scene = shadow::make_city(25, 60.0, 7);
  shadow::validate_scene(scene);
  const shadow::ShadowEngine engine(scene, 2);
  std::vector<shadow::Light> lights;
  for (double hour = 7; hour < 17; hour += 10.0 / 16) lights.push_back(shadow::directional_light("s", equinox_sun(48.0, hour)));
  ASSERT_EQ(lights.size(), 16u);
  for (shadow::Arithmetic arithmetic : {shadow::Arithmetic::Exact, shadow::Arithmetic::Fast})
    for (unsigned threads : {1u, 2u}) {
      shadow::SeriesOptions options;
      options.threads = threads;
      options.arithmetic = arithmetic;
      options.tile_casters = options.fast_tile_casters = 6;
      std::vector<shadow::Progress> calls;
      options.progress = [&](const shadow::Progress& p) { calls.push_back(p); };
      const shadow::SeriesResult series = engine.compute_series(lights, options);
      ASSERT_GE(series.stats.tiled_receivers, lights.size()) << "the ground should be split at every instant";
      ASSERT_FALSE(calls.empty());
      for (std::size_t n = 0; n < calls.size(); ++n) {
        EXPECT_EQ(calls[n].total, lights.size());
        EXPECT_LE(calls[n].done, lights.size());
        if (n > 0) EXPECT_GE(calls[n].done, calls[n - 1].done) << "call " << n;
      }
      EXPECT_EQ(calls.back().done, lights.size());
      // The first batch's end is reported before the second batch ends.
      bool batch_end = false;
      for (const shadow::Progress& p : calls) batch_end = batch_end || p.done == 8;
      EXPECT_TRUE(batch_end);
    }
}

TEST(Series, RejectsUnusableLightsAndThreads) {
  shadow::Scene scene = shadow::make_city(3, 20.0, 1);
  const shadow::ShadowEngine engine(scene, 1);
  std::vector<shadow::Light> lights{shadow::directional_light("ok", {0, 0, 1}),
                                    shadow::directional_light("zero", {0, 0, 0})};
  try {
    (void)engine.compute_series(lights);
    FAIL() << "a zero direction must be an InputError";
  } catch (const shadow::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("lights[1]"), std::string::npos) << e.what();
  }
  shadow::SeriesOptions options;
  options.threads = 5000;
  EXPECT_THROW((void)engine.compute_series({lights[0]}, options), shadow::InputError);
  const shadow::SeriesResult empty = engine.compute_series({});
  EXPECT_EQ(empty.instants, 0u);
  EXPECT_TRUE(empty.lit_area.empty());
}

/// An open square and four walls standing apart (none shades another at any equinox sun), at
/// 45 deg north, one instant an hour through a whole equinox day.
shadow::Scene equinox_day_scene() {
  shadow::Scene scene;
  shadow::add_mesh(scene, "square", {shadow::rectangle_z(0, 0, 10, 10, 0)});
  // Walls far from the square and each other, 3 m tall, fronts facing outward.
  shadow::add_mesh(scene, "north_wall", {{{104, 100, 0}, {100, 100, 0}, {100, 100, 3}, {104, 100, 3}}});   // normal +y
  shadow::add_mesh(scene, "south_wall", {{{200, 100, 0}, {204, 100, 0}, {204, 100, 3}, {200, 100, 3}}});   // normal -y
  shadow::add_mesh(scene, "east_wall", {{{300, 100, 0}, {300, 104, 0}, {300, 104, 3}, {300, 100, 3}}});    // normal +x
  scene.faces[1].name = "north facade";
  scene.faces[2].name = "south facade";
  scene.faces[3].name = "east facade";
  add_equinox_period(scene, 45.0, utc(2026, 3, 20), 24, 60, "2026-03-20", "2026-03-20");
  return scene;
}

TEST(Series, SunHoursOnAnEquinoxDay) {
  shadow::Scene scene = equinox_day_scene();
  shadow::validate_scene(scene);
  const shadow::SunSeries suns = shadow::sun_series(scene);
  // Above the horizon from 07:00 to 17:00 (06:00 and 18:00 are on it): 11 instants.
  ASSERT_EQ(suns.lights.size(), 11u);
  EXPECT_EQ(suns.all_instants, 24u);
  EXPECT_EQ(suns.hours_per_instant, 1.0);
  const shadow::ShadowEngine engine(scene, 2);
  const shadow::SeriesResult series = engine.compute_series(suns.lights);
  const std::vector<double> hours = shadow::sun_hours(series, suns.hours_per_instant);
  ASSERT_EQ(hours.size(), 4u);
  EXPECT_EQ(hours[0], 11.0);  // the open square: every hour the sun is up
  EXPECT_EQ(hours[1], 0.0);   // facing north: the sun is south of east-west all day
  EXPECT_EQ(hours[2], 11.0);  // facing south: all day
  EXPECT_EQ(hours[3], 5.0);   // facing east: 07:00 to 11:00 (at noon the sun is in its plane)
  const shadow::SurfaceSeries surfaces = shadow::surface_series(scene, series, suns.hours_per_instant);
  ASSERT_EQ(surfaces.surfaces.size(), 4u);
  EXPECT_EQ(surfaces.surfaces[0].label, "face_0");
  EXPECT_EQ(surfaces.surfaces[1].label, "north facade");
  EXPECT_EQ(surfaces.sun_hours, hours);
  EXPECT_EQ(shadow::sun_hours_error_bound(series, 1.0), std::vector<double>(4, 0.0));
}

TEST(Series, SunHoursUnderAnOverhang) {
  // A 10 x 10 square under a 10 x 5 roof 1 m up over its southern half (y in [0, 5]). The noon
  // equinox sun at 45 N is due south at 45 deg: the roof's shadow is the roof moved 1 m north,
  // y in [1, 6], so the lit part is y in [0, 1) and (6, 10]: half the square.
  shadow::Scene scene;
  shadow::add_mesh(scene, "square", {shadow::rectangle_z(0, 0, 10, 10, 0)});
  shadow::add_mesh(scene, "roof", {shadow::rectangle_z(0, 0, 10, 5, 1)}, false);
  shadow::SunPeriod period;
  period.times = {utc(2026, 3, 20, 12)};
  scene.sun = period;
  shadow::SunInstant noon;
  noon.time = period.times[0];
  noon.light_id = 0;
  scene.lights.push_back(shadow::directional_light("noon", equinox_sun(45.0, 12.0)));
  scene.sun_instants.push_back(noon);
  const shadow::SunSeries suns = shadow::sun_series(scene);
  EXPECT_TRUE(suns.explicit_times);
  EXPECT_EQ(suns.hours_per_instant, 1.0);  // a single time counts for an hour (docs/series.md)
  const shadow::ShadowEngine engine(scene, 1);
  const shadow::SeriesResult series = engine.compute_series(suns.lights);
  ASSERT_EQ(series.faces.size(), 1u);  // the roof receives nothing
  EXPECT_NEAR(series.lit_fraction[0], 0.5, 1e-12);
}

TEST(Series, NamedSurfacesAddTheirFacesUp) {
  shadow::Scene scene;
  // Two pieces of one facade (6 m^2 and 2 m^2) facing south under a fin 1 m deep along its top,
  // and an unnamed ground. At the three suns below the ratio of the sun's height to its
  // southward run is 1 (noon: elevation 45 deg), so the fin shades the facade's upper half.
  shadow::add_mesh(scene, "facade",
                   {{{0, 0, 0}, {3, 0, 0}, {3, 0, 2}, {0, 0, 2}}, {{5, 0, 0}, {6, 0, 0}, {6, 0, 2}, {5, 0, 2}}});
  shadow::add_mesh(scene, "fin", {shadow::rectangle_z(-3, -1, 9, 0, 2.0, false)}, false);
  shadow::add_mesh(scene, "ground", {shadow::rectangle_z(-20, -20, 20, 20, -0.5)});
  scene.faces[0].name = "facade, south";
  scene.faces[1].name = "facade, south";
  shadow::SunPeriod period;
  period.times = {utc(2026, 3, 20, 10), utc(2026, 3, 20, 12), utc(2026, 3, 20, 13)};
  scene.sun = period;
  for (std::size_t i = 0; i < period.times.size(); ++i) {
    shadow::SunInstant s;
    s.time = period.times[i];
    s.light_id = i;
    scene.lights.push_back(shadow::directional_light("s", equinox_sun(45.0, 10.0 + (i == 0 ? 0.0 : i + 1.0))));
    scene.sun_instants.push_back(s);
  }
  const shadow::SunSeries suns = shadow::sun_series(scene);
  EXPECT_EQ(suns.hours_per_instant, 1.5);  // gaps 2 h and 1 h: median 1.5 h
  const shadow::ShadowEngine engine(scene, 2);
  const shadow::SeriesResult series = engine.compute_series(suns.lights);
  const shadow::SurfaceSeries surfaces = shadow::surface_series(scene, series, suns.hours_per_instant);
  ASSERT_EQ(surfaces.surfaces.size(), 2u);
  EXPECT_EQ(surfaces.surfaces[0].label, "facade, south");
  EXPECT_EQ(surfaces.surfaces[0].faces, (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(surfaces.surfaces[1].label, "face_3");
  EXPECT_DOUBLE_EQ(surfaces.area[0], 8.0);
  double hours = 0;
  for (std::size_t i = 0; i < 3; ++i) {
    const double expected = (series.lit_area[series.at(0, i)] + series.lit_area[series.at(1, i)]) / 8.0;
    EXPECT_DOUBLE_EQ(surfaces.lit_fraction[i], expected);
    hours += surfaces.lit_fraction[i];
    EXPECT_LT(surfaces.lit_fraction[i], 1.0);  // the fin shades the facade at each of these suns
    EXPECT_GT(surfaces.lit_fraction[i], 0.0);
  }
  EXPECT_DOUBLE_EQ(surfaces.sun_hours[0], hours * 1.5);
  // Noon (instant 1): shaded from z = 2 down to z = 1 on both pieces.
  EXPECT_NEAR(series.lit_fraction[series.at(0, 1)], 0.5, 1e-12);
  EXPECT_NEAR(surfaces.lit_fraction[1], 0.5, 1e-12);

  std::ostringstream csv;
  shadow::write_sunlit_csv(csv, suns, surfaces);
  const std::string text = csv.str();
  EXPECT_EQ(text.substr(0, text.find("\r\n")), "time,\"facade, south\",face_3");
  EXPECT_NE(text.find("\r\n2026-03-20T12:00:00Z,"), std::string::npos) << text;
  std::ostringstream ep;
  EXPECT_FALSE(shadow::write_energyplus_shading_csv(ep, scene, suns, surfaces).written);  // explicit times
  EXPECT_TRUE(ep.str().empty());
}

TEST(Series, SunlitCsvValuesReadBackAsTheSameDoubles) {
  // sunlit.csv's numbers: to_chars's shortest form of each value, so that it reads back as the
  // same double; 0 and 1 (faces turned away, unshadowed) as "0" and "1", -0 keeping its sign.
  // Two rows, so that the second is written after the first in the same buffer.
  const std::vector<double> values = {0.0,
                                      -0.0,
                                      1.0,
                                      0.5,
                                      1.0 - std::numeric_limits<double>::epsilon() / 2,
                                      1.0 + std::numeric_limits<double>::epsilon(),
                                      1.778735898664716e-16,
                                      std::numeric_limits<double>::denorm_min(),
                                      -3 * std::numeric_limits<double>::denorm_min(),
                                      2.2250738585072009e-308,  // the largest subnormal
                                      -std::numeric_limits<double>::min(),  // the longest text: 24 characters
                                      std::numeric_limits<double>::max(),
                                      std::numeric_limits<double>::infinity(),
                                      0.1 + 0.2};
  shadow::SunSeries suns;
  suns.times = {utc(2026, 6, 21, 12), utc(2026, 6, 21, 13)};
  shadow::SurfaceSeries surfaces;
  surfaces.instants = 2;
  for (std::size_t s = 0; s < values.size(); ++s) {
    shadow::NamedSurface named;
    named.label = "s" + std::to_string(s);
    surfaces.surfaces.push_back(named);
    surfaces.lit_fraction.push_back(values[s]);  // instant 0
    surfaces.lit_fraction.push_back(0.25);       // instant 1 (surface-major: s * instants + i)
  }
  std::ostringstream csv;
  shadow::write_sunlit_csv(csv, suns, surfaces);
  const std::string text = csv.str();
  const std::size_t row = text.find("\r\n") + 2;
  const std::size_t second = text.find("\r\n", row) + 2;
  ASSERT_EQ(text.substr(text.size() - 2), "\r\n");
  std::string expected_second = "2026-06-21T13:00:00Z";
  for (std::size_t s = 0; s < values.size(); ++s) expected_second += ",0.25";
  EXPECT_EQ(text.substr(second), expected_second + "\r\n");
  const std::string first_row = text.substr(row, second - 2 - row);
  ASSERT_NE(first_row.back(), ',');
  std::vector<std::string> fields;
  std::stringstream line(first_row);
  for (std::string field; std::getline(line, field, ',');) fields.push_back(field);
  ASSERT_EQ(fields.size(), values.size() + 1);
  EXPECT_EQ(fields[0], "2026-06-21T12:00:00Z");
  EXPECT_EQ(fields[1], "0");
  EXPECT_EQ(fields[2], "-0");
  EXPECT_EQ(fields[3], "1");
  EXPECT_EQ(fields[4], "0.5");
  for (std::size_t s = 0; s < values.size(); ++s) {
    char shortest[64];
    const auto written = std::to_chars(shortest, shortest + sizeof shortest, values[s]);
    EXPECT_EQ(fields[s + 1], std::string(shortest, written.ptr)) << s;
    double back = 0;
    ASSERT_EQ(std::from_chars(fields[s + 1].data(), fields[s + 1].data() + fields[s + 1].size(), back).ec, std::errc()) << s;
    EXPECT_EQ(std::memcmp(&back, &values[s], sizeof back), 0) << s << ": " << fields[s + 1];
  }
}

TEST(Series, SunHoursPerObjectRollPartsUpAreaWeighted) {
  // Objects as a city model brings them: two parts of building "city/B" (which has no mesh of its
  // own), a building "city/C" with its own mesh, a zone, a plain mesh, and a shading mesh that
  // does not receive (and so is no object).
  shadow::Scene scene;
  shadow::add_mesh(scene, "city/B-1", {shadow::rectangle_z(0, 0, 2, 1, 3.0)});                                // 2 m2
  shadow::add_mesh(scene, "city/B-2", {shadow::rectangle_z(5, 0, 6, 1, 6.0), shadow::rectangle_z(7, 0, 8, 1, 6.0)});  // 2 x 1 m2
  shadow::add_mesh(scene, "city/C", {shadow::rectangle_z(10, 0, 13, 1, 1.0)});                                 // 3 m2
  shadow::add_mesh(scene, "Room", {shadow::rectangle_z(20, 0, 21, 1, 1.0)});
  shadow::add_mesh(scene, "pole", {shadow::rectangle_z(30, 0, 31, 1, 1.0)});
  shadow::add_mesh(scene, "Shading:Site", {shadow::rectangle_z(40, 0, 41, 1, 1.0)}, false);
  scene.meshes[0].object_type = scene.meshes[1].object_type = "BuildingPart";
  scene.meshes[0].parent = scene.meshes[1].parent = "city/B";
  scene.meshes[0].parent_type = scene.meshes[1].parent_type = "Building";
  scene.meshes[2].object_type = "Building";
  scene.meshes[3].object_type = "zone";
  const std::vector<shadow::SceneObject> objects = shadow::scene_objects(scene);
  ASSERT_EQ(objects.size(), 4u);
  EXPECT_EQ(objects[0].id, "city/B");
  EXPECT_EQ(objects[0].type, "Building");
  EXPECT_EQ(objects[0].meshes, (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(objects[1].id, "city/C");
  EXPECT_EQ(objects[2].type, "zone");
  EXPECT_EQ(objects[3].id, "pole");
  EXPECT_EQ(objects[3].type, "mesh");
  EXPECT_EQ(shadow::scene_objects(scene, false).size(), 5u);  // the shading mesh too
  const std::vector<shadow::SceneObject> meshes = shadow::scene_objects(scene, true, true);
  ASSERT_EQ(meshes.size(), 5u);
  EXPECT_EQ(meshes[1].id, "city/B-2");
  EXPECT_EQ(meshes[1].type, "BuildingPart");

  // A series made by hand: 2 instants of 0.5 h; lit areas chosen so the sums are exact.
  shadow::SeriesResult series;
  series.faces = {0, 1, 2, 3, 4, 5};  // every receiving face (the shading mesh's face 6 is none)
  series.instants = 2;
  series.area = {2.0, 1.0, 1.0, 3.0, 1.0, 1.0};
  series.lit_area = {2.0, 1.0,  0.5, 0.0,  1.0, 1.0,  3.0, 1.5,  0.25, 0.25,  1.0, 0.0};
  series.lit_fraction = {1.0, 0.5, 0.5, 0.0, 1.0, 1.0, 1.0, 0.5, 0.25, 0.25, 1.0, 0.0};
  series.faces_light.assign(12, 1);
  series.lit_area_error_bound.assign(12, 0.0);
  const shadow::ObjectSunHours hours = shadow::object_sun_hours(scene, series, 0.5);
  ASSERT_EQ(hours.objects.size(), 4u);
  EXPECT_EQ(hours.faces, (std::vector<std::size_t>{3, 1, 1, 1}));
  EXPECT_EQ(hours.area, (std::vector<double>{4.0, 3.0, 1.0, 1.0}));
  // city/B: (2 + 1 + 0.5 + 0 + 1 + 1) m2 x 0.5 h = 2.75 m2 h over 4 m2; the mean of its faces'
  // sun hours (0.75, 0.25, 1) weighted by their areas (2, 1, 1) is the same 0.6875 h.
  EXPECT_EQ(hours.sunlit_area_hours, (std::vector<double>{2.75, 2.25, 0.25, 0.5}));
  EXPECT_EQ(hours.sun_hours, (std::vector<double>{0.6875, 0.75, 0.25, 0.5}));
  const std::vector<double> face_hours = shadow::sun_hours(series, 0.5);
  EXPECT_EQ((face_hours[0] * 2 + face_hours[1] + face_hours[2]) / 4, hours.sun_hours[0]);
  const shadow::ObjectSunHours per_mesh = shadow::object_sun_hours(scene, series, 0.5, true);
  EXPECT_EQ(per_mesh.sun_hours, (std::vector<double>{0.75, 0.625, 0.75, 0.25, 0.5}));

  std::ostringstream csv;
  shadow::write_sun_hours_by_object_csv(csv, hours);
  EXPECT_EQ(csv.str(),
            "object,type,faces,area,sun_hours,sunlit_area_hours\r\n"
            "city/B,Building,3,4,0.6875,2.75\r\n"
            "city/C,Building,1,3,0.75,2.25\r\n"
            "Room,zone,1,1,0.25,0.25\r\n"
            "pole,mesh,1,1,0.5,0.5\r\n");
}

TEST(Series, TimesAndCsvFields) {
  EXPECT_EQ(shadow::format_iso8601_utc(0), "1970-01-01T00:00:00Z");
  EXPECT_EQ(shadow::format_iso8601_utc(utc(2028, 2, 29, 23, 45)), "2028-02-29T23:45:00Z");
  EXPECT_EQ(shadow::format_iso8601_utc(utc(2026, 12, 31, 23, 59) + 59), "2026-12-31T23:59:59Z");
  EXPECT_EQ(shadow::format_iso8601_utc(utc(1969, 12, 31, 12)), "1969-12-31T12:00:00Z");
  EXPECT_EQ(shadow::format_iso8601_utc(utc(2100, 3, 1)), "2100-03-01T00:00:00Z");
  for (shadow::UtcSeconds t = utc(1999, 1, 1); t < utc(2031, 1, 1); t += 86400 * 7 + 3601) {
    std::tm tm{};
    const std::time_t tt = static_cast<std::time_t>(t);
    gmtime_r(&tt, &tm);
    char expected[32];
    std::strftime(expected, sizeof expected, "%Y-%m-%dT%H:%M:%SZ", &tm);
    ASSERT_EQ(shadow::format_iso8601_utc(t), expected);
  }
  EXPECT_EQ(shadow::csv_field("plain"), "plain");
  EXPECT_EQ(shadow::csv_field("a,b"), "\"a,b\"");
  EXPECT_EQ(shadow::csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(shadow::csv_field("two\nlines"), "\"two\nlines\"");
}

/// series.pvd lists ceil(instants / every) readable .vtp files with lit_fraction.
void check_pvd(const fs::path& dir, std::size_t instants, std::size_t every) {
  std::ifstream pvd_file(dir / "series.pvd");
  const std::string pvd((std::istreambuf_iterator<char>(pvd_file)), std::istreambuf_iterator<char>());
  const std::regex file_re("file=\"([^\"]+)\"");
  std::size_t datasets = 0;
  for (auto it = std::sregex_iterator(pvd.begin(), pvd.end(), file_re); it != std::sregex_iterator(); ++it) {
    const fs::path file = dir / (*it)[1].str();
    ASSERT_TRUE(fs::exists(file)) << file;
    if (datasets++ % 500 == 0) {  // reading them all would take long: a sample
      vtkNew<vtkXMLPolyDataReader> reader;
      reader->SetFileName(file.c_str());
      reader->Update();
      vtkPolyData* poly = reader->GetOutput();
      ASSERT_EQ(poly->GetNumberOfCells(), 2);
      ASSERT_NE(poly->GetCellData()->GetArray("lit_fraction"), nullptr);
      EXPECT_EQ(poly->GetCellData()->GetArray("lit_fraction")->GetTuple1(0), 1.0);
    }
  }
  EXPECT_EQ(datasets, (instants + every - 1) / every);
}

/// The year files (sunlit.csv, energyplus-shading.csv, series.pvd, faces.vtp, report.json) of a
/// whole year in `dir`; checked here and, with LIBSHADOW_SERIES_FILES set, left there for the
/// Python check (tests/check_series_files.py).
void write_year(const fs::path& dir, int year, int step, std::size_t every) {
  shadow::Scene scene;
  shadow::add_mesh(scene, "square", {shadow::rectangle_z(0, 0, 10, 10, 0)});
  shadow::add_mesh(scene, "wall", {{{0, 12, 0}, {4, 12, 0}, {4, 12, 3}, {0, 12, 3}}});  // facing south
  scene.faces[0].name = "court \"yard\"";
  const bool leap = year % 4 == 0;
  const std::size_t count = static_cast<std::size_t>((leap ? 366 : 365) * 24 * 60 / step);
  add_equinox_period(scene, 45.0, utc(year, 1, 1), count, step, std::to_string(year) + "-01-01",
                     std::to_string(year) + "-12-31", /*energyplus=*/true);
  const shadow::SunSeries suns = shadow::sun_series(scene);
  const shadow::ShadowEngine engine(scene, 2);
  shadow::SeriesOptions options;
  options.threads = 2;
  const shadow::SeriesResult series = engine.compute_series(suns.lights, options);
  fs::remove_all(dir);
  shadow::OutputDirectory out(dir);
  shadow::OutputDirectory::SeriesFiles files;
  files.every = every;
  files.energyplus_shading = true;  // no EnergyPlus model here: asked for
  const std::vector<fs::path> written = out.write_series(scene, suns, series, files);
  ASSERT_FALSE(written.empty());
  EXPECT_EQ(written.back().filename(), "report.json");

  std::ifstream ep_file(dir / "energyplus-shading.csv");
  std::string line;
  std::getline(ep_file, line);
  // The names as EnergyPlus holds them: upper case.
  EXPECT_EQ(line, "Surface Name,\"COURT \"\"YARD\"\"\",FACE_1");
  std::size_t rows = 0;
  std::string first, last;
  while (std::getline(ep_file, line)) {
    if (rows == 0) first = line;
    last = line;
    ++rows;
  }
  EXPECT_EQ(rows, count);
  char first_stamp[16];
  std::snprintf(first_stamp, sizeof first_stamp, "01/01 00:%02d,", step % 60);
  EXPECT_EQ(first.rfind(step == 60 ? "01/01 01:00," : first_stamp, 0), 0u) << first;
  EXPECT_EQ(last.rfind("12/31 24:00,", 0), 0u) << last;

  std::ifstream report_file(dir / "report.json");
  const nlohmann::json report = nlohmann::json::parse(report_file);
  EXPECT_EQ(report["series"]["instants"], count);
  EXPECT_EQ(report["series"]["above_horizon"], suns.lights.size());
  EXPECT_EQ(report["series"]["energyplus"]["rows"], count);
  EXPECT_EQ(report["series"]["energyplus"]["rows_in_period"], count);
  // The equinox sun every day: the square has sun whenever the sun is up (12 h a day at hourly
  // steps, whose suns are mid-hour: 06:30..17:30), the south-facing wall too.
  const double days = leap ? 366 : 365;
  if (step == 60) {
    EXPECT_EQ(report["faces"][0]["sun_hours"], 12.0 * days);
    EXPECT_EQ(report["series"]["surfaces"][1]["sun_hours"], 12.0 * days);
  }

  // series.pvd names readable .vtp files with lit_fraction; faces.vtp has sun_hours.
  if (every == 0) {
    EXPECT_FALSE(fs::exists(dir / "series.pvd"));
  } else {
    check_pvd(dir, suns.lights.size(), every);
  }
  vtkNew<vtkXMLPolyDataReader> faces;
  faces->SetFileName((dir / "faces.vtp").c_str());
  faces->Update();
  ASSERT_NE(faces->GetOutput()->GetCellData()->GetArray("sun_hours"), nullptr);
  if (step == 60) EXPECT_EQ(faces->GetOutput()->GetCellData()->GetArray("sun_hours")->GetTuple1(0), 12.0 * days);
}

fs::path files_dir(const std::string& name) {
  const char* env = std::getenv("LIBSHADOW_SERIES_FILES");
  if (env != nullptr && *env != '\0') return fs::path(env) / name;
  return fs::temp_directory_path() / ("libshadow-series-" + std::to_string(getpid()) + "-" + name);
}

/// Writes and checks a year; the files stay only where LIBSHADOW_SERIES_FILES asked for them.
void year_case(const std::string& name, int year, int step, std::size_t every) {
  const fs::path dir = files_dir(name);
  write_year(dir, year, step, every);
  const char* env = std::getenv("LIBSHADOW_SERIES_FILES");
  if (env == nullptr || *env == '\0') fs::remove_all(dir);
}

TEST(SeriesFiles, Year2026Hourly) { year_case("2026-hourly", 2026, 60, 6); }
TEST(SeriesFiles, Year2028Hourly) { year_case("2028-hourly", 2028, 60, 24); }
TEST(SeriesFiles, Year2026QuarterHours) { year_case("2026-15min", 2026, 15, 0); }

TEST(SeriesFiles, ShortPeriodFillsTheRestOfTheYearWithZeros) {
  shadow::Scene scene;
  shadow::add_mesh(scene, "square", {shadow::rectangle_z(0, 0, 10, 10, 0)});
  add_equinox_period(scene, 45.0, utc(2026, 12, 21), 24 * 2, 30, "2026-12-21", "2026-12-21", true);
  scene.sun->step_minutes = 30;
  const shadow::EnergyPlusSchedule schedule = shadow::energyplus_schedule(scene);
  EXPECT_TRUE(schedule.written);
  EXPECT_EQ(schedule.rows, 365u * 48u);
  EXPECT_EQ(schedule.rows_in_period, 48u);
  EXPECT_NE(schedule.reason.find("the others are 0"), std::string::npos);
  scene.sun->step_minutes = 90;
  EXPECT_FALSE(shadow::energyplus_schedule(scene).written);
  // Instants at the steps' starts would give every row the sun of the step before EnergyPlus's
  // (half an hour early at hourly steps): no file, and the reason.
  scene.sun->step_minutes = 30;
  scene.sun->energyplus_times = false;
  const shadow::EnergyPlusSchedule starts = shadow::energyplus_schedule(scene);
  EXPECT_FALSE(starts.written);
  EXPECT_NE(starts.reason.find("EnergyPlus takes each step's sun at its end"), std::string::npos) << starts.reason;
}

// Each row holds the sun EnergyPlus takes for that time step: the instant at the step's end
// (the 15:15 row, 15:15), or mid-hour at hourly steps (the 16:00 row, 15:30). Rows held the
// sun of the step's start: one step early, half an hour at hourly steps.
TEST(SeriesFiles, EachRowHoldsTheSunEnergyPlusTakesForItsStep) {
  for (const int step : {15, 60}) {
    shadow::Scene scene;
    shadow::add_mesh(scene, "square", {shadow::rectangle_z(0, 0, 10, 10, 0)});
    const std::size_t per_day = static_cast<std::size_t>(24 * 60 / step);
    add_equinox_period(scene, 45.0, utc(2026, 3, 20), per_day, step, "2026-03-20", "2026-03-20", true);
    // A lit fraction per instant that names its time: minutes after midnight / 10000.
    const shadow::SunSeries suns = shadow::sun_series(scene);
    shadow::SurfaceSeries surfaces;
    surfaces.surfaces = shadow::named_surfaces(scene);
    surfaces.instants = suns.lights.size();
    surfaces.lit_fraction.resize(surfaces.instants);
    for (std::size_t i = 0; i < surfaces.instants; ++i)
      surfaces.lit_fraction[i] = static_cast<double>((suns.times[i] % 86400) / 60) / 10000.0;
    std::ostringstream csv;
    ASSERT_TRUE(shadow::write_energyplus_shading_csv(csv, scene, suns, surfaces).written);
    std::istringstream in(csv.str());
    std::string line;
    std::map<std::string, std::string> row;
    while (std::getline(in, line)) row[line.substr(0, line.find(','))] = line.substr(line.find(',') + 1);
    if (step == 15) {
      EXPECT_EQ(row.at("03/20 15:15"), "0.0915");  // 915 minutes: 15:15
      EXPECT_EQ(row.at("03/20 12:00"), "0.072");   // 720 minutes: noon
    } else {
      EXPECT_EQ(row.at("03/20 16:00"), "0.093");   // 930 minutes: 15:30
      EXPECT_EQ(row.at("03/20 13:00"), "0.075");   // 750 minutes: 12:30
    }
  }
}

TEST(SeriesFiles, APeriodAllBelowTheHorizonWritesEmptyRowsAndZeros) {
  shadow::Scene scene;
  shadow::add_mesh(scene, "square", {shadow::rectangle_z(0, 0, 10, 10, 0)});
  shadow::SunPeriod period;
  period.start = period.end = "2026-06-21";
  period.step_minutes = 60;
  period.energyplus_times = true;
  scene.sun = period;
  for (int h = 0; h < 24; ++h) {  // a polar night: every instant below the horizon, no light
    shadow::SunInstant instant;
    instant.time = utc(2026, 6, 21, h, 30);
    scene.sun_instants.push_back(instant);
  }
  const shadow::SunSeries suns = shadow::sun_series(scene);
  EXPECT_TRUE(suns.lights.empty());
  const shadow::ShadowEngine engine(scene, 1);
  const shadow::SeriesResult series = engine.compute_series(suns.lights);
  EXPECT_EQ(shadow::sun_hours(series, 1.0), std::vector<double>{0.0});
  const fs::path dir = files_dir("all-night");
  fs::remove_all(dir);
  {
    shadow::OutputDirectory out(dir);
    shadow::OutputDirectory::SeriesFiles files;
    files.energyplus_shading = true;
    out.write_series(scene, suns, series, files);
  }
  std::ifstream sunlit(dir / "sunlit.csv");
  const std::string text((std::istreambuf_iterator<char>(sunlit)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "time,face_0\r\n");
  std::ifstream ep(dir / "energyplus-shading.csv");
  std::string line;
  std::size_t rows = 0, zeros = 0;
  std::getline(ep, line);
  while (std::getline(ep, line)) {
    ++rows;
    zeros += line.substr(line.find(',')) == ",0" ? 1 : 0;
  }
  EXPECT_EQ(rows, 8760u);
  EXPECT_EQ(zeros, 8760u);
  EXPECT_TRUE(fs::exists(dir / "report.json"));
  EXPECT_FALSE(fs::exists(dir / ".shadow.lock"));
  fs::remove_all(dir);
}

TEST(SeriesFiles, FragmentsOfTheInstantsShownAddUpToTheirLitAreas) {
  shadow::Scene scene;
  shadow::add_mesh(scene, "square", {shadow::rectangle_z(0, 0, 10, 10, 0)});
  shadow::add_mesh(scene, "roof", {shadow::rectangle_z(0, 0, 10, 5, 1)}, false);
  add_equinox_period(scene, 45.0, utc(2026, 3, 20), 24, 60, "2026-03-20", "2026-03-20");
  const shadow::SunSeries suns = shadow::sun_series(scene);
  const shadow::ShadowEngine engine(scene, 2);
  const shadow::SeriesResult series = engine.compute_series(suns.lights);
  shadow::OutputDirectory::SeriesFiles files;
  files.every = 5;
  std::vector<std::size_t> asked;
  files.fragments = [&](std::size_t i) {
    asked.push_back(i);
    const std::size_t light = scene.sun_instants[suns.instants[i]].light_id;
    return engine.compute(scene.lights[light], light);
  };
  const fs::path dir = files_dir("fragments");
  fs::remove_all(dir);
  {
    shadow::OutputDirectory out(dir);
    out.write_series(scene, suns, series, files);
  }
  EXPECT_EQ(asked, (std::vector<std::size_t>{0, 5, 10}));
  ASSERT_TRUE(fs::exists(dir / "fragments.pvd"));
  for (std::size_t i : asked) {
    char name[64];
    std::snprintf(name, sizeof name, "series/fragments_%05zu.vtp", i);
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName((dir / name).c_str());
    reader->Update();
    vtkPolyData* poly = reader->GetOutput();
    vtkDataArray* lit = poly->GetCellData()->GetArray("lit");
    vtkDataArray* area = poly->GetCellData()->GetArray("area");
    vtkDataArray* face = poly->GetCellData()->GetArray("face_id");
    ASSERT_TRUE(lit && area && face) << name;
    double lit_area = 0;
    for (vtkIdType c = 0; c < poly->GetNumberOfCells(); ++c)
      if (face->GetTuple1(c) == 0 && lit->GetTuple1(c) == 1) lit_area += area->GetTuple1(c);
    EXPECT_NEAR(lit_area, series.lit_area[series.at(0, i)], 1e-9) << name;
  }
  // Written again without fragments: the earlier fragment files and fragments.pvd go.
  {
    shadow::OutputDirectory out(dir);
    out.write_series(scene, suns, series, 5);
  }
  EXPECT_FALSE(fs::exists(dir / "fragments.pvd"));
  EXPECT_FALSE(fs::exists(dir / "series" / "fragments_00000.vtp"));
  EXPECT_TRUE(fs::exists(dir / "series" / "sun_00000.vtp"));
  fs::remove_all(dir);
}

/// A wall named in mixed case, as IDF files name surfaces, under a day of hourly suns.
shadow::Scene mixed_case_scene() {
  shadow::Scene scene;
  shadow::add_mesh(scene, "zone", {{{0, 0, 0}, {4, 0, 0}, {4, 0, 3}, {0, 0, 3}}, shadow::rectangle_z(0, -5, 4, 0, 0)});
  scene.faces[0].name = "Zn001:Wall001";
  scene.faces[1].name = "Zn001:Flr001";
  add_equinox_period(scene, 45.0, utc(2026, 3, 20), 24, 60, "2026-03-20", "2026-03-20", /*energyplus=*/true);
  return scene;
}

/// The files write_series leaves in `dir` for `scene` with `files`, and report.json's series.energyplus.
std::pair<std::vector<std::string>, nlohmann::json> series_files(const shadow::Scene& scene, const fs::path& dir,
                                                                 shadow::OutputDirectory::SeriesFiles files) {
  const shadow::SunSeries suns = shadow::sun_series(scene);
  const shadow::ShadowEngine engine(scene, 1);
  const shadow::SeriesResult series = engine.compute_series(suns.lights);
  fs::remove_all(dir);
  files.every = 0;
  std::vector<std::string> names;
  {
    shadow::OutputDirectory out(dir);
    for (const fs::path& p : out.write_series(scene, suns, series, files)) names.push_back(p.filename().string());
  }
  std::ifstream report_file(dir / "report.json");
  return {names, nlohmann::json::parse(report_file)["series"]["energyplus"]};
}

TEST(SeriesFiles, EnergyPlusShadingOnlyForAnEnergyPlusModelOrWhenAsked) {
  shadow::Scene scene = mixed_case_scene();
  const fs::path dir = files_dir("energyplus-asked");
  auto has = [](const std::vector<std::string>& names) {
    return std::find(names.begin(), names.end(), "energyplus-shading.csv") != names.end();
  };
  // Not an EnergyPlus model, not asked: none, and report.json says why.
  EXPECT_FALSE(shadow::energyplus_shading_wanted(scene));
  auto [names, ep] = series_files(scene, dir, {});
  EXPECT_FALSE(has(names));
  EXPECT_FALSE(fs::exists(dir / "energyplus-shading.csv"));
  EXPECT_EQ(ep["written"], false);
  EXPECT_NE(ep["note"].get<std::string>().find("not asked for"), std::string::npos) << ep;
  // Asked for by the caller (the CLI's --energyplus-shading).
  shadow::OutputDirectory::SeriesFiles asked;
  asked.energyplus_shading = true;
  std::tie(names, ep) = series_files(scene, dir, asked);
  EXPECT_TRUE(has(names));
  EXPECT_EQ(ep["written"], true);
  // By the scene file's key.
  scene.energyplus_shading = true;
  EXPECT_TRUE(shadow::energyplus_shading_wanted(scene));
  EXPECT_TRUE(has(series_files(scene, dir, {}).first));
  // A mesh read from an EnergyPlus model: written unasked, and the key can still say no.
  scene.energyplus_shading.reset();
  scene.meshes[0].model = "energyplus";
  EXPECT_TRUE(shadow::energyplus_shading_wanted(scene));
  EXPECT_TRUE(has(series_files(scene, dir, {}).first));
  scene.energyplus_shading = false;
  EXPECT_FALSE(has(series_files(scene, dir, {}).first));
  EXPECT_FALSE(fs::exists(dir / "energyplus-shading.csv"));  // the earlier run's is gone
  fs::remove_all(dir);
}

TEST(SeriesFiles, EnergyPlusShadingNamesSurfacesInUpperCaseAsEnergyPlusDoes) {
  // EnergyPlus 9.6 upper-cases object names, then matches the header case-sensitively: a
  // column "Zn001:Wall001" would shade nothing. sunlit.csv keeps the model's own names.
  const shadow::Scene scene = mixed_case_scene();
  EXPECT_EQ(shadow::energyplus_name("Zn001:Wall001 ä-b"), "ZN001:WALL001 ä-B");
  const shadow::SunSeries suns = shadow::sun_series(scene);
  const shadow::ShadowEngine engine(scene, 1);
  const shadow::SeriesResult series = engine.compute_series(suns.lights);
  const shadow::SurfaceSeries surfaces = shadow::surface_series(scene, series, suns.hours_per_instant);
  std::ostringstream ep, sunlit;
  ASSERT_TRUE(shadow::write_energyplus_shading_csv(ep, scene, suns, surfaces).written);
  EXPECT_EQ(ep.str().substr(0, ep.str().find('\n')), "Surface Name,ZN001:WALL001,ZN001:FLR001");
  shadow::write_sunlit_csv(sunlit, suns, surfaces);
  EXPECT_EQ(sunlit.str().substr(0, sunlit.str().find("\r\n")), "time,Zn001:Wall001,Zn001:Flr001");
}

TEST(SeriesFiles, SurfacesThatDifferOnlyByCaseGiveNoEnergyPlusFile) {
  // One column to EnergyPlus: no file rather than a silently ambiguous one.
  shadow::Scene scene = mixed_case_scene();
  scene.faces[1].name = "ZN001:wall001";
  const shadow::EnergyPlusSchedule schedule = shadow::energyplus_schedule(scene);
  EXPECT_FALSE(schedule.written);
  EXPECT_NE(schedule.reason.find("\"Zn001:Wall001\" and \"ZN001:wall001\" differ only by case"), std::string::npos)
      << schedule.reason;
}

TEST(SeriesFiles, NoSunBlockIsAnInputError) {
  shadow::Scene scene;
  shadow::add_mesh(scene, "square", {shadow::rectangle_z(0, 0, 10, 10, 0)});
  EXPECT_THROW((void)shadow::sun_series(scene), shadow::InputError);
}

}  // namespace
