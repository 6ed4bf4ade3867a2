// SPDX-License-Identifier: GPL-3.0-or-later
// Radiosity (issue 32): form factors against Howell's catalogue, reciprocity, closed boxes, an
// occluder against Monte Carlo with exact ray tests; the solver's furnace test and energy balance.
#include "support/scene_builders.hpp"

#include <shadow/generators.hpp>
#include <shadow/radiosity.hpp>
#include <shadow/scene.hpp>
#include <shadow/scene_io.hpp>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <vector>

namespace {

using glm::dvec3;
using shadow::Scene;
using shadow::SurfacePoint;
using Polygon3 = std::vector<dvec3>;

constexpr double kPi = 3.14159265358979323846;

Scene scene_of(const std::vector<Polygon3>& faces) {
  Scene scene;
  shadow::add_mesh(scene, "faces", faces);
  shadow::validate_scene(scene);
  return scene;
}

const Polygon3 kFloor = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};    // front +z
const Polygon3 kCeiling = {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}};  // front -z
const Polygon3 kWall = {{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}};     // front +x

/// Howell's C-11: from a differential area to a parallel rectangle a x b at distance c with a
/// corner above it.
double corner_rectangle(double a, double b, double c) {
  const double x = a / c, y = b / c;
  const double sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
  return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2 * kPi);
}

/// Howell's C-11 (two parallel, directly opposed rectangles a x b at distance c), exact.
double parallel_rectangles(double a, double b, double c) {
  const double x = a / c, y = b / c;
  const double x1 = std::sqrt(1 + x * x), y1 = std::sqrt(1 + y * y);
  return 2 / (kPi * x * y) *
         (std::log(std::sqrt((1 + x * x) * (1 + y * y) / (1 + x * x + y * y))) + x * y1 * std::atan(x / y1) +
          y * x1 * std::atan(y / x1) - x * std::atan(x) - y * std::atan(y));
}

TEST(FormFactor, PointToParallelSquareMatchesTheAnalyticValue) {
  const Scene scene = scene_of({kFloor, kCeiling});
  const std::vector<SurfacePoint> points = {{0, {0.5, 0.5, 0}}, {0, {0, 0, 0}}, {0, {0.25, 0.5, 0}}};
  const std::vector<double> f = shadow::point_form_factors(scene, 1, points, 1);
  EXPECT_NEAR(f[0], 4 * corner_rectangle(0.5, 0.5, 1), 1e-12);
  EXPECT_NEAR(f[1], corner_rectangle(1, 1, 1), 1e-12);
  EXPECT_NEAR(f[2], 2 * corner_rectangle(0.25, 0.5, 1) + 2 * corner_rectangle(0.75, 0.5, 1), 1e-12);
}

TEST(FormFactor, ParallelOpposedUnitSquaresHowell) {
  const Scene scene = scene_of({kFloor, kCeiling});
  const shadow::FormFactor f = shadow::form_factor(scene, 0, 1, {1e-6, 32, 1});
  EXPECT_NEAR(parallel_rectangles(1, 1, 1), 0.19982, 5e-6);
  EXPECT_NEAR(f.value, parallel_rectangles(1, 1, 1), std::max(1e-6, 2 * f.error));
  EXPECT_NEAR(f.value, 0.19982, 1e-5);
  EXPECT_LE(f.error, 1e-6);
}

TEST(FormFactor, PerpendicularSquaresSharingAnEdgeHowell) {
  const Scene scene = scene_of({kFloor, kWall});
  const shadow::FormFactor f = shadow::form_factor(scene, 0, 1, {1e-5, 64, 1});
  // Howell C-14 with unit sides: 0.20004 (0.2000438).
  EXPECT_NEAR(f.value, 0.2000438, std::max(2e-5, 2 * f.error));
  EXPECT_LT(f.error, 1e-4);
  const shadow::FormFactor back = shadow::form_factor(scene, 1, 0, {1e-5, 64, 1});
  EXPECT_NEAR(back.value, 0.2000438, std::max(2e-5, 2 * back.error));
}

