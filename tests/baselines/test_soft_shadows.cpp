// SPDX-License-Identifier: GPL-3.0-or-later
// The soft-shadow baselines (baselines.hpp: PCF, PCSS, k rays per point) against visible
// fractions known in closed form, and against each other.
#include "support/scene_builders.hpp"

#include <shadow/area_lights.hpp>
#include <shadow/baselines.hpp>
#include <shadow/shadow.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace shadow::test {
namespace {

/// A square area light of side `side` centred at (0, 0, height), shining down.
Light square_light(double side, double height) {
  Light l;
  l.name = "panel";
  l.type = LightType::Area;
  const double h = 0.5 * side;
  // Clockwise seen from above: the front (counter-clockwise side) faces down.
  l.polygon = {{-h, -h, height}, {-h, h, height}, {h, h, height}, {h, -h, height}};
  return l;
}

Light disk_light(double radius, double height) {
  Light l;
  l.name = "disk";
  l.type = LightType::Disk;
  l.position = {0, 0, height};
  l.normal = {0, 0, -1};
  l.radius = radius;
  return l;
}

Light sun_disk(glm::dvec3 to_light, double degrees = 0.53) {
  Light l = directional_light("sun", to_light);
  l.angular_diameter = degrees;
  return l;
}

/// Ground [-10, 10]^2 (face 0), and with `edge` an occluder at height 2 covering x < 0 over the
/// ground's width (faces 1 and 2: front up and front down).
Scene ground_scene(bool edge) {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-10, -10, 10, 10, 0)});
  if (edge) add_mesh(scene, "occluder", {rectangle_z(-30, -30, 0, 30, 2), rectangle_z(-30, -30, 0, 30, 2, false)}, false);
  validate_scene(scene);
  return scene;
}

SoftRayOptions rays(unsigned k, unsigned threads = 2) {
  SoftRayOptions o;
  o.rays = k;
  o.threads = threads;
  o.seed = 7;
  return o;
}

TEST(SoftRays, HalfCoveredLightConvergesToOneHalf) {
  // From the origin, the occluder's edge (x = 0 at height 2) splits each light below its middle:
  // a light symmetric about x = 0 is exactly half hidden.
  const Scene scene = ground_scene(true);
  const std::vector<SurfacePoint> origin{{0, {0, 0, 0}}};
  for (const Light& light : {square_light(2, 4), disk_light(1, 4), sun_disk({0, 0, 1}, 2.0)}) {
    for (unsigned k : {16u, 256u, 4096u}) {
      const double v = ray_visibility(scene, light, origin, rays(k)).visibility.at(0);
      const double error = std::abs(v - 0.5);
      // Stratified: a 1/n-wide band of strata straddles the edge, so the error is within 1/n.
      EXPECT_LE(error, 1.0 / std::sqrt(static_cast<double>(k)) + 1e-12) << light.name << " k = " << k;
      if (k == 4096) EXPECT_LE(error, 0.01) << light.name;
    }
  }
}

TEST(SoftRays, OpenSpaceSeesAllAndAClosedBoxNone) {
  const Scene open = ground_scene(false);
  Scene box;
  add_mesh(box, "room", room_faces({-3, -3, 0}, {3, 3, 3}));  // face 1 is the floor, front up
  validate_scene(box);
  const std::vector<SurfacePoint> ground{{0, {0.3, -0.7, 0}}, {0, {5, 5, 0}}};
  const std::vector<SurfacePoint> floor{{1, {0.3, -0.7, 0}}, {1, {2, 2, 0}}};
  for (const Light& light : {square_light(2, 4), disk_light(1, 4), sun_disk({0.2, 0.1, 1})}) {
    for (double v : ray_visibility(open, light, ground, rays(256)).visibility) EXPECT_EQ(v, 1.0) << light.name;
    for (double v : ray_visibility(box, light, floor, rays(256)).visibility) EXPECT_EQ(v, 0.0) << light.name;
    SoftShadowMapOptions map;
    map.resolution = 256;
    map.threads = 2;
    for (double v : pcf_visibility(open, light, ground, map).visibility) EXPECT_EQ(v, 1.0) << light.name;
    for (double v : pcss_visibility(open, light, ground, map).visibility) EXPECT_EQ(v, 1.0) << light.name;
    for (double v : pcf_visibility(box, light, floor, map).visibility) EXPECT_EQ(v, 0.0) << light.name;
    for (double v : pcss_visibility(box, light, floor, map).visibility) EXPECT_EQ(v, 0.0) << light.name;
  }
}

