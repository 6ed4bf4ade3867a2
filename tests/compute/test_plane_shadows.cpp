// SPDX-License-Identifier: GPL-3.0-or-later
// Blinn's shadow matrices and exact plane shadows: against the seed's formulas, against direct
// ray/plane intersection, against closed-form areas, and against the per-face engine.
#include "support/scene_builders.hpp"

#include <shadow/shadow.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <random>

namespace shadow::test {
namespace {

Plane ground_plane() {
  Plane p;
  p.name = "ground";
  p.point = {0, 0, 0};
  p.normal = {0, 0, 1};
  return p;
}

/// Row r, column c of a GLM (column-major) matrix.
double at(const glm::dmat4& m, int r, int c) { return m[c][r]; }

TEST(BlinnMatrix, DirectionalLightOnGroundIsZlTimesTheSeedsEquation7) {
  const double xl = 0.4, yl = -0.3, zl = 0.85;
  const glm::dmat4 m = shadow_matrix(ground_plane(), directional_light("sun", {xl, yl, zl}));
  // Seed 004, eq. (7): [1 0 -xl/zl 0; 0 1 -yl/zl 0; 0 0 0 0; 0 0 0 1], up to the factor zl.
  const double seed[4][4] = {{1, 0, -xl / zl, 0}, {0, 1, -yl / zl, 0}, {0, 0, 0, 0}, {0, 0, 0, 1}};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(at(m, r, c), zl * seed[r][c], 1e-15) << r << "," << c;
}

TEST(BlinnMatrix, PointLightOnGroundIsTheCorrectedEquation12AndGivesEquation11) {
  const double xl = 1.5, yl = -2.0, zl = 9.5;
  const glm::dmat4 m = shadow_matrix(ground_plane(), point_light("lamp", {xl, yl, zl}));
  // The seed's printed (12) is garbled (y_l in the third row); the correct matrix is
  // [-zl 0 xl 0; 0 -zl yl 0; 0 0 0 0; 0 0 1 -zl], and ours is its negative.
  const double fixed[4][4] = {{-zl, 0, xl, 0}, {0, -zl, yl, 0}, {0, 0, 0, 0}, {0, 0, 1, -zl}};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) EXPECT_EQ(at(m, r, c), -fixed[r][c]) << r << "," << c;
  // Eq. (11): x_s = (x_l z_p - x_p z_l) / (z_p - z_l), likewise y_s.
  const glm::dvec3 p(0.25, 0.75, 2.0);
  const glm::dvec3 s = project_with(m, p);
  EXPECT_DOUBLE_EQ(s.x, (xl * p.z - p.x * zl) / (p.z - zl));
  EXPECT_DOUBLE_EQ(s.y, (yl * p.z - p.y * zl) / (p.z - zl));
  EXPECT_EQ(s.z, 0.0);
}

TEST(BlinnMatrix, AgreesWithRayPlaneIntersectionForAnyPlaneAndLight) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-5, 5);
  for (int trial = 0; trial < 200; ++trial) {
    Plane plane;
    plane.point = {u(rng), u(rng), u(rng)};
    plane.normal = {u(rng), u(rng), u(rng)};
    const bool point = trial % 2 == 0;
    const Light light = point ? point_light("l", {u(rng), u(rng), u(rng)}) : directional_light("l", {u(rng), u(rng), u(rng)});
    const glm::dvec3 x(u(rng), u(rng), u(rng));
    // Direct: the line through x and the light meets the plane at t.
    const glm::dvec3 dir = point ? light.position - x : light.to_light;
    const double denom = glm::dot(plane.normal, dir);
    if (std::abs(denom) < 1e-3) continue;
    const double t = glm::dot(plane.normal, plane.point - x) / denom;
    const glm::dvec3 expected = x + t * dir;
    const glm::dvec3 got = project_with(shadow_matrix(plane, light), x);
    EXPECT_NEAR(glm::length(got - expected), 0.0, 1e-9 * (1 + glm::length(expected))) << trial;
    EXPECT_NEAR(glm::dot(plane.normal, got - plane.point), 0.0, 1e-9 * (1 + glm::length(got)));
  }
}