TEST(FormFactor, ReciprocityOfUnequalFaces) {
  // A unit square on the floor and a tilted 2 x 0.5 rectangle above it, facing down-ish.
  const Polygon3 tilted = {{-0.5, 0.2, 1.2}, {-0.5, 0.7, 1.6}, {1.5, 0.7, 1.6}, {1.5, 0.2, 1.2}};
  const Scene scene = scene_of({kFloor, tilted});
  const double a0 = 1.0, a1 = 2.0 * std::sqrt(0.5 * 0.5 + 0.4 * 0.4);
  const shadow::FormFactor f01 = shadow::form_factor(scene, 0, 1, {1e-7, 64, 1});
  const shadow::FormFactor f10 = shadow::form_factor(scene, 1, 0, {1e-7, 64, 1});
  EXPECT_GT(f01.value, 0.05);
  EXPECT_NEAR(a0 * f01.value, a1 * f10.value, 1e-6 * a0 * f01.value + 2 * (a0 * f01.error + a1 * f10.error));
}

TEST(FormFactor, AClosedBoxSumsToOneFromEveryFace) {
  const Scene scene = scene_of(shadow::room_faces({0, 0, 0}, {2, 1, 1.5}));
  for (std::size_t i = 0; i < scene.faces.size(); ++i) {
    double sum = 0, error = 0;
    for (std::size_t j = 0; j < scene.faces.size(); ++j) {
      const shadow::FormFactor f = shadow::form_factor(scene, i, j, {1e-5, 64, 1});
      sum += f.value;
      error += f.error;
    }
    EXPECT_NEAR(sum, 1.0, std::max(1e-4, 2 * error)) << "face " << i;
  }
}

// ---- Monte Carlo with exact ray tests ------------------------------------------------------

/// The first face (other than `from`) that the ray x + t d (t > 0) meets, or -1: each face is
/// convex here, the test exact enough for points that are not on an edge (measure zero).
int first_hit(const Scene& scene, std::size_t from, const dvec3& x, const dvec3& d) {
  int best = -1;
  double best_t = 1e300;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    if (f == from) continue;
    const Polygon3& p = scene.faces[f].vertices;
    const dvec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
    const double den = glm::dot(n, d);
    if (den == 0) continue;
    const double t = glm::dot(n, p[0] - x) / den;
    if (!(t > 0) || t >= best_t) continue;
    const dvec3 y = x + t * d;
    bool inside = true;
    for (std::size_t a = 0; a < p.size() && inside; ++a)
      inside = glm::dot(glm::cross(p[(a + 1) % p.size()] - p[a], y - p[a]), n) >= 0;
    if (inside) best = static_cast<int>(f), best_t = t;
  }
  return best;
}

TEST(FormFactor, AnOccluderBetweenTwoSquaresAgreesWithMonteCarlo) {
  // A square plate, both sides hiding, half-way between the floor and the ceiling, off centre.
  const Polygon3 plate = {{0.2, 0.3, 0.5}, {0.7, 0.3, 0.5}, {0.7, 0.9, 0.5}, {0.2, 0.9, 0.5}};
  const Scene scene = scene_of({kFloor, kCeiling, plate});
  const shadow::FormFactor f = shadow::form_factor(scene, 0, 1, {1e-4, 32, 1});
  EXPECT_LT(f.value, 0.19982 - 0.03);  // the plate hides a good part

  std::mt19937_64 rng(32);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int samples = 200000;
  int hits = 0;
  for (int s = 0; s < samples; ++s) {
    const dvec3 x(u(rng), u(rng), 0.0);
    // Cosine-weighted direction about +z.
    const double r = std::sqrt(u(rng)), phi = 2 * kPi * u(rng);
    const dvec3 d(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0, 1 - r * r)));
    hits += first_hit(scene, 0, x, d) == 1 ? 1 : 0;
  }
  const double p = static_cast<double>(hits) / samples;
  const double sigma = std::sqrt(p * (1 - p) / samples);
  EXPECT_NEAR(f.value, p, 4 * sigma + f.error) << "Monte Carlo " << p << " +- " << sigma;
}

TEST(FormFactor, BadFacesAreInputErrors) {
  const Scene scene = scene_of({kFloor, kCeiling});
  EXPECT_THROW(shadow::form_factor(scene, 0, 2), shadow::InputError);
  EXPECT_THROW(shadow::form_factor(scene, 5, 1), shadow::InputError);
  EXPECT_EQ(shadow::form_factor(scene, 0, 0).value, 0.0);
}

