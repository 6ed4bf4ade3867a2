// SPDX-License-Identifier: GPL-3.0-or-later
// Irradiation over a weather period (shadow/irradiance.hpp): Perez 1990 against pvlib's
// published test values, sky view factors of unobstructed faces and of the infinite urban
// canyon (Johnson and Watson 1984), the direct component against the series engine bit for bit,
// and energy conservation.
#include <shadow/generators.hpp>
#include <shadow/irradiance.hpp>
#include <shadow/scene_io.hpp>
#include <shadow/shadows.hpp>
#include <shadow/epw.hpp>
#include <shadow/weather.hpp>

#include <gtest/gtest.h>

#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <string>

namespace {

constexpr double kPi = 3.14159265358979323846;

double cosd(double d) { return std::cos(d * kPi / 180.0); }
double sind(double d) { return std::sin(d * kPi / 180.0); }

// pvlib's test_irradiance.py (fixtures irrad_data, ephem_data, dni_et, relative_airmass; tests
// test_perez and test_perez_components, pvlib 0.9-0.11): a plane of tilt 40 facing south
// (azimuth 180) in Tucson on 2014-06-01 at 06:00 and 18:00 MST. Inputs and expected outputs
// are pvlib's numbers as published there; the angle of incidence follows from them.
struct PvlibCase {
  double dhi, dni, apparent_zenith, azimuth, dni_extra, airmass;
  double total, isotropic, circumsolar, horizon;
};
constexpr PvlibCase kPvlib[] = {
    {40.46149818, 316.1949056, 82.85457044, 66.71410338, 1321.1655834833093, 7.58831596, 31.46046871, 26.84138589,
     0.0, 4.62212181},
    {62.03376265, 646.22886049, 72.41687122, 287.04104128, 1321.1655834833093, 3.27930443, 45.45539877, 31.72696071,
     4.47966439, 9.25316454},
};

TEST(Perez, MatchesPvlibPublishedValues) {
  for (const PvlibCase& c : kPvlib) {
    const double tilt = 40.0, surface_azimuth = 180.0;
    const double cos_aoi = cosd(c.apparent_zenith) * cosd(tilt) +
                           sind(c.apparent_zenith) * sind(tilt) * cosd(c.azimuth - surface_azimuth);
    const shadow::PerezSky sky = shadow::perez_sky(c.dhi, c.dni, c.apparent_zenith, c.dni_extra, c.airmass);
    const shadow::PerezParts parts = shadow::perez_diffuse(tilt, cos_aoi, c.apparent_zenith, c.dhi, sky);
    EXPECT_NEAR(parts.isotropic, c.isotropic, 1e-6);
    EXPECT_NEAR(parts.circumsolar, c.circumsolar, 1e-6);
    EXPECT_NEAR(parts.horizon, c.horizon, 1e-6);
    EXPECT_NEAR(parts.total(), parts.isotropic + parts.circumsolar + parts.horizon, 1e-12);
    // pvlib's published total differs from the sum of its published components by 3e-3 W/m2
    // (its test compares them to 2 decimals): the components are matched to 1e-6 above.
    EXPECT_NEAR(parts.total(), c.total, 5e-3);
  }
  // Night: no diffuse, no coefficients.
  EXPECT_EQ(shadow::perez_sky(0.0, 0.0, 124.0390863, 1321.17, std::nan("")).bin, 0);
  // Kasten and Young's air mass against the fixture's (pvlib's default model).
  EXPECT_NEAR(shadow::relative_airmass(82.85457044), 7.58831596, 1e-6);
  EXPECT_NEAR(shadow::relative_airmass(72.41687122), 3.27930443, 1e-6);
  EXPECT_TRUE(std::isnan(shadow::relative_airmass(95.0)));
  // pvlib's test_get_extra_radiation: 1383.636203 W/m2 on 2016-10-26 (day 300), for every
  // method it has, within 10 W/m2; Spencer's is within 1.
  EXPECT_NEAR(shadow::extraterrestrial_normal(300), 1383.636203, 1.0);
  // Perihelion (early January) above aphelion (early July), by about 6.7 % (Spencer).
  EXPECT_NEAR(shadow::extraterrestrial_normal(3) / shadow::extraterrestrial_normal(185), 1.069, 2e-3);
}

TEST(SkyPatches, CountsAndSolidAngles) {
  for (int count : {145, 577, 2305}) {
    const std::vector<shadow::SkyPatch> patches = shadow::sky_patches(count);
    ASSERT_EQ(patches.size(), static_cast<std::size_t>(count));
    double solid = 0.0, cos_weighted = 0.0;
    for (const shadow::SkyPatch& p : patches) {
      solid += p.solid_angle;
      cos_weighted += p.solid_angle * p.to_patch.z / kPi;
    }
    EXPECT_NEAR(solid, 2.0 * kPi, 1e-12) << count;
    // The patch centres integrate cos over the hemisphere to within a percent.
    EXPECT_NEAR(cos_weighted, 1.0, 1e-2) << count;
  }
  EXPECT_THROW(shadow::sky_patches(100), shadow::InputError);
}

// A small EPW text: `days` days from 21 June, DNI 600 and DHI 100 from 06:00 to 18:00 local,
// global horizontal missing (9999) on one hour.
std::string sunny_epw(int days) {
  std::string text =
      "LOCATION,Canyon,XX,ZZZ,Test,000001,49.5,8.5,1.0,100.0\nDESIGN CONDITIONS,0\nTYPICAL/EXTREME PERIODS,0\n"
      "GROUND TEMPERATURES,0\nHOLIDAYS/DAYLIGHT SAVINGS,No,0,0,0\nCOMMENTS 1,test\nCOMMENTS 2,\n"
      "DATA PERIODS,1,1,Data,Wednesday, 6/21,6/" + std::to_string(20 + days) + "\n";
  for (int d = 0; d < days; ++d)
    for (int h = 1; h <= 24; ++h) {
      const bool day = h >= 7 && h <= 18;
      char line[256];
      std::snprintf(line, sizeof line,
                    "2023,6,%d,%d,60,x,15,10,70,100000,0,0,300,%s,%d,%d,0,0,0,0,180,2,5,5,20,77777,9,999999999,10,"
                    "0.1,0,88,999,0,0\n",
                    21 + d, h, h == 12 ? "9999" : day ? "500" : "0", day ? 600 : 0, day ? 100 : 0);
      text += line;
    }
  return text;
}

shadow::Weather weather(int days) {
  std::istringstream in(sunny_epw(days));
  return shadow::parse_epw(in, "sunny.epw");
}

// Faces in the open at several tilts: the sky view factor is (1 + cos tilt) / 2.
TEST(Irradiance, UnobstructedFacesSeeTheirHemisphere) {
  shadow::Scene scene;
  shadow::add_mesh(scene, "flat", {shadow::rectangle_z(0, 0, 1, 1, 0)});
  // Far apart (a patch 6 degrees up casts a 1 m face's shadow 10 m far): none shades another.
  shadow::add_mesh(scene, "wall", {{{100, 0, 0}, {101, 0, 0}, {101, 0, 1}, {100, 0, 1}}});  // faces -y (south)
  shadow::add_mesh(scene, "tilted", {{{200, 0, 0}, {201, 0, 0}, {201, 0.5, std::sqrt(0.75)}, {200, 0.5, std::sqrt(0.75)}}});
  shadow::validate_scene(scene);
  const shadow::ShadowEngine engine(scene, 1);
  for (int patches : {145, 577}) {
    shadow::IrradianceOptions options;
    options.sky_patches = patches;
    options.series.threads = 1;
    const shadow::IrradianceResult r = shadow::compute_irradiance(engine, scene, weather(1), options);
    ASSERT_EQ(r.faces.size(), 3u);
    EXPECT_EQ(r.sky_view_factor[0], 1.0);
    EXPECT_NEAR(r.sky_view_factor[1], 0.5, 1e-15);
    EXPECT_NEAR(r.sky_view_factor[2], 0.5 * (1.0 + 0.5), 1e-15);  // tilt 60 degrees
    for (std::size_t row = 0; row < 3; ++row) {
      // Nothing shades: every component equals its unshaded value.
      EXPECT_NEAR(r.direct[row], r.direct_unshaded[row], 1e-12);
      EXPECT_NEAR(r.sky_diffuse[row], r.sky_diffuse_unshaded[row], 1e-9);
      EXPECT_NEAR(r.total[row], r.direct[row] + r.sky_diffuse[row] + r.ground_reflected[row], 1e-9);
    }
    // The ground views of the open faces: exactly (1 - cos tilt) / 2, so that sky and ground add
    // up to 1; the horizontal face sees no ground (no ground patch is in front of it).
    EXPECT_EQ(r.ground_view[0], 0.0);
    EXPECT_NEAR(r.ground_view[1], 0.5, 1e-15);
    EXPECT_NEAR(r.ground_view[2], 0.25, 1e-15);
    for (std::size_t row = 0; row < 3; ++row) EXPECT_NEAR(r.sky_view_factor[row] + r.ground_view[row], 1.0, 1e-15);
    // The horizontal face: ground view 0; its diffuse is Perez's on a flat plane.
    EXPECT_EQ(r.ground_reflected[0], 0.0);
    // The ground reflectance defaults to 0.2 (the file's albedo is missing): the wall sees half
    // the ground, so it gets 0.2 x GHI / 2 summed.
    double ghi = 0.0;
    for (const shadow::IrradianceHour& h : r.hours) ghi += h.ghi;
    EXPECT_NEAR(r.ground_reflected[1], 0.2 * ghi * 0.5 / 1000.0, 1e-12);
  }
}

/// A street canyon of width w between two rows of buildings of height h, 60 w long; the
/// middle of the street (floor, walls) is a face of its own, length w, so that the canyon's
/// ends are 30 w away. Returns the face ids of the floor and the two walls.
struct Canyon {
  shadow::Scene scene;
  std::size_t floor = 0, west_wall = 0, east_wall = 0;
};

Canyon canyon(double h, double w, bool with_floor = true) {
  Canyon c;
  const double half = 30.0 * w, mid = 0.5 * w;
  const double ys[] = {-half, -mid, mid, half};
  for (int k = 0; k < 3; ++k) {
    std::vector<shadow::Polygon3> west = shadow::box_faces({-10.0, ys[k], 0.0}, {0.0, ys[k + 1], h});
    std::vector<shadow::Polygon3> east = shadow::box_faces({w, ys[k], 0.0}, {w + 10.0, ys[k + 1], h});
    const std::size_t west_first = shadow::add_mesh(c.scene, "west" + std::to_string(k), west);
    const std::size_t east_first = shadow::add_mesh(c.scene, "east" + std::to_string(k), east);
    if (k == 1) {
      c.west_wall = west_first + 4;  // box_faces order: top, bottom, south, north, east, west
      c.east_wall = east_first + 5;
    }
  }
  if (with_floor) c.floor = shadow::add_mesh(c.scene, "floor", {shadow::rectangle_z(0.0, -mid, w, mid, 0.0)});
  shadow::validate_scene(c.scene);
  return c;
}

std::size_t row_of(const shadow::IrradianceResult& r, std::size_t face) {
  for (std::size_t row = 0; row < r.faces.size(); ++row)
    if (r.faces[row] == face) return row;
  ADD_FAILURE() << "face " << face << " is not a row";
  return 0;
}

// Johnson and Watson (1984): the sky view factors of an infinitely long canyon of aspect ratio
// H/W, averaged over its floor and over a wall.
TEST(Irradiance, UrbanCanyonConvergesToJohnsonWatson) {
  for (double aspect : {0.5, 1.0, 2.0}) {
    const Canyon c = canyon(10.0 * aspect, 10.0);
    const double floor_svf = std::sqrt(1.0 + aspect * aspect) - aspect;
    const double wall_svf = 0.5 * (1.0 + aspect - std::sqrt(1.0 + aspect * aspect)) / aspect;
    const shadow::ShadowEngine engine(c.scene, 2);
    double previous_floor_error = 1.0;
    for (int patches : {145, 577, 2305}) {
      shadow::IrradianceOptions options;
      options.sky_patches = patches;
      options.series.threads = 2;
      const shadow::IrradianceResult r = shadow::compute_irradiance(engine, c.scene, weather(1), options);
      const double floor = r.sky_view_factor[row_of(r, c.floor)];
      const double west = r.sky_view_factor[row_of(r, c.west_wall)];
      const double east = r.sky_view_factor[row_of(r, c.east_wall)];
      std::printf("canyon H/W %.1f, %4d patches: floor %.5f (exact %.5f), walls %.5f %.5f (exact %.5f)\n", aspect,
                  patches, floor, floor_svf, west, east, wall_svf);
      // Relative errors measured (docs/irradiance.md): the deep canyon's floor, a narrow slot of
      // sky, is the hardest (7 %, 1.6 %, 0.4 % at H/W = 2).
      const double tolerance = patches == 145 ? 0.08 : patches == 577 ? 0.02 : 0.005;
      EXPECT_NEAR(floor, floor_svf, tolerance * floor_svf) << patches;
      EXPECT_NEAR(west, wall_svf, tolerance * wall_svf) << patches;
      EXPECT_NEAR(east, wall_svf, tolerance * wall_svf) << patches;
      // The floor's error does not grow with the patch count.
      const double floor_error = std::abs(floor - floor_svf);
      EXPECT_LE(floor_error, previous_floor_error + 1e-3) << patches;
      previous_floor_error = floor_error;
    }
  }
}

// The direct component is sum over hours of DNI x cos(incidence) x the sunlit fraction that
// ShadowEngine::compute_series reports for the hour's sun, bit for bit; energy is conserved.
TEST(Irradiance, DirectIsTheSeriesSumBitForBitAndEnergyIsConserved) {
  const Canyon c = canyon(10.0, 10.0);
  const shadow::ShadowEngine engine(c.scene, 2);
  const shadow::Weather w = weather(2);
  for (shadow::Arithmetic arithmetic : {shadow::Arithmetic::Exact, shadow::Arithmetic::Fast}) {
    shadow::IrradianceOptions options;
    options.series.threads = 2;
    options.series.arithmetic = arithmetic;
    const shadow::IrradianceResult r = shadow::compute_irradiance(engine, c.scene, w, options);
    ASSERT_FALSE(r.sun_lights.empty());
    shadow::SeriesOptions series;
    series.threads = 1;
    series.arithmetic = arithmetic;
    const shadow::SeriesResult s = engine.compute_series(r.sun_lights, series);
    ASSERT_EQ(s.faces, r.faces);
    for (std::size_t row = 0; row < r.faces.size(); ++row) {
      double direct = 0.0;
      for (const shadow::IrradianceHour& h : r.hours) {
        if (h.sun == shadow::IrradianceHour::none) continue;
        const double lit = s.lit_fraction[s.at(row, h.sun)];
        EXPECT_EQ(std::memcmp(&lit, &r.sun.lit_fraction[r.sun.at(row, h.sun)], sizeof lit), 0);
        const double cos_incidence = r.normal[row].x * h.to_sun.x + r.normal[row].y * h.to_sun.y +
                                     r.normal[row].z * h.to_sun.z;
        if (cos_incidence > 0.0 && lit > 0.0) direct += h.dni * cos_incidence * lit;
      }
      EXPECT_EQ(r.direct[row], direct / 1000.0) << "row " << row;
    }
    // The sun of each hour is the SPA's at mid-hour: 12:00-13:00 local (UTC+1) on 21 June is
    // 11:30 UTC.
    const shadow::IrradianceHour& noon = r.hours[12];
    shadow::SolarSite site;
    site.latitude = 49.5;
    site.longitude = 8.5;
    site.elevation = 100.0;
    site.pressure = 1013.25 * std::pow(1.0 - 2.25577e-5 * 100.0, 5.25588);
    const shadow::SunPosition sun = shadow::solar_position(site, w.start_utc[12] + 1800);
    EXPECT_EQ(shadow::format_iso8601_utc(w.start_utc[12] + 1800), "2023-06-21T11:30:00Z");
    EXPECT_EQ(noon.zenith, sun.zenith);
    // Energy: shaded never above unshaded, no component negative, the total their sum.
    EXPECT_LE(r.max_direct_excess, 1e-9);
    EXPECT_LE(r.max_diffuse_excess, 1e-9);
    EXPECT_GE(r.min_component, 0.0);
    for (std::size_t row = 0; row < r.faces.size(); ++row) {
      EXPECT_LE(r.direct[row], r.direct_unshaded[row] + 1e-12);
      EXPECT_LE(r.sky_diffuse[row], r.sky_diffuse_unshaded[row] + 1e-9);
      double months = 0.0;
      for (int m = 0; m < 12; ++m) months += r.monthly_total[row * 12 + m];
      EXPECT_NEAR(months, r.total[row], 1e-9);
    }
  }
}

// The direct irradiation map: over each face, the area-weighted mean of its cells' direct
// kWh/m2 is the face's direct irradiation (an exact overlay against the per-hour lit fractions).
TEST(Irradiance, MapCellsAddUpToTheFacesDirect) {
  const Canyon c = canyon(10.0, 10.0);
  const shadow::ShadowEngine engine(c.scene, 2);
  shadow::IrradianceOptions options;
  options.series.threads = 2;
  const shadow::IrradianceResult r = shadow::compute_irradiance(engine, c.scene, weather(1), options);
  // The floor, both walls, and a bottom face that never sees the beam (no instant at all).
  const std::size_t bottom = c.west_wall - 3;
  shadow::SunHoursOptions map_options;
  map_options.threads = 2;
  const shadow::SunHoursMap map =
      shadow::irradiation_map(engine, r, {c.east_wall, c.floor, c.west_wall, bottom}, map_options);
  ASSERT_EQ(map.faces.size(), 4u);
  for (const shadow::SunHoursFace& face : map.faces) {
    double integral = 0.0;
    std::size_t previous = 0;
    for (const shadow::SunHoursCell& cell : map.cells) {
      if (cell.face_id != face.face_id) continue;
      integral += cell.sun_hours * cell.area;
      EXPECT_GE(cell.face_id, previous);
      previous = cell.face_id;
    }
    const std::size_t row = row_of(r, face.face_id);
    EXPECT_NEAR(integral / face.area, r.direct[row], 1e-9 * (1.0 + r.direct[row])) << face.face_id;
    EXPECT_NEAR(face.hour_area / face.area, r.direct[row], 1e-9 * (1.0 + r.direct[row])) << face.face_id;
  }
  EXPECT_GT(r.direct[row_of(r, c.floor)], 0.0);
  EXPECT_EQ(r.direct[row_of(r, bottom)], 0.0);
}

// A missing direct normal or diffuse value counts 0 and the other is kept, as EnergyPlus reads
// them (before, either missing zeroed the whole hour); both missing, the hour adds nothing. Each
// case against the same file with the value written as 0, bit for bit, on a roof, a south wall
// and a wall facing away from the sun.
TEST(Irradiance, AMissingValueCountsZeroAndKeepsTheOther) {
  shadow::Scene scene;
  shadow::add_mesh(scene, "flat", {shadow::rectangle_z(0, 0, 1, 1, 0)});
  shadow::add_mesh(scene, "south", {{{100, 0, 0}, {101, 0, 0}, {101, 0, 1}, {100, 0, 1}}});
  shadow::add_mesh(scene, "north", {{{201, 0, 0}, {200, 0, 0}, {200, 0, 1}, {201, 0, 1}}});
  shadow::validate_scene(scene);
  const shadow::ShadowEngine engine(scene, 1);
  shadow::IrradianceOptions options;
  options.series.threads = 1;
  const shadow::Weather base = weather(1);
  const std::size_t noon = 12, afternoon = 15;  // records of hours 13 and 16: DNI 600, DHI 100
  ASSERT_EQ(base.direct_normal[noon], 600.0);
  ASSERT_EQ(base.diffuse_horizontal[afternoon], 100.0);
  const shadow::IrradianceResult full = shadow::compute_irradiance(engine, scene, base, options);
  EXPECT_EQ(full.missing_hours, 0u);
  auto run = [&](std::vector<double> shadow::Weather::*field, std::size_t rec, double value) {
    shadow::Weather w = base;
    (w.*field)[rec] = value;
    return shadow::compute_irradiance(engine, scene, w, options);
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (auto field : {&shadow::Weather::direct_normal, &shadow::Weather::diffuse_horizontal}) {
    for (std::size_t rec : {noon, afternoon}) {
      const shadow::IrradianceResult missing = run(field, rec, nan);
      const shadow::IrradianceResult zero = run(field, rec, 0.0);
      EXPECT_EQ(missing.missing_hours, 1u);
      EXPECT_EQ(zero.missing_hours, 0u);
      for (std::size_t row = 0; row < 3; ++row) {
        EXPECT_EQ(missing.direct[row], zero.direct[row]) << row;
        EXPECT_EQ(missing.sky_diffuse[row], zero.sky_diffuse[row]) << row;
        EXPECT_EQ(missing.ground_reflected[row], zero.ground_reflected[row]) << row;
        EXPECT_EQ(missing.total[row], zero.total[row]) << row;
      }
      // The value kept still counts: the hour is not dropped whole.
      EXPECT_GT(full.total[0] - missing.total[0], 0.0);
      EXPECT_LT(full.total[0] - missing.total[0], (field == &shadow::Weather::direct_normal ? 0.6 : 0.1) + 1e-9);
    }
  }
  // Both missing: the hour adds nothing, its global horizontal value (500) not read either.
  shadow::Weather both = base, dark = base;
  both.direct_normal[afternoon] = both.diffuse_horizontal[afternoon] = nan;
  dark.direct_normal[afternoon] = dark.diffuse_horizontal[afternoon] = dark.global_horizontal[afternoon] = 0.0;
  const shadow::IrradianceResult a = shadow::compute_irradiance(engine, scene, both, options);
  const shadow::IrradianceResult b = shadow::compute_irradiance(engine, scene, dark, options);
  EXPECT_EQ(a.missing_hours, 1u);
  for (std::size_t row = 0; row < 3; ++row) EXPECT_EQ(a.total[row], b.total[row]) << row;
  EXPECT_GT(b.total[1], 0.0);
}

// Perez's horizon band can be negative (a low sun, overcast hours): a wall whose horizon a fence hides loses
// that negative term and gets more sky diffuse than in the open. The model's own, so the energy
// check allows it (it reported FAILED on clean inputs) and says how large it was; an excess
// beyond that allowance still fails.
TEST(Irradiance, EnergyCheckAllowsPerezNegativeHorizonBand) {
  shadow::Scene scene;
  shadow::add_mesh(scene, "wall", {{{0, 0, 0}, {10, 0, 0}, {10, 0, 10}, {0, 0, 10}}});  // faces -y
  shadow::add_mesh(scene, "fence", {{{-50, -5, 0}, {-50, -5, 2}, {60, -5, 2}, {60, -5, 0}}});
  scene.meshes[1].receiver = false;
  shadow::validate_scene(scene);
  const shadow::ShadowEngine engine(scene, 1);
  // A clear sky with the sun near the horizon (Tokyo's year has such hours: DNI 314, DHI 44 at
  // zenith 89.7 degrees gave F1 0 and F2 -0.26): every hour DNI 300 and DHI 45.
  shadow::Weather low_sun = weather(1);
  for (std::size_t h = 0; h < low_sun.hours(); ++h) {
    low_sun.direct_normal[h] = 300.0;
    low_sun.diffuse_horizontal[h] = 45.0;
  }
  shadow::IrradianceOptions options;
  options.series.threads = 1;
  const shadow::IrradianceResult r = shadow::compute_irradiance(engine, scene, low_sun, options);
  ASSERT_EQ(r.faces.size(), 1u);
  double largest = 0.0, allowance = 0.0;
  for (std::size_t h = 0; h < r.hours.size(); ++h) {
    const shadow::FaceIrradiance e = shadow::face_irradiance(r, 0, h);
    largest = std::max(largest, e.sky_diffuse - e.sky_diffuse_unshaded);
    allowance = std::max(allowance, e.sky_diffuse_horizon_allowance);
  }
  EXPECT_GT(largest, 1e-3);  // the effect is there (W/m2)
  EXPECT_LE(largest, allowance + 1e-9);
  EXPECT_EQ(r.max_horizon_band_excess, largest);
  EXPECT_LE(r.max_diffuse_excess, 1e-9);
  EXPECT_TRUE(r.energy_check_ok());
  shadow::IrradianceResult broken = r;
  broken.max_diffuse_excess = 1e-3;
  EXPECT_FALSE(broken.energy_check_ok());
}

// A scene for irradiance needs no lights (its suns come from the weather file); others still do.
TEST(Irradiance, ScenesNeedNoLights) {
  const std::string text = R"({"meshes": [{"name": "roof", "polygons": [[[0,0,0],[1,0,0],[1,1,0],[0,1,0]]]}]})";
  shadow::LoadOptions options;
  EXPECT_THROW(shadow::parse_scene(text, "roof.json", options), shadow::InputError);
  options.require_lights = false;
  const shadow::Scene scene = shadow::parse_scene(text, "roof.json", options);
  EXPECT_EQ(scene.faces.size(), 1u);
  EXPECT_TRUE(scene.lights.empty());
}

// The fast path within its stated bounds: direct irradiation and sky view factors against exact.
TEST(Irradiance, FastWithinItsBounds) {
  const Canyon c = canyon(10.0, 10.0);
  const shadow::ShadowEngine engine(c.scene, 2);
  shadow::IrradianceOptions options;
  options.series.threads = 2;
  const shadow::IrradianceResult exact = shadow::compute_irradiance(engine, c.scene, weather(1), options);
  options.series.arithmetic = shadow::Arithmetic::Fast;
  const shadow::IrradianceResult fast = shadow::compute_irradiance(engine, c.scene, weather(1), options);
  ASSERT_EQ(exact.faces, fast.faces);
  for (std::size_t row = 0; row < exact.faces.size(); ++row) {
    EXPECT_EQ(exact.direct_error_bound[row], 0.0);
    EXPECT_LE(std::abs(fast.direct[row] - exact.direct[row]), fast.direct_error_bound[row] + 1e-12) << row;
    EXPECT_LE(std::abs(fast.sky_view_factor[row] - exact.sky_view_factor[row]),
              fast.sky_view_factor_error_bound[row] + 1e-12)
        << row;
    EXPECT_EQ(exact.ground_view_factor_error_bound[row], 0.0);
    EXPECT_LE(std::abs(fast.ground_view[row] - exact.ground_view[row]), fast.ground_view_factor_error_bound[row] + 1e-12)
        << row;
  }
}

// Faces looking down see the whole ground, except a CityJSON GroundSurface, which rests on it.
TEST(Irradiance, GroundSurfacesSeeNoGround) {
  shadow::Scene scene;
  shadow::add_mesh(scene, "soffit", {shadow::rectangle_z(0, 0, 1, 1, 3, false)});
  shadow::add_mesh(scene, "footprint", {shadow::rectangle_z(100, 0, 101, 1, 0, false)});
  scene.faces[1].kind = "GroundSurface";
  shadow::validate_scene(scene);
  const shadow::ShadowEngine engine(scene, 1);
  shadow::IrradianceOptions options;
  options.series.threads = 1;
  options.ground_reflectance = 0.25;
  const shadow::IrradianceResult r = shadow::compute_irradiance(engine, scene, weather(1), options);
  double ghi = 0.0;
  for (const shadow::IrradianceHour& h : r.hours) ghi += h.ghi;
  EXPECT_EQ(r.ground_view[0], 1.0);
  EXPECT_NEAR(r.ground_reflected[0], 0.25 * ghi / 1000.0, 1e-12);
  EXPECT_EQ(r.sky_view_factor[0], 0.0);
  EXPECT_EQ(r.total[1], 0.0);
}

// The ground patches are the sky's mirrored below the horizon; their cos-weighted sum over the
// patches in front of a face converges to the face's view of the open ground, (1 - cos tilt) / 2,
// as the patches grow finer (the reported value is scaled to it exactly).
TEST(GroundPatches, MirrorTheSkyAndConverge) {
  for (int count : {145, 577, 2305}) {
    const std::vector<shadow::SkyPatch> sky = shadow::sky_patches(count, 20.0);
    const std::vector<shadow::SkyPatch> ground = shadow::ground_patches(count, 20.0);
    ASSERT_EQ(ground.size(), sky.size());
    double solid = 0.0;
    for (std::size_t p = 0; p < ground.size(); ++p) {
      EXPECT_EQ(ground[p].altitude, -sky[p].altitude);
      EXPECT_EQ(ground[p].to_patch.x, sky[p].to_patch.x);
      EXPECT_EQ(ground[p].to_patch.y, sky[p].to_patch.y);
      EXPECT_EQ(ground[p].to_patch.z, -sky[p].to_patch.z);
      EXPECT_LT(ground[p].to_patch.z, 0.0);
      solid += ground[p].solid_angle;
    }
    EXPECT_NEAR(solid, 2.0 * kPi, 1e-12);
  }
  for (double tilt : {30.0, 60.0, 90.0, 120.0, 150.0}) {
    const glm::dvec3 n(0.0, -sind(tilt), cosd(tilt));  // facing south
    double previous = 1.0;
    for (int count : {145, 577, 2305}) {
      double sum = 0.0;
      for (const shadow::SkyPatch& p : shadow::ground_patches(count)) {
        const double c = n.x * p.to_patch.x + n.y * p.to_patch.y + n.z * p.to_patch.z;
        if (c > 0.0) sum += c * p.solid_angle / kPi;
      }
      const double error = std::abs(sum - 0.5 * (1.0 - cosd(tilt)));
      std::printf("ground patches, tilt %3.0f, %4d patches: %.6f (exact %.6f)\n", tilt, count, sum,
                  0.5 * (1.0 - cosd(tilt)));
      EXPECT_LT(error, 0.012) << tilt << " " << count;
      EXPECT_LT(error, previous + 1e-4) << tilt << " " << count;
      previous = error;
    }
    EXPECT_LT(previous, 1.5e-3) << tilt;
  }
}

// A box on a ground plane that is a face of the scene: the ground face is the ground, so a wall
// sees half the world below it as ground; the same ground not marked as ground (an explicit empty
// `ground`) hides it all; a roof sees no ground; the ground face itself sees none (it is flat).
TEST(Irradiance, GroundFacesAreTheGround) {
  shadow::Scene scene;
  const std::size_t ground_face = shadow::add_mesh(scene, "ground", {shadow::rectangle_z(-1000, -1000, 1000, 1000, 0)});
  const std::size_t box = shadow::add_mesh(scene, "box", shadow::box_faces({0, 0, 0}, {4, 4, 3}));
  const std::size_t roof = box, south = box + 2;  // box_faces order: top, bottom, south, north, east, west
  shadow::validate_scene(scene);
  const std::vector<unsigned char> marked = shadow::ground_faces(scene);
  EXPECT_EQ(marked[ground_face], 1);
  EXPECT_EQ(marked[south], 0);
  const shadow::Weather w = weather(1);
  double ghi = 0.0;
  for (int count : {145, 577}) {
    for (bool as_ground : {true, false}) {
      shadow::Scene s = scene;
      if (!as_ground) s.ground.emplace();  // the scene names no ground mesh
      const shadow::ShadowEngine engine(s, 1);
      shadow::IrradianceOptions options;
      options.sky_patches = count;
      options.series.threads = 1;
      options.ground_reflectance = 0.2;
      const shadow::IrradianceResult r = shadow::compute_irradiance(engine, s, w, options);
      ghi = 0.0;
      for (const shadow::IrradianceHour& h : r.hours) ghi += h.ghi;
      const std::size_t wall = row_of(r, south);
      EXPECT_EQ(r.ground_view[row_of(r, roof)], 0.0);
      EXPECT_EQ(r.ground_view[row_of(r, ground_face)], 0.0);
      EXPECT_EQ(r.on_ground[row_of(r, ground_face)], as_ground ? 1 : 0);
      // The box's bottom rests on the ground plane: no ground view when the plane is the ground
      // (the rule has a ground to compare with); without a ground mesh it looks down onto the
      // open ground (the coplanar plane casts nothing on it).
      EXPECT_EQ(r.ground_view[row_of(r, roof + 1)], as_ground ? 0.0 : 1.0);
      if (as_ground) {
        // Nothing but the ground below the wall: exactly the open wall's half.
        EXPECT_NEAR(r.ground_view[wall], 0.5, 1e-15) << count;
        EXPECT_NEAR(r.ground_reflected[wall], 0.2 * ghi * 0.5 / 1000.0, 1e-12);
      } else {
        // The plane (2 km wide) catches every downward ray of the 3 m wall: no ground is seen,
        // only a scene face, whose reflection is the scene's own (not computed here).
        EXPECT_EQ(r.ground_view[wall], 0.0) << count;
        EXPECT_EQ(r.ground_reflected[wall], 0.0);
      }
    }
  }
}

// Johnson and Watson's canyon, below the horizon: a wall of an infinite canyon of aspect ratio
// x = H/W sees the street (the ground) with the form factor of two perpendicular strips sharing an
// edge (crossed strings), (H + W - sqrt(H^2 + W^2)) / (2 H) = (1 + x - sqrt(1 + x^2)) / (2 x), the
// rest below its horizon being the opposite wall. The street marked as ground, or no street face
// at all (the open ground plane), give the same; by the canyon's symmetry about mid-height it is
// also the wall's sky view factor, patch for patch. The floor, flat, sees no ground.
TEST(Irradiance, UrbanCanyonWallsSeeTheStreet) {
  for (double aspect : {0.5, 1.0, 2.0}) {
    const double exact = 0.5 * (1.0 + aspect - std::sqrt(1.0 + aspect * aspect)) / aspect;
    for (bool with_floor : {true, false}) {
      Canyon c = canyon(10.0 * aspect, 10.0, with_floor);
      if (with_floor) c.scene.ground = std::vector<std::size_t>{c.scene.meshes.size() - 1};  // the floor
      const shadow::ShadowEngine engine(c.scene, 2);
      for (int patches : {145, 577, 2305}) {
        if (!with_floor && patches == 2305) continue;  // the same rays as with the floor
        shadow::IrradianceOptions options;
        options.sky_patches = patches;
        options.series.threads = 2;
        const shadow::IrradianceResult r = shadow::compute_irradiance(engine, c.scene, weather(1), options);
        const double west = r.ground_view[row_of(r, c.west_wall)];
        const double east = r.ground_view[row_of(r, c.east_wall)];
        std::printf("canyon H/W %.1f, %4d patches, %s: wall ground view %.5f %.5f (exact %.5f)\n", aspect, patches,
                    with_floor ? "street as ground" : "no street face", west, east, exact);
        const double tolerance = patches == 145 ? 0.01 : patches == 577 ? 0.003 : 0.001;
        EXPECT_NEAR(west, exact, tolerance * exact) << patches;
        EXPECT_NEAR(east, exact, tolerance * exact) << patches;
        EXPECT_NEAR(west, r.sky_view_factor[row_of(r, c.west_wall)], 1e-12) << patches;
        if (with_floor) {
          EXPECT_EQ(r.ground_view[row_of(r, c.floor)], 0.0);
          EXPECT_EQ(r.on_ground[row_of(r, c.floor)], 1);
        }
      }
    }
  }
}

// The scene file's `ground` names the ground meshes, spelt as `receivers`; an unknown name is an
// error at its place; without the key the default rule holds (a mesh named `ground`).
TEST(Irradiance, SceneFileNamesTheGround) {
  const std::string meshes = R"("meshes": [{"name": "street", "polygons": [[[0,0,0],[9,0,0],[9,9,0],[0,9,0]]]},
                                           {"name": "ground", "polygons": [[[20,0,0],[29,0,0],[29,9,0],[20,9,0]]]}])";
  shadow::LoadOptions options;
  options.require_lights = false;
  const shadow::Scene named = shadow::parse_scene("{" + meshes + R"(, "ground": ["street"]})", "s.json", options);
  ASSERT_TRUE(named.ground.has_value());
  EXPECT_EQ(*named.ground, std::vector<std::size_t>{0});
  EXPECT_EQ(shadow::ground_faces(named), (std::vector<unsigned char>{1, 0}));
  const shadow::Scene plain = shadow::parse_scene("{" + meshes + "}", "s.json", options);
  EXPECT_FALSE(plain.ground.has_value());
  EXPECT_EQ(shadow::ground_faces(plain), (std::vector<unsigned char>{0, 1}));
  const shadow::Scene none = shadow::parse_scene("{" + meshes + R"(, "ground": []})", "s.json", options);
  EXPECT_EQ(shadow::ground_faces(none), (std::vector<unsigned char>{0, 0}));
  try {
    (void)shadow::parse_scene("{" + meshes + R"(, "ground": ["road"]})", "s.json", options);
    ADD_FAILURE() << "no error";
  } catch (const shadow::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ground[0]"), std::string::npos) << e.what();
  }
}

TEST(Irradiance, OptionsAreChecked) {
  shadow::Scene scene;
  shadow::add_mesh(scene, "flat", {shadow::rectangle_z(0, 0, 1, 1, 0)});
  shadow::validate_scene(scene);
  const shadow::ShadowEngine engine(scene, 1);
  shadow::IrradianceOptions options;
  options.ground_reflectance = 1.5;
  EXPECT_THROW(shadow::compute_irradiance(engine, scene, weather(1), options), shadow::InputError);
  options.ground_reflectance = 0.3;
  options.sky_patches = 146;
  EXPECT_THROW(shadow::compute_irradiance(engine, scene, weather(1), options), shadow::InputError);
  options.sky_patches = 145;
  options.first_record = 30;
  EXPECT_THROW(shadow::compute_irradiance(engine, scene, weather(1), options), shadow::InputError);
}

}  // namespace
