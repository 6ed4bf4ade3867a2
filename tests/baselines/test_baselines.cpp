// SPDX-License-Identifier: GPL-3.0-or-later
// The sampled baselines (shadow mapping, Embree ray sampling) against closed-form answers and
// against the exact engine. Their errors must shrink with the resolution, within bounds tied to
// the grid spacing or texel size and the shadow's perimeter.
#include "support/scene_builders.hpp"

#include <shadow/baselines.hpp>
#include <shadow/shadow.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace shadow::test {
namespace {

/// Ground [-5, 5]^2 (face 0, area 100) under a 2 x 2 square at height 2 facing up (face 1) and
/// its back twin facing down (face 2).
Scene square_over_ground(const Light& light) {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "square", {rectangle_z(-1, -1, 1, 1, 2), rectangle_z(-1, -1, 1, 1, 2, false)});
  scene.lights.push_back(light);
  validate_scene(scene);
  return scene;
}

const FaceLighting& at(const BaselineResult& r, std::size_t face) {
  const FaceLighting* fl = r.find(face, 0);
  if (!fl) throw std::runtime_error("missing entry");
  return *fl;
}

TEST(RaySampling, SquareUnderSlantedSunConvergesWithinPerimeterTimesSpacing) {
  // Shadow: the 2 x 2 square shifted by -(1, 0.5) * 2: inside the ground, area 4. Lit 0.96.
  const Scene scene = square_over_ground(directional_light("sun", {1, 0.5, 1}));
  for (double h : {0.5, 0.1, 0.02}) {
    RaySamplingOptions options;
    options.spacing = h;
    options.threads = 2;
    const BaselineResult r = ray_sampling_lighting(scene, options);
    // Only cells cut by the shadow's boundary (perimeter 8) can be miscounted.
    EXPECT_NEAR(at(r, 0).lit_fraction, 0.96, 8 * h / 100 + 1e-12) << "h = " << h;
    EXPECT_EQ(at(r, 1).lit_fraction, 1.0);  // nothing above the square
    EXPECT_FALSE(at(r, 2).faces_light);     // back to the sun
    EXPECT_EQ(at(r, 2).lit_area, 0.0);
    EXPECT_DOUBLE_EQ(at(r, 0).area, 100.0);
  }
}

TEST(RaySampling, GeoreferencedCoordinatesKeepTheirAccuracyThroughRecentring) {
  // At 1e6 float32 has 6 cm steps; the baselines subtract the scene's centre in double first.
  Scene scene = square_over_ground(directional_light("sun", {1, 0.5, 1}));
  for (Face& f : scene.faces)
    for (glm::dvec3& v : f.vertices) v += glm::dvec3(1e6, -2e6, 0);
  RaySamplingOptions options;
  options.spacing = 0.02;
  options.threads = 2;
  EXPECT_NEAR(at(ray_sampling_lighting(scene, options), 0).lit_fraction, 0.96, 8 * 0.02 / 100);
  ShadowMapOptions map;
  map.resolution = 1024;
  map.threads = 2;
  EXPECT_NEAR(at(shadow_map_lighting(scene, map), 0).lit_fraction, 0.96, 8 * 3 * 10 * std::sqrt(2.0) / 1024 / 100);
}

TEST(RaySampling, PointLightShadowIsTheSquareScaledFromTheLight) {
  // Lamp at height 4 over a square at height 2: shadow twice as wide, area 16. Lit 0.84.
  const Scene scene = square_over_ground(point_light("lamp", {0.1, 0.2, 4}));
  RaySamplingOptions options;
  options.spacing = 0.02;
  options.threads = 2;
  const BaselineResult r = ray_sampling_lighting(scene, options);
  EXPECT_NEAR(at(r, 0).lit_fraction, 0.84, 16 * 0.02 / 100);
  EXPECT_EQ(at(r, 1).lit_fraction, 1.0);
  EXPECT_FALSE(at(r, 2).faces_light);
}