// ---- the solver ------------------------------------------------------------------------------

/// A closed room whose inner faces all emit `e` and reflect `rho`.
Scene furnace(double e, double rho) { return shadow::test::furnace_room(e, rho); }

TEST(Radiosity, FurnaceIsEOverOneMinusRhoEverywhereForTwoMeshings) {
  const double e = 10.0, rho = 0.6;
  for (const double max_area : {0.5, 0.1}) {
    shadow::RadiosityOptions options;
    options.max_element_area = max_area;
    options.patch_area = max_area == 0.1 ? 0.1 : 0.0;  // patches = elements, or 16 elements each
    options.tolerance = 1e-4;
    options.threads = 2;
    const shadow::RadiosityResult r = shadow::solve_radiosity(furnace(e, rho), options);
    ASSERT_TRUE(r.converged);
    EXPECT_LE(r.unshot_fraction, 1e-4);
    // The stated error: the unshot share amplified by the reflections to come, and the form
    // factors' quadrature (their sums from each element are 1 only up to it).
    const double expected = e / (1 - rho);
    double worst = 0;
    for (const shadow::RadiosityElement& el : r.elements) worst = std::max(worst, std::abs(el.radiosity - expected) / expected);
    // Measured: 7e-6 and 4e-5 (docs/radiosity.md); the estimate is conservative (about 1%).
    EXPECT_LE(worst, 1e-3) << "max area " << max_area;
    EXPECT_LE(worst, r.error_estimate) << "max area " << max_area;
    EXPECT_LE(r.balance_residual, 1e-9);
    // A closed room loses nothing but the quadrature error.
    EXPECT_LE(std::abs(r.escaped_power), 1e-3 * (r.emitted_power + r.direct_power));
    for (const shadow::FaceRadiosity& f : r.faces) EXPECT_NEAR(f.radiosity, expected, 1e-3 * expected);
    std::cout << "furnace max area " << max_area << ": " << r.elements.size() << " elements, " << r.shots
              << " shots, worst " << worst << ", error estimate " << r.error_estimate << "\n";
  }
}

TEST(Radiosity, DirectSunAndOneBounceBalance) {
  // A floor lit by the sun, a wall beside it: the wall gets the floor's reflected light.
  Scene scene;
  shadow::Material ground, wall;
  ground.name = "ground";
  ground.reflectance = 0.2;
  wall.name = "wall";
  wall.reflectance = 0.3;
  scene.materials = {ground, wall};
  shadow::add_mesh(scene, "ground", {shadow::rectangle_z(-5, -5, 5, 5, 0)});
  shadow::add_mesh(scene, "box", shadow::box_faces({-1, -1, 0}, {1, 1, 2}));
  scene.meshes[0].material = "ground";
  scene.meshes[1].material = "wall";
  shadow::Light sun;
  sun.name = "sun";
  sun.type = shadow::LightType::Directional;
  sun.to_light = {0.3, -0.5, 1};
  sun.intensity = 800;
  scene.lights.push_back(sun);
  shadow::validate_scene(scene);
  shadow::RadiosityOptions options;
  options.max_element_area = 2.0;
  options.tolerance = 1e-4;
  options.threads = 2;
  const shadow::RadiosityResult r = shadow::solve_radiosity(scene, options);
  EXPECT_TRUE(r.converged);
  EXPECT_LE(r.balance_residual, 1e-9);
  // The ground's direct irradiance on its lit part is I cos(theta); the shadow removes some.
  const double cos_theta = 1 / glm::length(sun.to_light);
  EXPECT_LT(r.faces[0].direct_irradiance, 800 * cos_theta);
  EXPECT_GT(r.faces[0].direct_irradiance, 0.9 * 800 * cos_theta);
  // The north wall (+y, facing away from the sun) gets no direct light but reflected light.
  const shadow::FaceRadiosity& north = r.faces[1 + 3];
  EXPECT_EQ(north.direct_irradiance, 0.0);
  EXPECT_GT(north.irradiance, 0.0);
  EXPECT_NEAR(north.radiosity, 0.3 * north.irradiance, 1e-9 * north.irradiance);
  // An open scene: most reflected light escapes; what stays is absorbed.
  EXPECT_GT(r.escaped_power, 0.0);
  EXPECT_NEAR(r.emitted_power + r.direct_power, r.absorbed_power + r.escaped_power + r.unshot_power,
              1e-9 * r.direct_power);
}

