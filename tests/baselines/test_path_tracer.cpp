// SPDX-License-Identifier: GPL-3.0-or-later
// The diffuse path tracer (path_trace_faces, path_trace_points) against analytic answers: the
// furnace (a closed box that emits E and reflects rho everywhere has H = E / (1 - rho)),
// Howell's parallel unit squares (F = 0.1998249) through an emitting face and through an area
// light, the exact sums of a fixed number of bounces, hard lights, radiosity in a closed room with an
// emitting floor (an independent method); and its determinism.
#include <shadow/baselines.hpp>
#include "support/scene_builders.hpp"

#include <shadow/generators.hpp>
#include <shadow/radiosity.hpp>
#include <shadow/scene.hpp>
#include <shadow/validation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace {

using glm::dvec3;
using shadow::Scene;

constexpr double kPi = 3.14159265358979323846;
/// F between two directly opposed parallel unit squares 1 apart (closed form; Howell 0.19982).
constexpr double kParallelSquares = 0.19982489569838;

Scene furnace(double e, double rho) { return shadow::test::furnace_room(e, rho); }

/// A black unit floor [0, 1]^2 facing up (face 0) under a unit square at height 1 facing down
/// (face 1), which emits `e` (reflectance 0).
Scene emitting_square_over_floor(double e) {
  Scene scene;
  shadow::Material lamp;
  lamp.name = "lamp";
  lamp.emittance = e;
  scene.materials.push_back(lamp);
  shadow::add_mesh(scene, "floor", {{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}});
  shadow::add_mesh(scene, "lamp", {{{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}}});
  scene.meshes[1].material = "lamp";
  shadow::validate_scene(scene);
  return scene;
}

shadow::PathTracerOptions options_of(std::uint64_t samples, unsigned threads = 2) {
  shadow::PathTracerOptions o;
  o.samples = samples;
  o.threads = threads;
  o.seed = 32;
  return o;
}

TEST(PathTracer, FurnaceIsEOverOneMinusRhoWithinFourSigma) {
  const double e = 10.0, rho = 0.6, expected = e / (1 - rho);
  const Scene scene = furnace(e, rho);
  const shadow::PathTracerResult r = shadow::path_trace_faces(scene, options_of(4000));
  ASSERT_EQ(r.estimates.size(), 6u);
  EXPECT_EQ(r.max_bounces, 0u);
  EXPECT_TRUE(r.russian_roulette);
  EXPECT_EQ(r.paths, 6u * 4000u);
  for (const shadow::IrradianceEstimate& est : r.estimates) {
    // One path's H is E times a geometric number of hits: sd E sqrt(rho) / (1 - rho) = 19.4.
    EXPECT_GT(est.standard_error, 0.2);
    EXPECT_LT(est.standard_error, 0.45);
    EXPECT_NEAR(est.irradiance, expected, 4 * est.standard_error) << "face " << est.face_id;
    EXPECT_NEAR(est.radiosity, e + rho * est.irradiance, 1e-12);
    EXPECT_EQ(est.direct_irradiance, 0.0);  // no lights
    EXPECT_GT(est.area, 1.0);
  }
}

TEST(PathTracer, FixedBouncesWithoutRouletteSumTheSeriesExactly) {
  // Every path in the closed box hits a front: H = E (1 + rho + rho^2) for two bounces, every path.
  const Scene scene = furnace(10.0, 0.6);
  shadow::PathTracerOptions o = options_of(256);
  o.russian_roulette = false;
  o.max_bounces = 2;
  const shadow::PathTracerResult r = shadow::path_trace_faces(scene, o);
  EXPECT_EQ(r.max_bounces, 2u);
  EXPECT_FALSE(r.russian_roulette);
  for (const shadow::IrradianceEstimate& est : r.estimates) {
    EXPECT_NEAR(est.irradiance, 10.0 * (1 + 0.6 + 0.36), 1e-9) << "face " << est.face_id;
    EXPECT_LT(est.standard_error, 1e-6);
  }
  // With the roulette the same truncation is reached on average.
  o.russian_roulette = true;
  o.samples = 4000;
  for (const shadow::IrradianceEstimate& est : shadow::path_trace_faces(scene, o).estimates)
    EXPECT_NEAR(est.irradiance, 19.6, 4 * est.standard_error) << "face " << est.face_id;
}