Scene square_above_ground(const Light& light) {
  Scene scene;
  add_mesh(scene, "square", {rectangle_z(0, 0, 1, 1, 1)});
  scene.lights.push_back(light);
  scene.planes.push_back(ground_plane());
  validate_scene(scene);
  return scene;
}

TEST(PlaneShadows, UnitSquareAtHeightOneUnderALampAtThreeCastsExactlyTwoAndAQuarter) {
  const Scene scene = square_above_ground(point_light("lamp", {0.5, 0.5, 3}));
  const std::vector<PlaneShadow> s = compute_plane_shadows(scene);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].area, 2.25);
  EXPECT_FALSE(s[0].reaches_window);
  double sum = 0;
  for (double a : s[0].polygon_area) sum += a;
  EXPECT_EQ(sum, 2.25);
  for (const auto& polygon : s[0].polygons)
    for (const glm::dvec3& v : polygon) {
      EXPECT_EQ(v.z, 0.0);
      EXPECT_GE(v.x, -0.25);
      EXPECT_LE(v.x, 1.25);
    }
}

TEST(PlaneShadows, TheSunCastsTheSquareUnchangedInArea) {
  const Scene scene = square_above_ground(directional_light("sun", {1, 2, 1}));
  EXPECT_EQ(compute_plane_shadows(scene)[0].area, 1.0);
}

TEST(PlaneShadows, GeometryCrossingThePlaneCastsOnlyFromAboveIt) {
  // A 2 x 2 x 2 box sunk halfway into the ground under an overhead sun: the part above the
  // plane casts its footprint; the part below casts nothing.
  Scene scene;
  add_mesh(scene, "box", box_faces({0, 0, -1}, {2, 2, 1}));
  scene.lights.push_back(directional_light("sun", {0, 0, 1}));
  scene.planes.push_back(ground_plane());
  validate_scene(scene);
  EXPECT_EQ(compute_plane_shadows(scene)[0].area, 4.0);
  // From below the plane (sun under the horizon), the same box casts from its lower half.
  scene.lights[0] = directional_light("sun", {0, 0, -1});
  EXPECT_EQ(compute_plane_shadows(scene)[0].area, 4.0);
}

TEST(PlaneShadows, GeometryRisingAboveThePointLightCastsAShadowWithoutEnd) {
  // A wall from height 0.5 to 5 next to a lamp at height 2: the wall's part above the lamp
  // casts nothing, the part just below it casts to infinity; the window bounds what is reported.
  Scene scene;
  add_mesh(scene, "wall", {{{1, -1, 0.5}, {1, 1, 0.5}, {1, 1, 5}, {1, -1, 5}}});
  scene.lights.push_back(point_light("lamp", {0, 0, 2}));
  scene.planes.push_back(ground_plane());
  validate_scene(scene);
  ShadowOptions options;
  options.plane_window = 100;
  const std::vector<PlaneShadow> s = compute_plane_shadows(scene, options);
  EXPECT_TRUE(s[0].reaches_window);
  EXPECT_GT(s[0].area, 0.0);
  for (const auto& polygon : s[0].polygons)
    for (const glm::dvec3& v : polygon) EXPECT_GE(v.x, 4.0 / 3.0 - 1e-12);  // starts where the wall's foot projects
}

TEST(PlaneShadows, ALampOnAFacesEdgeOrInsideItDoesNotBreakThePlaneShadow) {
  // The face's plane contains the lamp: it is edge-on and casts nothing (its projection would
  // divide by zero at the lamp).
  Scene scene;
  add_mesh(scene, "square", {rectangle_z(0, 0, 1, 1, 1)});
  add_mesh(scene, "wall", {{{-1, -1, 0.5}, {-1, 1, 0.5}, {-1, 1, 2}, {-1, -1, 2}}});  // lamp on its top edge
  add_mesh(scene, "panel", {{{-2, 2, 1.5}, {2, 2, 2.5}, {2, 3, 2.5}, {-2, 3, 1.5}}});   // lamp in its plane
  scene.lights.push_back(point_light("lamp", {-1, 0, 2}));
  scene.planes.push_back(ground_plane());
  validate_scene(scene);
  ShadowOptions options;
  options.plane_window = 50;
  const std::vector<PlaneShadow> s = compute_plane_shadows(scene, options);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_GT(s[0].area, 0.0);
}