// An extended light stands for its centre in the hard baselines, as FaceLighting::lit_area of
// the exact engine (docs/area-lights.md): an area light centred at the lamp of the test above
// gives the lamp's results; before, it was taken as a directional light overhead (to_light's
// default) and gave 0.96.
TEST(RaySampling, AnAreaLightIsSampledFromItsCentre) {
  Light area;
  area.name = "panel";
  area.type = LightType::Area;
  area.polygon = {{-0.15, -0.05, 4}, {-0.15, 0.45, 4}, {0.35, 0.45, 4}, {0.35, -0.05, 4}};  // centroid (0.1, 0.2, 4)
  const Scene panel = square_over_ground(area);
  const Scene lamp = square_over_ground(point_light("lamp", centre_light(area).position));
  RaySamplingOptions options;
  options.spacing = 0.02;
  options.threads = 2;
  ShadowMapOptions map;
  map.resolution = 512;
  map.threads = 2;
  EXPECT_EQ(at(ray_sampling_lighting(panel, options), 0).lit_area, at(ray_sampling_lighting(lamp, options), 0).lit_area);
  EXPECT_NEAR(at(ray_sampling_lighting(panel, options), 0).lit_fraction, 0.84, 16 * 0.02 / 100);
  EXPECT_EQ(at(shadow_map_lighting(panel, map), 0).lit_area, at(shadow_map_lighting(lamp, map), 0).lit_area);
  // A sun disk: its central direction.
  Light sun = directional_light("sun", {1, 0.5, 1});
  const Scene point_sun = square_over_ground(sun);
  sun.angular_diameter = 0.53;
  const Scene disk_sun = square_over_ground(sun);
  EXPECT_EQ(at(ray_sampling_lighting(disk_sun, options), 0).lit_area,
            at(ray_sampling_lighting(point_sun, options), 0).lit_area);
}

TEST(ShadowMap, SquareUnderSlantedSunConvergesWithinPerimeterTimesTexel) {
  const Scene scene = square_over_ground(directional_light("sun", {1, 0.5, 1}));
  double previous = 1;
  for (int resolution : {64, 256, 1024}) {
    ShadowMapOptions options;
    options.resolution = resolution;
    options.threads = 2;
    const BaselineResult r = shadow_map_lighting(scene, options);
    // The window spans at most the ground's 10 m diagonal across the light: texel <= 10 * sqrt 2 / R.
    // A boundary is off by up to a texel from the depth lookup and a sample cell from counting.
    const double texel = 10 * std::sqrt(2.0) / resolution;
    const double error = std::abs(at(r, 0).lit_fraction - 0.96);
    EXPECT_LE(error, 8 * 3 * texel / 100) << "R = " << resolution;
    EXPECT_LE(error, previous + 1e-12);
    previous = error;
    EXPECT_EQ(at(r, 1).lit_fraction, 1.0) << "shadow acne on the square's top, R = " << resolution;
    EXPECT_FALSE(at(r, 2).faces_light);
  }
}

TEST(ShadowMap, PointLightCubeMapConverges) {
  const Scene scene = square_over_ground(point_light("lamp", {0.1, 0.2, 4}));
  for (int resolution : {128, 512}) {
    ShadowMapOptions options;
    options.resolution = resolution;
    options.threads = 2;
    const BaselineResult r = shadow_map_lighting(scene, options);
    // Texel footprint on the ground (4 m below): up to 4 * 2 / R; shadow perimeter 16.
    const double texel = 8.0 / resolution;
    EXPECT_NEAR(at(r, 0).lit_fraction, 0.84, 16 * 3 * texel / 100) << "R = " << resolution;
    EXPECT_EQ(at(r, 1).lit_fraction, 1.0);
  }
}

TEST(ShadowMap, WithoutBiasALitFaceShadowsItself) {
  // The acne that bias exists for: a tilted roof with nothing above it, no bias at all.
  Scene scene;
  add_mesh(scene, "roof", {{{0, 0, 0}, {10, 0, 0}, {10, 10, 3}, {0, 10, 3}}});
  scene.lights.push_back(directional_light("sun", sun_direction(30, 200)));
  validate_scene(scene);
  ShadowMapOptions options;
  options.resolution = 256;
  options.threads = 1;
  options.constant_bias = 0;
  options.slope_bias = 0;
  const double no_bias = shadow_map_lighting(scene, options).lighting[0].lit_fraction;
  options.constant_bias = 1e-3;
  options.slope_bias = 1.0;
  const double biased = shadow_map_lighting(scene, options).lighting[0].lit_fraction;
  EXPECT_LT(no_bias, 0.9);
  EXPECT_EQ(biased, 1.0);
}