TEST(PathTracer, EmittingSquareOverFloorGivesHowellsFormFactor) {
  const Scene scene = emitting_square_over_floor(1.0);
  const shadow::PathTracerResult r = shadow::path_trace_faces(scene, options_of(200000));
  const shadow::IrradianceEstimate& floor = r.estimates[0];
  // Binary per path (the lamp is hit or not): sigma = sqrt(F (1 - F) / n) = 8.9e-4.
  EXPECT_NEAR(floor.standard_error, std::sqrt(kParallelSquares * (1 - kParallelSquares) / 200000), 2e-5);
  EXPECT_NEAR(floor.irradiance, kParallelSquares, 4 * floor.standard_error);
  EXPECT_EQ(floor.radiosity, 0.0);  // black
  EXPECT_EQ(r.estimates[1].irradiance, 0.0);  // the lamp sees the floor's black front
  EXPECT_EQ(r.estimates[1].radiosity, 1.0);   // its own emittance
}

TEST(PathTracer, AreaLightOverFloorGivesPiLTimesTheFormFactorByNextEvents) {
  // The lamp as an area light of radiance L: H = pi L F on the floor, from one shadow ray a path.
  Scene scene;
  shadow::add_mesh(scene, "floor", {{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}});
  shadow::Light lamp;
  lamp.name = "lamp";
  lamp.type = shadow::LightType::Area;
  lamp.intensity = 3.0;
  lamp.polygon = {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}};
  scene.lights.push_back(lamp);
  shadow::validate_scene(scene);
  const shadow::PathTracerResult r = shadow::path_trace_faces(scene, options_of(100000));
  const shadow::IrradianceEstimate& floor = r.estimates[0];
  const double expected = kPi * 3.0 * kParallelSquares;
  EXPECT_GT(floor.standard_error, 0.0);
  EXPECT_NEAR(floor.irradiance, expected, 4 * floor.standard_error);
  EXPECT_LT(floor.standard_error, 0.01 * expected);
  EXPECT_EQ(floor.irradiance, floor.direct_irradiance);  // nothing else to see
}

TEST(PathTracer, AgreesWithRadiosityInARoomWithAnEmittingFloor) {
  // The closed 2 x 1 x 1.5 room, its floor emitting 10 W/m^2 (rho 0.3), the rest white (0.7):
  // no occluder, so radiosity's form factors are exact up to their quadrature, and its stated
  // error bounds the rest.
  Scene scene;
  shadow::Material lamp, white;
  lamp.name = "lamp";
  lamp.emittance = 10.0;
  lamp.reflectance = 0.3;
  white.name = "white";
  white.reflectance = 0.7;
  scene.materials = {lamp, white};
  std::vector<shadow::Polygon3> floor, walls;
  for (const shadow::Polygon3& f : shadow::room_faces({0, 0, 0}, {2, 1, 1.5}))
    (f[0].z == 0 && f[1].z == 0 && f[2].z == 0 ? floor : walls).push_back(f);
  ASSERT_EQ(floor.size(), 1u);
  shadow::add_mesh(scene, "floor", floor);
  shadow::add_mesh(scene, "walls", walls);
  scene.meshes[0].material = "lamp";
  scene.meshes[1].material = "white";
  shadow::validate_scene(scene);
  shadow::RadiosityOptions ro;
  ro.max_element_area = 0.25;
  ro.patch_area = 0.25;
  ro.tolerance = 1e-4;
  ro.threads = 2;
  const shadow::RadiosityResult rad = shadow::solve_radiosity(scene, ro);
  ASSERT_TRUE(rad.converged);
  const shadow::PathTracerResult pt = shadow::path_trace_faces(scene, options_of(20000));
  ASSERT_EQ(pt.estimates.size(), 6u);
  for (const shadow::IrradianceEstimate& est : pt.estimates) {
    const double h = rad.faces[est.face_id].irradiance;
    EXPECT_GT(h, 1.0);
    EXPECT_LT(est.standard_error, 0.02 * h);
    EXPECT_NEAR(est.irradiance, h, 4 * est.standard_error + rad.error_estimate * h) << "face " << est.face_id;
  }
}

