// SPDX-License-Identifier: GPL-3.0-or-later
// libshadow::testing: the exact oracles against closed forms and against an independent
// double-precision ray caster, the checkers' verdicts (passing and failing), and the generators'
// promises (simple, convex, holes tile, valid scenes). RC_PARAMS seeds the properties.
#include "support/ray_caster.hpp"
#include "support/scene_builders.hpp"

#include <shadow/shadow.hpp>
#include <shadow/testing.hpp>
#include <shadow/testing/generators.hpp>
#include <shadow/testing/gtest.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <random>

namespace shadow::test {
namespace {

namespace kit = shadow::testing;

/// A 10 x 10 ground centred on the origin and the unit cube [0, 1]^3 standing on it.
Scene cube_on_ground(glm::dvec3 to_light) {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "cube", box_faces({0, 0, 0}, {1, 1, 1}));
  scene.lights.push_back(directional_light("sun", to_light));
  validate_scene(scene);
  return scene;
}

ShadowResult run(const Scene& scene, bool polygons = true) {
  ShadowOptions options;
  options.threads = 2;
  options.polygons = polygons;
  return compute_shadows(scene, options);
}

TEST(Oracle, OverheadSunLightsTheGroundOutsideTheFootprint) {
  const Scene scene = cube_on_ground({0, 0, 1});
  EXPECT_PRED_FORMAT3(kit::IsLitAt, scene, glm::dvec3(2, 2, 0), 0);
  EXPECT_PRED_FORMAT3(kit::IsLitAt, scene, glm::dvec3(1.5, 0.5, 0), 0);
  // Under the cube: on the ground (up) and on the cube's bottom (down): not lit.
  EXPECT_PRED_FORMAT3(kit::IsShadowedAt, scene, glm::dvec3(0.5, 0.5, 0), 0);
  // Inside the cube (on no face): the top blocks.
  EXPECT_PRED_FORMAT3(kit::IsShadowedAt, scene, glm::dvec3(0.5, 0.5, 0.5), 0);
  // On the top: lit. On the top's edge with the east wall (grazing): not lit, but lit as a
  // point of the top.
  EXPECT_PRED_FORMAT3(kit::IsLitAt, scene, glm::dvec3(0.5, 0.5, 1), 0);
  EXPECT_PRED_FORMAT3(kit::IsShadowedAt, scene, glm::dvec3(1, 0.5, 1), 0);
  EXPECT_TRUE(kit::is_lit_on_face(scene, 1, {1, 0.5, 1}, 0));   // face 1: the top
  EXPECT_FALSE(kit::is_lit_on_face(scene, 5, {1, 0.5, 0.5}, 0));  // face 5: east wall, grazing
  // Footprint boundary: on the cube's bottom (down) and east wall (grazing): not lit. As a
  // point of the ground, its ray runs up the east wall (edge-on, no block) but meets the top's
  // edge at (1, 0.5, 1): a shadow boundary, shadowed. One ulp further out it is lit.
  EXPECT_PRED_FORMAT3(kit::IsShadowedAt, scene, glm::dvec3(1, 0.5, 0), 0);
  EXPECT_FALSE(kit::is_lit_on_face(scene, 0, {1, 0.5, 0}, 0));
  EXPECT_PRED_FORMAT3(kit::IsLitAt, scene, glm::dvec3(std::nextafter(1.0, 2.0), 0.5, 0), 0);
  EXPECT_TRUE(kit::on_face(scene, 0, {1, 0.5, 0}));
  EXPECT_FALSE(kit::on_face(scene, 0, {1, 0.5, 1e-300}));
}

TEST(Oracle, ShadowBoundaryIsDecidedExactlyAndCountsAsShadowed) {
  // Sun toward (-1, 0, 1): the cube's shadow on the ground is x in [1, 2], y in [0, 1].
  const Scene scene = cube_on_ground({-1, 0, 1});
  EXPECT_PRED_FORMAT3(kit::IsShadowedAt, scene, glm::dvec3(1.5, 0.5, 0), 0);  // ray hits the east wall
  // The far shadow edge x = 2: the ray meets the cube's top east edge at (1, 0.5, 1) exactly.
  EXPECT_PRED_FORMAT3(kit::IsShadowedAt, scene, glm::dvec3(2, 0.5, 0), 0);
  EXPECT_PRED_FORMAT3(kit::IsLitAt, scene, glm::dvec3(std::nextafter(2.0, 3.0), 0.5, 0), 0);
  EXPECT_PRED_FORMAT3(kit::IsShadowedAt, scene, glm::dvec3(std::nextafter(2.0, 1.0), 0.5, 0), 0);
  // Side boundary y = 1 (the ray slides along the north wall's plane, hits the top's edge).
  EXPECT_PRED_FORMAT3(kit::IsShadowedAt, scene, glm::dvec3(1.5, 1, 0), 0);
  EXPECT_PRED_FORMAT3(kit::IsLitAt, scene, glm::dvec3(1.5, std::nextafter(1.0, 2.0), 0), 0);
  // The engine agrees on the area: 100 - 1 (footprint) - 1 (cast shadow).
  EXPECT_EQ(kit::exact_lit_area(scene, 0, 0), 98.0);
}

TEST(Oracle, LampOnAPlaneAndBadIds) {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  scene.lights.push_back(point_light("lamp", {3, 3, 0}));
  validate_scene(scene);
  EXPECT_FALSE(kit::is_lit(scene, {4, 4, 0}, 0));   // the ground does not face a lamp in its plane
  EXPECT_TRUE(kit::is_lit(scene, {3, 3, 1}, 0));    // the segment touches the ground only at the lamp
  EXPECT_TRUE(kit::is_lit(scene, {3, 3, -1}, 0));   // ...from below too
  EXPECT_FALSE(kit::is_lit(scene, {3, 3, 0}, 0));   // on the ground, at the lamp: not facing
  EXPECT_TRUE(kit::is_lit(scene, {4, 4, -1}, 0));   // the segment meets the ground only at the lamp
  EXPECT_EQ(kit::exact_lit_area(scene, 0, 0), 0.0);
  EXPECT_THROW(kit::is_lit(scene, {0, 0, 1}, 1), InputError);
  EXPECT_THROW(kit::is_lit_on_face(scene, 3, {0, 0, 0}, 0), InputError);
  EXPECT_THROW(kit::exact_shadow_area(scene, 0, 0), InputError);
}

TEST(Oracle, ExactShadowAreaOnAPlaneIsTheClosedForm) {
  // A 2 x 3 panel at height 2, sun along (1, 0, 2): its shadow on z = 0 is the panel shifted,
  // area 6; a point light at height 4 doubles it linearly: area 6 * (4 / (4 - 2))^2 = 24.
  Scene scene;
  add_mesh(scene, "panel", {rectangle_z(0, 0, 2, 3, 2)});
  scene.lights.push_back(directional_light("sun", {1, 0, 2}));
  scene.lights.push_back(point_light("lamp", {1, 1.5, 4}));
  Plane ground;
  ground.name = "ground";
  scene.planes.push_back(ground);
  validate_scene(scene);
  EXPECT_EQ(kit::exact_shadow_area(scene, 0, 0), 6.0);
  EXPECT_EQ(kit::exact_shadow_area(scene, 0, 1), 24.0);
}

RC_GTEST_PROP(Oracle, AgreesWithAnIndependentRayCasterWhereItIsSure, ()) {
  const auto seed = *rc::gen::inRange<std::uint64_t>(0, 1u << 30);
  Scene scene = random_scene(seed);
  validate_scene(scene);
  int decided = 0;
  const kit::ExactOracle oracle(scene);
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    if (scene.faces[f].degenerate) continue;
    for (const glm::dvec3& p : kit::sample_face(scene, f, 3, seed + f)) {
      const RayVerdict v = cast_shadow_ray(scene, f, p, scene.lights[0], 1e-6);
      if (v == RayVerdict::Unsure) continue;
      ++decided;
      RC_ASSERT(oracle.is_lit_on_face(f, p, 0) == (v == RayVerdict::Lit));
    }
  }
  RC_ASSERT(decided > 0);
}