TEST(SoftRays, ResultDoesNotDependOnThreadsAndPointsBehindTheLightSeeNothing) {
  const Scene scene = ground_scene(true);
  const FacePoints pts = face_sample_points(scene, 1.0);
  ASSERT_EQ(pts.face_ids.size(), 1u);  // the occluder does not receive
  ASSERT_EQ(pts.points.size(), 400u);
  const Light light = square_light(2, 4);
  EXPECT_EQ(ray_visibility(scene, light, pts.points, rays(64, 1)).visibility,
            ray_visibility(scene, light, pts.points, rays(64, 2)).visibility);
  Light upward = light;  // front facing up: the ground is behind it
  std::reverse(upward.polygon.begin(), upward.polygon.end());
  for (double v : ray_visibility(scene, upward, pts.points, rays(16)).visibility) EXPECT_EQ(v, 0.0);
}

TEST(SoftShadowMap, PcfOfRadiusZeroIsTheHardShadowMap) {
  // The sun's disk with its blur turned off against shadow_map_lighting of the point sun in its
  // centre: every point is 0 or 1, and each face's share agrees within what the two sample
  // grids can differ by (cells along the shadow's outline, perimeter 8, on a 100 m^2 ground).
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "square", {rectangle_z(-1, -1, 1, 1, 2), rectangle_z(-1, -1, 1, 1, 2, false)});
  const glm::dvec3 dir{1, 0.5, 1};
  scene.lights.push_back(directional_light("sun", dir));
  validate_scene(scene);
  ShadowMapOptions hard;
  hard.resolution = 512;
  hard.threads = 2;
  const BaselineResult h = shadow_map_lighting(scene, hard);
  SoftShadowMapOptions pcf;
  pcf.resolution = 512;
  pcf.pcf_radius = 0;
  pcf.threads = 2;
  const double spacing = 0.02;
  const FacePoints pts = face_sample_points(scene, spacing);
  const SoftResult soft = pcf_visibility(scene, sun_disk(dir), pts.points, pcf);
  for (double v : soft.visibility) EXPECT_TRUE(v == 0.0 || v == 1.0);
  const std::vector<FaceLighting> faces = soft_face_estimates(pts, soft.visibility, 0);
  const double texel = 10 * std::sqrt(2.0) * 1.5 / 512;  // the window is at most this wide
  for (const FaceLighting& f : faces) {
    const FaceLighting* e = h.find(f.face_id, 0);
    ASSERT_NE(e, nullptr);
    EXPECT_NEAR(f.lit_fraction, e->lit_fraction, 8 * 2 * (texel + spacing) / f.area) << "face " << f.face_id;
  }
  // And the ground's share is the closed form: shadow of area 4 inside 100.
  EXPECT_NEAR(faces[0].lit_fraction, 0.96, 8 * 2 * (texel + spacing) / 100);
}

/// The penumbra's width along x, measured on a row of points at y = `y` on face `face` at height z.
double penumbra_width(const std::vector<double>& v, double dx) {
  std::size_t n = 0;
  for (double x : v) n += (x > 0.02 && x < 0.98) ? 1 : 0;
  return static_cast<double>(n) * dx;
}

TEST(SoftShadowMap, PcssWidensThePenumbraOfAFartherReceiver) {
  // A 1 x 1 light at height 10 over an occluder edge (x = 0) at height 8. By similar triangles
  // the penumbra is 1 x (10 - 2) / 2 = 4 m wide on the ground (z = 0) and 1 x (4 - 2) / 2 = 1 m
  // on a plate at z = 6; a fixed-radius PCF gives both the same width in texels.
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-10, -8, 10, -1, 0)});
  add_mesh(scene, "plate", {rectangle_z(-10, 1, 10, 8, 6)});
  add_mesh(scene, "occluder", {rectangle_z(-30, -30, 0, 30, 8), rectangle_z(-30, -30, 0, 30, 8, false)}, false);
  validate_scene(scene);
  const Light light = square_light(1, 10);
  const double dx = 0.02;
  std::vector<SurfacePoint> ground, plate;
  for (double x = -4 + 0.5 * dx; x < 4; x += dx) {
    ground.push_back({0, {x, -4, 0}});
    plate.push_back({1, {x, 4, 6}});
  }
  SoftShadowMapOptions o;
  o.resolution = 1024;
  o.threads = 2;
  o.max_kernel_radius = 256;
  o.max_search_radius = 256;
  const double wide = penumbra_width(pcss_visibility(scene, light, ground, o).visibility, dx);
  const double narrow = penumbra_width(pcss_visibility(scene, light, plate, o).visibility, dx);
  RecordProperty("pcss_ground_width", std::to_string(wide));
  RecordProperty("pcss_plate_width", std::to_string(narrow));
  EXPECT_GT(narrow, 0.0);
  EXPECT_GT(wide, 2.5 * narrow);
  EXPECT_NEAR(wide, 4.0, 1.5);
  EXPECT_NEAR(narrow, 1.0, 0.5);
  // k rays find the closed forms (strata straddling an edge blur them by about 1/n of a width).
  EXPECT_NEAR(penumbra_width(ray_visibility(scene, light, ground, rays(1024)).visibility, dx), 4.0, 0.4);
  EXPECT_NEAR(penumbra_width(ray_visibility(scene, light, plate, rays(1024)).visibility, dx), 1.0, 0.15);
  // A fixed PCF: the same kernel in texels; on the cube map a texel at 6 m is 0.6 of one at 10 m.
  o.pcf_radius = 4;
  const double pcf_ground = penumbra_width(pcf_visibility(scene, light, ground, o).visibility, dx);
  const double pcf_plate = penumbra_width(pcf_visibility(scene, light, plate, o).visibility, dx);
  EXPECT_LT(pcf_ground, 1.0);
  EXPECT_LT(pcf_plate, 1.0);
}