TEST(PlaneShadows, GeometryWhollyAboveALampCastsNothingAndIsNotReportedAsCut) {
  Scene scene;
  add_mesh(scene, "ceiling", {rectangle_z(-5, -5, 5, 5, 3, false)});
  scene.lights.push_back(point_light("lamp", {0, 0, 2}));
  scene.planes.push_back(ground_plane());
  validate_scene(scene);
  const std::vector<PlaneShadow> s = compute_plane_shadows(scene);
  EXPECT_EQ(s[0].area, 0.0);
  EXPECT_FALSE(s[0].reaches_window);
}

TEST(PlaneShadows, AWindowTooLargeToRepresentIsAnInputErrorNotACrash) {
  Scene scene = square_above_ground(point_light("lamp", {0.5, 0.5, 3}));
  scene.planes[0].window = 1.7e308;
  EXPECT_THROW(compute_plane_shadows(scene), InputError);
}

TEST(PlaneShadows, FacesLyingInThePlaneCastNothing) {
  Scene scene;
  add_mesh(scene, "floor", {rectangle_z(-1, -1, 1, 1, 0)});
  scene.lights.push_back(directional_light("sun", {0.3, 0.2, 1}));
  scene.planes.push_back(ground_plane());
  validate_scene(scene);
  EXPECT_EQ(compute_plane_shadows(scene)[0].area, 0.0);
}

TEST(PlaneShadows, ComputeShadowsFillsThemInPlaneThenLightOrder) {
  Scene scene = square_above_ground(point_light("lamp", {0.5, 0.5, 3}));
  scene.lights.push_back(directional_light("sun", {0, 0, 1}));
  Plane high = ground_plane();
  high.name = "deck";
  high.point = {0, 0, -1};
  scene.planes.push_back(high);
  const ShadowResult r = compute_shadows(scene);
  ASSERT_EQ(r.plane_shadows.size(), 4u);
  EXPECT_EQ(r.plane_shadows[0].plane_id, 0u);
  EXPECT_EQ(r.plane_shadows[0].light_id, 0u);
  EXPECT_EQ(r.plane_shadows[1].light_id, 1u);
  EXPECT_EQ(r.plane_shadows[3].plane_id, 1u);
  EXPECT_EQ(r.plane_shadows[0].area, 2.25);
  EXPECT_EQ(r.plane_shadows[1].area, 1.0);
  EXPECT_EQ(r.plane_shadows[2].area, 4.0);  // from height 3 to a plane at -1: scale 4/2
}

// Two independent methods, one answer: the Blinn plane shadow must equal the shadowed part of a
// large face lying in that plane, as the per-face (Atherton) engine computes it.
RC_GTEST_PROP(PlaneShadowProperties, PlaneShadowEqualsTheShadowedPartOfAFaceInThatPlane, ()) {
  const auto seed = *rc::gen::inRange<std::uint64_t>(0, 1u << 30);
  RC_LOG() << "random_scene(" << seed << ")\n";
  Scene scene = random_scene(seed);
  // Replace the ground by one much larger than any shadow, and add the plane it lies in.
  scene.faces[0].vertices = rectangle_z(-400, -400, 400, 400, 0);
  scene.planes.push_back(ground_plane());
  validate_scene(scene);
  ShadowOptions options;
  options.threads = 2;
  options.polygons = false;
  options.plane_window = 400;
  const ShadowResult r = compute_shadows(scene, options);
  const PlaneShadow& plane = r.plane_shadows.at(0);
  // A lamp below the top of some geometry casts without end: no finite face can hold that.
  RC_PRE(!plane.reaches_window);
  RC_TAG(scene.lights[0].type == LightType::Point ? "point light" : "sun");
  RC_ASSERT(plane.area == r.find(0, 0)->shadow_area);
}

}  // namespace
}  // namespace shadow::test