TEST(Radiosity, DirectIrradianceByLightAddsUpAndMatchesEachLightAlone) {
  Scene scene;
  shadow::Material grey;
  grey.name = "grey";
  grey.reflectance = 0.3;
  scene.materials = {grey};
  shadow::add_mesh(scene, "ground", {shadow::rectangle_z(-5, -5, 5, 5, 0)});
  shadow::add_mesh(scene, "box", shadow::box_faces({-1, -1, 0}, {1, 1, 2}));
  scene.meshes[0].material = scene.meshes[1].material = "grey";
  scene.lights = {shadow::directional_light("sun", {0.3, -0.5, 1}), shadow::directional_light("west", {-1, 0.2, 0.6})};
  scene.lights[0].intensity = 800;
  scene.lights[1].intensity = 300;
  shadow::validate_scene(scene);
  shadow::RadiosityOptions options;
  options.max_element_area = 1.0;
  options.tolerance = 1e-3;
  options.threads = 2;
  const shadow::RadiosityResult both = shadow::solve_radiosity(scene, options);
  Scene sun_only = scene, west_only = scene;
  sun_only.lights.pop_back();
  west_only.lights.erase(west_only.lights.begin());
  const shadow::RadiosityResult sun = shadow::solve_radiosity(sun_only, options);
  const shadow::RadiosityResult west = shadow::solve_radiosity(west_only, options);
  // The west light alone on the elements of `both` (cut along the sun's shadows): the sun kept
  // first, dark.
  Scene dark_sun = scene;
  dark_sun.lights[0].intensity = 0;
  const shadow::RadiosityResult west_same_mesh = shadow::solve_radiosity(dark_sun, options);
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const shadow::FaceRadiosity& face = both.faces[f];
    ASSERT_EQ(face.direct_irradiance_by_light.size(), 2u);
    EXPECT_NEAR(face.direct_irradiance_by_light[0] + face.direct_irradiance_by_light[1], face.direct_irradiance,
                1e-12 * (1 + face.direct_irradiance));
    // The first light's fragments make the elements in both runs: its share is the same.
    EXPECT_NEAR(face.direct_irradiance_by_light[0], sun.faces[f].direct_irradiance, 1e-9 * (1 + face.direct_irradiance));
    // The second light's shadow boundaries cut the elements too: its share is what it gives alone.
    EXPECT_NEAR(face.direct_irradiance_by_light[1], west.faces[f].direct_irradiance,
                1e-9 * west.faces[f].direct_irradiance + 1e-9)
        << f;
    // Each light's share of all the irradiance, reflected light included: they add up to it (each
    // solution stops with up to 1e-3 of its power unshot), and the first light's is what the sun
    // alone gives on the same elements.
    ASSERT_EQ(face.irradiance_by_light.size(), 2u);
    const double reflected = face.irradiance - face.direct_irradiance;
    EXPECT_NEAR(face.irradiance_by_light[0] + face.irradiance_by_light[1], face.irradiance, 0.01 * reflected + 1e-9) << f;
    EXPECT_NEAR(face.irradiance_by_light[0], sun.faces[f].irradiance, 0.01 * reflected + 1e-9) << f;
    EXPECT_NEAR(face.irradiance_by_light[1], west_same_mesh.faces[f].irradiance, 0.01 * reflected + 1e-9) << f;
    // and what it gives alone on its own elements: the wall east of the box sees the ground in the
    // box's shadow from the west light (before the patches were cut along that shadow, the lit
    // ground's light was shot from the shadowed part too: 12.6 W/m^2 against 6.1).
    EXPECT_NEAR(face.irradiance_by_light[1], west.faces[f].irradiance, 0.02 * west.faces[f].irradiance + 0.05) << f;
    EXPECT_GE(face.irradiance_by_light[1], face.direct_irradiance_by_light[1]);
    // One light alone: its share is all of it, without another solution.
    ASSERT_EQ(sun.faces[f].irradiance_by_light.size(), 1u);
    EXPECT_EQ(sun.faces[f].irradiance_by_light[0], sun.faces[f].irradiance);
  }
  EXPECT_GT(both.faces[0].direct_irradiance_by_light[1], 0.0);
  // The walls get reflected light of the west light from the ground.
  EXPECT_GT(both.faces[3].irradiance_by_light[1], both.faces[3].direct_irradiance_by_light[1]);
  options.per_light = false;
  EXPECT_TRUE(shadow::solve_radiosity(scene, options).faces[0].irradiance_by_light.empty());
}