TEST(SoftRays, AgreeWithTheExactVisibleFractionOnRandomScenes) {
  // Two independent methods: k = 1024 stratified rays (Embree, float32) and light_visibility
  // (exact unions). Stratified on a 32 x 32 grid, a point's error comes from the strata that the
  // visible part's outline crosses, a few times 1/32 of them at most: bounds 0.03 (a
  // point) and 0.003 (the mean); every method's fractions stay in [0, 1].
  for (std::uint64_t seed : {3u, 11u}) {
    Scene scene = random_scene(seed);
    const glm::dvec3 d = scene.lights[0].type == LightType::Directional ? scene.lights[0].to_light : glm::dvec3(0.3, 0.2, 1);
    scene.lights.clear();
    validate_scene(scene);
    const FacePoints pts = face_sample_points(scene, 0.75, 512);
    Light disk = disk_light(1.5, 13);
    disk.position = {2, -1, 13};
    for (const Light& light : {square_light(3, 14), disk, sun_disk(d, 3.0)}) {
      const std::vector<double> exact = light_visibility(scene, light, pts.points, 2);
      const std::vector<double> k = ray_visibility(scene, light, pts.points, rays(1024)).visibility;
      double sum = 0, worst = 0;
      std::size_t partial = 0;
      for (std::size_t i = 0; i < exact.size(); ++i) {
        const double e = std::abs(k[i] - exact[i]);
        sum += e;
        worst = std::max(worst, e);
        partial += exact[i] > 0 && exact[i] < 1 ? 1 : 0;
      }
      RecordProperty("seed" + std::to_string(seed) + "_" + light.name,
                     std::to_string(exact.size()) + " points, " + std::to_string(partial) + " partial, mean " +
                         std::to_string(sum / static_cast<double>(exact.size())) + ", max " + std::to_string(worst));
      EXPECT_LE(worst, 0.03) << "seed " << seed << ", " << light.name;
      EXPECT_LE(sum / static_cast<double>(exact.size()), 0.001) << "seed " << seed << ", " << light.name;
      EXPECT_GT(partial, 0u) << "seed " << seed << ", " << light.name;  // the case has penumbrae
      SoftShadowMapOptions map;
      map.resolution = 512;
      map.threads = 2;
      for (const std::vector<double>& v : {pcf_visibility(scene, light, pts.points, map).visibility,
                                           pcss_visibility(scene, light, pts.points, map).visibility})
        for (double x : v) EXPECT_TRUE(x >= 0.0 && x <= 1.0) << light.name;
    }
  }
}

TEST(SoftBaselines, RejectUnusableInput) {
  const Scene scene = ground_scene(true);
  const std::vector<SurfacePoint> origin{{0, {0, 0, 0}}};
  EXPECT_THROW(ray_visibility(scene, point_light("lamp", {0, 0, 4}), origin), InputError);
  EXPECT_THROW(pcf_visibility(scene, directional_light("sun", {0, 0, 1}), origin), InputError);
  EXPECT_THROW(ray_visibility(scene, square_light(2, 4), {{99, {0, 0, 0}}}), InputError);
  EXPECT_THROW(ray_visibility(scene, square_light(2, 4), origin, rays(0)), InputError);
  SoftShadowMapOptions bad;
  bad.resolution = 0;
  EXPECT_THROW(pcss_visibility(scene, square_light(2, 4), origin, bad), InputError);
  Light flat = square_light(2, 4);
  flat.polygon = {{0, 0, 4}, {1, 0, 4}, {2, 0, 4}};
  EXPECT_THROW(ray_visibility(scene, flat, origin), InputError);
  // One bound for angular_diameter, check_light's [0, 60] (it was (0, 180) here).
  EXPECT_NO_THROW(ray_visibility(scene, sun_disk({0, 0, 1}, 60.0), origin, rays(16)));
  try {
    (void)ray_visibility(scene, sun_disk({0, 0, 1}, 61.0), origin, rays(16));
    ADD_FAILURE() << "a 61-degree sun was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(e.where().place.find("angular_diameter"), std::string::npos) << e.what();
  }
  Light no_radius = disk_light(1, 4);
  no_radius.radius = 0;
  EXPECT_THROW(pcf_visibility(scene, no_radius, origin), InputError);
  EXPECT_THROW(face_sample_points(scene, 0.0), InputError);
}

}  // namespace
}  // namespace shadow::test