RC_GTEST_PROP(Oracle, SampledLitFractionMatchesTheEngine, ()) {
  // Monte Carlo with the oracle against the engine's exact fraction: within 5 sigma.
  const auto seed = *rc::gen::inRange<std::uint64_t>(0, 1u << 30);
  Scene scene = random_scene(seed);
  validate_scene(scene);
  const ShadowResult r = run(scene, false);
  const kit::ExactOracle oracle(scene);
  for (const FaceLighting& fl : r.lighting) {
    if (fl.area <= 0 || fl.face_id % 3 != 0) continue;  // a third of the faces: keeps it short
    const auto points = kit::sample_face(scene, fl.face_id, 200, seed);
    if (points.size() < 100) continue;
    int lit = 0;
    for (const glm::dvec3& p : points) lit += oracle.is_lit_on_face(fl.face_id, p, fl.light_id);
    const double n = static_cast<double>(points.size()), estimate = lit / n;
    const double sigma = std::sqrt(std::max(fl.lit_fraction * (1 - fl.lit_fraction), 1.0 / n) / n);
    RC_ASSERT(std::abs(estimate - fl.lit_fraction) <= 5 * sigma);
  }
}

TEST(Checkers, PassOnTheEngineAndExplainFailures) {
  const Scene scene = cube_on_ground({-1, 0, 1});
  ShadowResult r = run(scene);
  EXPECT_PRED_FORMAT2(kit::Partitions, scene, r);
  EXPECT_PRED_FORMAT3(kit::LitClaimsHold, scene, r, 7u);
  // A wrong lit area breaks the partition; a flipped fragment breaks the lit claims.
  ShadowResult bad = r;
  bad.lighting[0].lit_area += 0.5;
  const kit::Verdict v = kit::check_partition(scene, bad);
  EXPECT_FALSE(v.ok);
  EXPECT_NE(v.message.find("face 0 (ground[0]) light 0 (sun)"), std::string::npos) << v.message;
  for (Fragment& f : bad.fragments)
    if (f.face_id == 0) f.lit = !f.lit;
  const kit::Verdict w = kit::check_lit_claims(scene, bad, 7);
  EXPECT_FALSE(w.ok);
  EXPECT_NE(w.message.find("disagree with their fragment"), std::string::npos) << w.message;
}