TEST(Radiosity, ColourFurnaceIsEOverOneMinusRhoPerChannel) {
  // Each channel is its own furnace: B_c = E / (1 - rho_c); the scalar solution uses the mean.
  Scene scene = furnace(10.0, 0.6);
  scene.materials[0].reflectance_rgb = {0.3, 0.6, 0.9};
  shadow::RadiosityOptions options;
  options.max_element_area = 0.5;
  options.tolerance = 1e-5;
  options.threads = 2;
  const shadow::RadiosityResult r = shadow::solve_radiosity(scene, options);
  ASSERT_TRUE(r.colour);
  EXPECT_LE(r.channel_unshot_fraction, 1e-5);
  for (const shadow::FaceRadiosity& f : r.faces) {
    EXPECT_NEAR(f.radiosity, 25.0, 1e-3 * 25.0);
    EXPECT_NEAR(f.radiosity_rgb.x, 10.0 / 0.7, 1e-3 * 10.0 / 0.7);
    EXPECT_NEAR(f.radiosity_rgb.y, 25.0, 1e-3 * 25.0);
    EXPECT_NEAR(f.radiosity_rgb.z, 100.0, 2e-3 * 100.0);  // rho 0.9 amplifies the quadrature error
  }
  // Without colour the channels are the scalar solution.
  const shadow::RadiosityResult grey = shadow::solve_radiosity(furnace(10.0, 0.6), options);
  EXPECT_FALSE(grey.colour);
  for (const shadow::RadiosityElement& e : grey.elements) EXPECT_EQ(e.radiosity_rgb, dvec3(e.radiosity));
}

TEST(Radiosity, ColourBleedsFromARedWall) {
  // A white floor beside a red wall under a sun: the floor near the wall is redder than green.
  Scene scene;
  shadow::Material white, red;
  white.name = "white";
  white.reflectance = 0.7;
  white.reflectance_rgb = {0.7, 0.7, 0.7};
  red.name = "red";
  red.reflectance_rgb = {0.8, 0.1, 0.1};
  red.reflectance = (0.8 + 0.1 + 0.1) / 3;
  scene.materials = {white, red};
  shadow::add_mesh(scene, "floor", {shadow::rectangle_z(0, 0, 4, 4, 0)});
  shadow::add_mesh(scene, "wall", {{{0, 0, 0}, {0, 4, 0}, {0, 4, 3}, {0, 0, 3}}});  // front +x
  scene.meshes[0].material = "white";
  scene.meshes[1].material = "red";
  shadow::Light sun;
  sun.name = "sun";
  sun.type = shadow::LightType::Directional;
  sun.to_light = {1, 0.2, 1};  // on the wall and the floor
  sun.intensity = 500;
  scene.lights.push_back(sun);
  shadow::validate_scene(scene);
  shadow::RadiosityOptions options;
  options.max_element_area = 0.5;
  options.tolerance = 1e-4;
  options.threads = 2;
  const shadow::RadiosityResult r = shadow::solve_radiosity(scene, options);
  ASSERT_TRUE(r.colour);
  const shadow::FaceRadiosity& floor = r.faces[0];
  EXPECT_GT(floor.irradiance_rgb.x, floor.irradiance_rgb.y);
  EXPECT_DOUBLE_EQ(floor.irradiance_rgb.y, floor.irradiance_rgb.z);
  // The red channel's floor irradiance exceeds the green one by what the wall reflects more.
  EXPECT_GT(floor.irradiance_rgb.x - floor.irradiance_rgb.y, 1.0);
}