TEST(PathTracer, DiskLightAndSunDiskByNextEvents) {
  // A black floor; a disk of radius R = 0.5 facing down at height h = 1 over the origin, radiance
  // 2: H = pi L R^2 / (h^2 + R^2) under its centre. The sun's disk (1 degree, 30 degrees from the
  // zenith, nothing in the way): H = I cos(30 degrees) on every ray, no variance.
  Scene scene;
  shadow::add_mesh(scene, "floor", {{{-5, -5, 0}, {5, -5, 0}, {5, 5, 0}, {-5, 5, 0}}});
  shadow::Light disk;
  disk.name = "disk";
  disk.type = shadow::LightType::Disk;
  disk.position = {0, 0, 1};
  disk.normal = {0, 0, -1};
  disk.radius = 0.5;
  disk.intensity = 2.0;
  scene.lights.push_back(disk);
  shadow::validate_scene(scene);
  const shadow::PathTracerResult r = shadow::path_trace_points(scene, {{0, {0, 0, 0}}}, options_of(100000));
  const double expected = kPi * 2.0 * 0.25 / 1.25;
  EXPECT_LT(r.estimates[0].standard_error, 0.01 * expected);
  EXPECT_NEAR(r.estimates[0].irradiance, expected, 4 * r.estimates[0].standard_error);

  Scene sunny;
  shadow::add_mesh(sunny, "floor", {{{-5, -5, 0}, {5, -5, 0}, {5, 5, 0}, {-5, 5, 0}}});
  shadow::Light sun = shadow::directional_light("sun", {std::sin(kPi / 6), 0, std::cos(kPi / 6)});
  sun.angular_diameter = 1.0;
  sun.intensity = 4.0;
  sunny.lights.push_back(sun);
  shadow::validate_scene(sunny);
  const shadow::PathTracerResult s = shadow::path_trace_faces(sunny, options_of(64));
  EXPECT_NEAR(s.estimates[0].irradiance, 4.0 * std::cos(kPi / 6), 1e-12);
  EXPECT_LT(s.estimates[0].standard_error, 1e-9);
}

TEST(PathTracer, HardLightsAtPointsAreExactAndShadowed) {
  // Floor z = 0 (face 0) with a black square [0.4, 1.6]^2 at height 1 (face 1, facing down); the
  // default material reflects nothing, so H is the lights' alone.
  Scene scene;
  shadow::add_mesh(scene, "floor", {{{-5, -5, 0}, {5, -5, 0}, {5, 5, 0}, {-5, 5, 0}}});
  shadow::add_mesh(scene, "blocker", {{{0.4, 0.4, 1}, {0.4, 1.6, 1}, {1.6, 1.6, 1}, {1.6, 0.4, 1}}});
  shadow::Light lamp = shadow::point_light("lamp", {0, 0, 2});
  lamp.intensity = 8.0;
  scene.lights.push_back(lamp);
  shadow::Light sun = shadow::directional_light("sun", {0, 0, 1});
  sun.intensity = 5.0;
  scene.lights.push_back(sun);
  shadow::validate_scene(scene);
  const std::vector<shadow::SurfacePoint> points = {{0, {0, 0, 0}}, {0, {3, 4, 0}}, {0, {1, 1, 0}}};
  const shadow::PathTracerResult r = shadow::path_trace_points(scene, points, options_of(16));
  ASSERT_EQ(r.estimates.size(), 3u);
  // Under the lamp: I / r^2 + sun; at (3, 4): I cos / r^2 = 8 * 2 / 29^1.5, + sun (the lamp's
  // ray passes z = 1 at (1.5, 2), beside the square); at (1, 1) the square hides both (the
  // lamp's ray passes z = 1 at (0.5, 0.5)).
  EXPECT_NEAR(r.estimates[0].irradiance, 8.0 / 4 + 5.0, 1e-9);
  EXPECT_NEAR(r.estimates[1].irradiance, 8.0 * 2 / std::pow(29.0, 1.5) + 5.0, 1e-9);
  EXPECT_EQ(r.estimates[0].standard_error, 0.0);
  EXPECT_EQ(r.estimates[2].irradiance, 0.0);
  EXPECT_EQ(r.estimates[2].area, 0.0);
}