TEST(Checkers, InvarianceAndMonotonicity) {
  const Scene scene = cube_on_ground({-1, 0.5, 2});
  kit::Similarity s;
  s.quarter_turns_z = 1;
  s.quarter_turns_x = 2;
  s.scale_exponent = -3;
  s.translation = {1024, -2048, 64};
  EXPECT_TRUE(kit::to_assertion(kit::check_invariance(scene, s, 0.0)));
  // A method that depends on where the scene is: caught, with the face named.
  const auto moving = [](const Scene& sc) {
    ShadowResult r = compute_shadows(sc);
    if (sc.faces[0].vertices[0].x > 100) r.lighting[0].lit_fraction *= 0.5;
    return r;
  };
  kit::Similarity far;
  far.translation = {4096, 0, 0};
  const kit::Verdict v = kit::check_invariance(scene, far, 1e-12, moving);
  EXPECT_FALSE(v.ok);
  EXPECT_NE(v.message.find("face 0"), std::string::npos) << v.message;
  EXPECT_TRUE(kit::to_assertion(kit::check_monotone_occluder(scene, {rectangle_z(-3, -3, -1, -1, 2)})));
}

TEST(Comparison, ReportsTheWorstFaceItsErrorAndTheSeed) {
  const Scene scene = cube_on_ground({-1, 0, 1});
  const ShadowResult r = run(scene, false);
  const auto exact = [&](const Scene&, std::size_t f, std::size_t l) { return r.find(f, l)->lit_fraction; };
  const kit::Comparison same = kit::compare_lit_fractions(scene, exact, 0.0, 42);
  EXPECT_PRED_FORMAT1(kit::WithinTolerance, same);
  EXPECT_EQ(same.error, 0.0);
  EXPECT_EQ(same.pairs, 7u);
  const auto off = [&](const Scene& sc, std::size_t f, std::size_t l) { return exact(sc, f, l) + (f == 3 ? 0.25 : 0.01); };
  const kit::Comparison c = kit::compare_lit_fractions(scene, off, 0.1, 42);
  EXPECT_FALSE(c.ok);
  EXPECT_EQ(c.worst_face, 3u);
  EXPECT_DOUBLE_EQ(c.error, 0.25);
  const std::string report = c.report();
  EXPECT_NE(report.find("worst face 3 (cube[2]) light 0"), std::string::npos) << report;
  EXPECT_NE(report.find("error 0.25"), std::string::npos) << report;
  EXPECT_NE(report.find("seed 42"), std::string::npos) << report;
}

// ---- generators ----------------------------------------------------------------------------