TEST(Radiosity, FaceIrradianceFromOutsideIsLinear) {
  // A closed room whose faces receive H0 from outside and reflect rho: H = H0 / (1 - rho).
  Scene scene = furnace(0.0, 0.5);
  shadow::RadiosityOptions options;
  options.max_element_area = 0.5;
  options.tolerance = 1e-5;
  options.threads = 2;
  options.face_irradiance.assign(scene.faces.size(), 100.0);
  const shadow::RadiosityResult r = shadow::solve_radiosity(scene, options);
  for (const shadow::FaceRadiosity& f : r.faces) {
    EXPECT_DOUBLE_EQ(f.direct_irradiance, 100.0);
    EXPECT_NEAR(f.irradiance, 200.0, 1e-3 * 200.0);
  }
  // Twice the source, twice the answer (the same shots in the same order).
  for (double& h : options.face_irradiance) h *= 2;
  const shadow::RadiosityResult twice = shadow::solve_radiosity(scene, options);
  for (std::size_t f = 0; f < r.faces.size(); ++f)
    EXPECT_NEAR(twice.faces[f].irradiance, 2 * r.faces[f].irradiance, 1e-12 * r.faces[f].irradiance);
  options.face_irradiance.pop_back();
  EXPECT_THROW(shadow::solve_radiosity(scene, options), shadow::InputError);
}

TEST(Radiosity, FloorElementsStopAtTheWallsOfABoxStandingOnIt) {
  // No floor element may reach under the box: it would average the room's light with the dark
  // beneath and shoot into the box.
  Scene scene;
  shadow::Material grey;
  grey.name = "grey";
  grey.reflectance = 0.5;
  grey.emittance = 1.0;
  scene.materials.push_back(grey);
  shadow::add_mesh(scene, "floor", {shadow::rectangle_z(0, 0, 4, 4, 0)});
  shadow::add_mesh(scene, "box", shadow::box_faces({1.3, 1.1, 0}, {2.2, 2.9, 1}));
  scene.meshes[0].material = scene.meshes[1].material = "grey";
  shadow::validate_scene(scene);
  shadow::RadiosityOptions options;
  options.max_element_area = 1.0;
  options.tolerance = 1e-2;
  options.threads = 1;
  const shadow::RadiosityResult r = shadow::solve_radiosity(scene, options);
  std::size_t under = 0;
  for (const shadow::RadiosityElement& e : r.elements) {
    if (e.face_id != 0) continue;
    int inside = 0, outside = 0;
    for (const dvec3& v : e.polygon) {
      const bool in = v.x > 1.3 + 1e-9 && v.x < 2.2 - 1e-9 && v.y > 1.1 + 1e-9 && v.y < 2.9 - 1e-9;
      const bool out = v.x < 1.3 - 1e-9 || v.x > 2.2 + 1e-9 || v.y < 1.1 - 1e-9 || v.y > 2.9 + 1e-9;
      inside += in ? 1 : 0;
      outside += out ? 1 : 0;
    }
    EXPECT_FALSE(inside > 0 && outside > 0) << "a floor element straddles the box's wall";
    const dvec3 c = (e.polygon[0] + e.polygon[1] + e.polygon[2]) / 3.0;
    under += c.x > 1.3 && c.x < 2.2 && c.y > 1.1 && c.y < 2.9 ? 1 : 0;
  }
  EXPECT_GT(under, 0u);
}

TEST(Radiosity, BadOptionsAreInputErrors) {
  const Scene scene = furnace(1, 0.5);
  shadow::RadiosityOptions options;
  options.tolerance = 0;
  EXPECT_THROW(shadow::solve_radiosity(scene, options), shadow::InputError);
  options.tolerance = 1e-3;
  options.max_element_area = -1;
  EXPECT_THROW(shadow::solve_radiosity(scene, options), shadow::InputError);
  // An element area that would make billions of elements is refused before any is made (it ran
  // the process out of memory, killed by the system with no word).
  options.max_element_area = 1e-12;
  try {
    shadow::solve_radiosity(scene, options);
    ADD_FAILURE() << "no error";
  } catch (const shadow::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("max_element_area: 1e-12 m^2 would cut the scene's"), std::string::npos) << e.what();
  }
}

}  // namespace