TEST(PathTracer, DeterministicForASeedAndAnyThreadCount) {
  const Scene scene = furnace(10.0, 0.6);
  const shadow::PathTracerResult a = shadow::path_trace_faces(scene, options_of(300, 1));
  const shadow::PathTracerResult b = shadow::path_trace_faces(scene, options_of(300, 2));
  const shadow::PathTracerResult c = shadow::path_trace_faces(scene, options_of(300, 3));
  shadow::PathTracerOptions other = options_of(300, 2);
  other.seed = 33;
  const shadow::PathTracerResult d = shadow::path_trace_faces(scene, other);
  ASSERT_EQ(a.estimates.size(), b.estimates.size());
  bool differs = false;
  for (std::size_t i = 0; i < a.estimates.size(); ++i) {
    EXPECT_EQ(a.estimates[i].irradiance, b.estimates[i].irradiance);
    EXPECT_EQ(a.estimates[i].standard_error, b.estimates[i].standard_error);
    EXPECT_EQ(a.estimates[i].irradiance, c.estimates[i].irradiance);
    differs = differs || d.estimates[i].irradiance != a.estimates[i].irradiance;
  }
  EXPECT_EQ(a.rays, b.rays);
  EXPECT_TRUE(differs);  // another seed, other paths
}

TEST(PathTracer, SameResultOnAnyThreadCountInACityWhoseBvhIsBuiltInParallel) {
  // 2,000 boxes: 12,001 faces, enough for Embree to build its BVH on several threads.
  Scene scene = shadow::make_city(2000, 700, 2026);
  shadow::Material grey;
  grey.name = "grey";
  grey.reflectance = 0.5;
  scene.materials.push_back(grey);
  for (shadow::Mesh& m : scene.meshes) m.material = "grey";
  scene.lights.push_back(shadow::directional_light("sun", {1, 0.5, 1}));
  shadow::validate_scene(scene);
  const shadow::PathTracerResult a = shadow::path_trace_faces(scene, options_of(4, 1));
  const shadow::PathTracerResult b = shadow::path_trace_faces(scene, options_of(4, 2));
  ASSERT_EQ(a.estimates.size(), b.estimates.size());
  std::size_t same = 0;
  for (std::size_t i = 0; i < a.estimates.size(); ++i)
    same += a.estimates[i].irradiance == b.estimates[i].irradiance ? 1 : 0;
  EXPECT_EQ(same, a.estimates.size());
  EXPECT_EQ(a.rays, b.rays);
}

TEST(PathTracer, RejectsBadOptionsAndFaces) {
  const Scene scene = furnace(10.0, 0.6);
  shadow::PathTracerOptions o = options_of(0);
  EXPECT_THROW(shadow::path_trace_faces(scene, o), shadow::InputError);
  o.samples = 4;
  o.russian_roulette = false;  // and no limit: paths in a closed box would never end
  EXPECT_THROW(shadow::path_trace_faces(scene, o), shadow::InputError);
  EXPECT_THROW(shadow::path_trace_faces(scene, options_of(4), {6}), shadow::InputError);
  EXPECT_THROW(shadow::path_trace_points(scene, {{9, {0, 0, 0}}}, options_of(4)), shadow::InputError);
  EXPECT_THROW(shadow::path_trace_points(scene, {{0, {0, std::nan(""), 0}}}, options_of(4)), shadow::InputError);
}

}  // namespace