TEST(Baselines, AgreeWithTheExactEngineOnRandomScenes) {
  for (std::uint64_t seed : {3u, 17u, 42u}) {
    Scene scene = random_scene(seed);
    validate_scene(scene);
    ShadowOptions exact_options;
    exact_options.threads = 2;
    exact_options.polygons = false;
    const ShadowResult exact = compute_shadows(scene, exact_options);
    RaySamplingOptions ray_options;
    ray_options.spacing = 0.05;
    ray_options.threads = 2;
    ShadowMapOptions map_options;
    map_options.resolution = 1024;
    map_options.threads = 2;
    map_options.max_samples_per_face = 1u << 22;  // keeps the test fast
    const BaselineResult rays = ray_sampling_lighting(scene, ray_options);
    const BaselineResult map = shadow_map_lighting(scene, map_options);
    ASSERT_EQ(rays.lighting.size(), exact.lighting.size());
    ASSERT_EQ(map.lighting.size(), exact.lighting.size());
    double exact_lit = 0, ray_lit = 0, map_lit = 0;
    for (std::size_t e = 0; e < exact.lighting.size(); ++e) {
      const FaceLighting& x = exact.lighting[e];
      EXPECT_EQ(rays.lighting[e].face_id, x.face_id);
      EXPECT_EQ(rays.lighting[e].faces_light, x.faces_light) << "seed " << seed << " face " << x.face_id;
      EXPECT_EQ(map.lighting[e].faces_light, x.faces_light) << "seed " << seed << " face " << x.face_id;
      exact_lit += x.lit_area;
      ray_lit += rays.lighting[e].lit_area;
      map_lit += map.lighting[e].lit_area;
    }
    // Totals: the boundary errors of many faces largely cancel.
    EXPECT_NEAR(ray_lit / exact_lit, 1.0, 0.01) << "seed " << seed;
    EXPECT_NEAR(map_lit / exact_lit, 1.0, 0.02) << "seed " << seed;
  }
}

TEST(SphereField, OneSphereUnderOverheadSunCastsItsEquatorialTwelveGon) {
  // Ground (20 + 10 + 10)^2 = 1600; the UV sphere's widest section is its equator, a regular
  // 12-gon of radius r and area 3 r^2; the sphere touches the ground at its south pole.
  Scene scene = make_sphere_field(1, 20, 5);
  ASSERT_EQ(scene.faces.size(), 1u + 120u);
  scene.lights.push_back(directional_light("sun", {0, 0, 1}));
  validate_scene(scene);
  double top = 0;
  for (const Face& f : scene.faces)
    for (const glm::dvec3& v : f.vertices) top = std::max(top, v.z);
  const double r = top / 2, expected = 1 - 3 * r * r / 1600;
  ShadowOptions options;
  options.threads = 2;
  options.polygons = false;
  EXPECT_NEAR(compute_shadows(scene, options).find(0, 0)->lit_fraction, expected, 1e-12);
  RaySamplingOptions rays;
  rays.spacing = 0.05;
  rays.threads = 2;
  // The 12-gon's perimeter is below 2 pi r.
  EXPECT_NEAR(ray_sampling_lighting(scene, rays).find(0, 0)->lit_fraction, expected, 2 * M_PI * r * 0.05 / 1600);
}

TEST(Baselines, RejectUnusableOptions) {
  const Scene scene = square_over_ground(directional_light("sun", {0, 0, 1}));
  RaySamplingOptions rays;
  rays.spacing = 0;
  EXPECT_THROW(ray_sampling_lighting(scene, rays), InputError);
  ShadowMapOptions map;
  map.resolution = 0;
  EXPECT_THROW(shadow_map_lighting(scene, map), InputError);
  map.resolution = 64;
  map.lights = {3};
  EXPECT_THROW(shadow_map_lighting(scene, map), InputError);
  Scene zero = scene;
  zero.lights[0].to_light = {0, 0, 0};
  EXPECT_THROW(ray_sampling_lighting(zero, RaySamplingOptions{}), InputError);
}

}  // namespace
}  // namespace shadow::test