RC_GTEST_PROP(Generators, PolygonsAreWhatTheySay, ()) {
  const kit::Polygon2 convex = *kit::gen::convex_polygon();
  RC_ASSERT(kit::is_simple(convex));
  for (std::size_t v = 0; v < convex.size(); ++v) {
    const glm::dvec2 a = convex[v], b = convex[(v + 1) % convex.size()], c = convex[(v + 2) % convex.size()];
    RC_ASSERT((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x) > 0);  // strictly left turns
  }
  const kit::Polygon2 simple = *kit::gen::simple_polygon();
  RC_ASSERT(kit::is_simple(simple));
  RC_ASSERT(kit::signed_area2(simple) > 0);
  RC_ASSERT(kit::is_simple(*kit::gen::nonconvex_polygon()));
  const Polygon3 tilted = *kit::gen::planar_polygon({0, 0, 3}, {1, 0, 0}, {0, 0, 1});
  for (const glm::dvec3& v : tilted) RC_ASSERT(v.y == 0.0);  // exactly on y = 0
}

RC_GTEST_PROP(Generators, HolesTileExactly, ()) {
  const kit::PolygonWithHoles region = *kit::gen::rectangle_with_holes();
  double expected = kit::signed_area2(region.outer);
  for (const kit::Polygon2& h : region.holes) {
    RC_ASSERT(kit::signed_area2(h) < 0);  // clockwise
    expected += kit::signed_area2(h);
  }
  double tiled = 0;
  for (const kit::Polygon2& t : kit::tile_rectangles(region)) {
    RC_ASSERT(kit::signed_area2(t) > 0);
    tiled += kit::signed_area2(t);
    glm::dvec2 c(0.0);
    for (const glm::dvec2& q : t) c += q / 4.0;
    for (const kit::Polygon2& h : region.holes)  // no tile centre inside a hole
      RC_ASSERT(!(c.x > h[0].x && c.x < h[2].x && c.y > h[0].y && c.y < h[2].y));
  }
  RC_ASSERT(tiled == expected);
}

// Shrinking: a property that fails on cities of 3 boxes or more shrinks to exactly 3 unit cubes
// at the origin; one that fails on polygons of 6 vertices or more, to a hexagon of radius 1.
// The last failing case rapidcheck evaluates is the shrunk counterexample.
TEST(Generators, ShrinkToSmallCounterexamples) {
  Scene smallest;
  EXPECT_FALSE(rc::check("cities have fewer than 3 boxes", [&] {
    const Scene city = *kit::gen::box_city();
    if (city.faces.size() >= 1 + 3 * 6) {
      smallest = city;
      RC_FAIL("3 boxes or more");
    }
  }));
  ASSERT_EQ(smallest.faces.size(), 1u + 3 * 6);
  for (std::size_t f = 1; f < smallest.faces.size(); ++f)
    for (const glm::dvec3& v : smallest.faces[f].vertices) {
      EXPECT_TRUE(v.x == 0 || v.x == 1) << v.x;
      EXPECT_TRUE(v.y == 0 || v.y == 1) << v.y;
      EXPECT_TRUE(v.z == 0 || v.z == 1) << v.z;
    }
  kit::Polygon2 shortest;
  EXPECT_FALSE(rc::check("polygons have fewer than 6 vertices", [&] {
    const kit::Polygon2 p = *kit::gen::simple_polygon();
    if (p.size() >= 6) {
      shortest = p;
      RC_FAIL("6 vertices or more");
    }
  }));
  ASSERT_EQ(shortest.size(), 6u);
  for (const glm::dvec2& v : shortest) EXPECT_NEAR(glm::length(v), 1.0, 0.2);  // radius 1 on the 1/4 grid
}

void check_scene(Scene scene) {
  validate_scene(scene);
  const ShadowResult r = run(scene);
  const kit::Verdict partition = kit::check_partition(scene, r);
  if (!partition.ok) RC_FAIL(partition.message);
  const kit::Verdict claims = kit::check_lit_claims(scene, r, 5, 2);
  if (!claims.ok) RC_FAIL(claims.message);
}

RC_GTEST_PROP(Generators, CitiesAndRoomsSatisfyTheInvariants, ()) {
  check_scene(*kit::gen::box_city());
  check_scene(*kit::gen::room_with_lamp());
}

RC_GTEST_PROP(Generators, HardCasesSatisfyTheInvariants, ()) { check_scene(*kit::gen::hard_case()); }

}  // namespace
}  // namespace shadow::test
