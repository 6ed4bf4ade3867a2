// SPDX-License-Identifier: GPL-3.0-or-later
// Shadows with answers known in closed form.
#include "support/polygon_tools.hpp"
#include "support/scene_builders.hpp"

#include <shadow/shadow.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

namespace shadow::test {
namespace {

ShadowResult compute(Scene& scene, unsigned threads = 1) {
  validate_scene(scene);
  ShadowOptions options;
  options.threads = threads;
  return compute_shadows(scene, options);
}

double fragment_area_sum(const ShadowResult& r, std::size_t face, std::size_t light, int lit) {
  double sum = 0;
  for (const Fragment& f : r.fragments)
    if (f.face_id == face && f.light_id == light && (lit < 0 || f.lit == (lit == 1))) sum += f.area;
  return sum;
}

Scene square_over_ground(const Light& light) {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "square", {rectangle_z(0, 0, 1, 1, 1)});
  scene.lights.push_back(light);
  return scene;
}

TEST(AnalyticShadows, UnitSquareUnderOverheadSunShadowsExactlyOneSquareUnit) {
  Scene scene = square_over_ground(directional_light("sun", {0, 0, 1}));
  const ShadowResult r = compute(scene);
  const FaceLighting* ground = r.find(0, 0);
  ASSERT_NE(ground, nullptr);
  EXPECT_EQ(ground->area, 100.0);
  EXPECT_EQ(ground->lit_area, 99.0);
  EXPECT_EQ(ground->shadow_area, 1.0);
  EXPECT_EQ(ground->lit_fraction, 0.99);
  EXPECT_TRUE(ground->faces_light);
  const FaceLighting* square = r.find(1, 0);
  ASSERT_NE(square, nullptr);
  EXPECT_EQ(square->lit_area, 1.0);
  EXPECT_EQ(square->lit_fraction, 1.0);
}

TEST(AnalyticShadows, ObliqueSunShiftsTheShadowWithoutChangingItsArea) {
  Scene scene = square_over_ground(directional_light("sun", {1, 0.5, 1}));
  const ShadowResult r = compute(scene);
  EXPECT_EQ(r.find(0, 0)->shadow_area, 1.0);
  // The shadow is the square moved by -(1, 0.5): its fragment has that outline.
  bool found = false;
  for (const Fragment& f : r.fragments) {
    if (f.face_id != 0 || f.lit) continue;
    found = true;
    for (const glm::dvec3& v : f.polygon) {
      EXPECT_TRUE(v.x == -1.0 || v.x == 0.0) << v.x;
      EXPECT_TRUE(v.y == -0.5 || v.y == 0.5) << v.y;
      EXPECT_EQ(v.z, 0.0);
    }
  }
  EXPECT_TRUE(found);
}

TEST(AnalyticShadows, UnitSquareAtHeightOneUnderPointLightAtThreeCastsTwoAndAQuarter) {
  Scene scene = square_over_ground(point_light("lamp", {0.5, 0.5, 3}));
  const ShadowResult r = compute(scene);
  EXPECT_EQ(r.find(0, 0)->shadow_area, 2.25);
  EXPECT_EQ(r.find(0, 0)->lit_area, 100.0 - 2.25);
}

TEST(AnalyticShadows, PointLightOffCentreStillScalesTheShadowByItsHeightRatio) {
  // Light at height 4 over (3, -2): the square at height 1 projects scaled by 4/3.
  Scene scene = square_over_ground(point_light("lamp", {3, -2, 4}));
  const ShadowResult r = compute(scene);
  EXPECT_DOUBLE_EQ(r.find(0, 0)->shadow_area, 16.0 / 9.0);
}

TEST(AnalyticShadows, BoxOnTheGroundUnderA45DegreeSunCastsFootprintPlusSweep) {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-10, -10, 10, 10, 0)});
  add_mesh(scene, "box", box_faces({0, 0, 0}, {1, 1, 2}));
  scene.lights.push_back(directional_light("sun", {1, 0, 1}));
  const ShadowResult r = compute(scene);
  // Footprint [0,1]^2 plus the sweep of the roof to x in [-2, 0]: 1 x 3.
  EXPECT_EQ(r.find(0, 0)->shadow_area, 3.0);
  // Box faces in scene order: top, bottom, south, north, east, west.
  EXPECT_EQ(r.find(1, 0)->lit_fraction, 1.0);  // top
  EXPECT_FALSE(r.find(2, 0)->faces_light);     // bottom
  EXPECT_FALSE(r.find(3, 0)->faces_light);     // south: edge-on, attached shadow
  EXPECT_FALSE(r.find(4, 0)->faces_light);     // north: edge-on
  EXPECT_EQ(r.find(5, 0)->lit_fraction, 1.0);  // east faces the sun
  EXPECT_EQ(r.find(6, 0)->lit_fraction, 0.0);  // west: back to the sun
  EXPECT_EQ(r.find(6, 0)->shadow_area, 2.0);
}

TEST(AnalyticShadows, BoxUnderLowSunCastsALongShadowOfKnownLength) {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-100, -10, 10, 10, 0)});
  add_mesh(scene, "box", box_faces({0, 0, 0}, {1, 1, 2}));
  const glm::dvec3 sun = sun_direction(5.0, 90.0);  // toward +x, 5 degrees up
  scene.lights.push_back(directional_light("sun", sun));
  const ShadowResult r = compute(scene);
  const long double length = 2.0L * static_cast<long double>(sun.x) / static_cast<long double>(sun.z);
  const double expected = static_cast<double>(1.0L + length);
  EXPECT_NEAR(r.find(0, 0)->shadow_area, expected, 1e-13 * expected);
}

TEST(AnalyticShadows, FaceLitThroughASquareHoleReceivesExactlyTheHole) {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  // A ceiling at z = 2 covering [-6, 6]^2 except the hole [0, 1]^2, as four frames.
  add_mesh(scene, "ceiling",
           {rectangle_z(-6, -6, 6, 0, 2), rectangle_z(-6, 1, 6, 6, 2), rectangle_z(-6, 0, 0, 1, 2),
            rectangle_z(1, 0, 6, 1, 2)},
           /*receiver=*/false);
  scene.lights.push_back(directional_light("sun", {1, 0, 2}));
  const ShadowResult r = compute(scene);
  ASSERT_EQ(r.lighting.size(), 1u) << "only the ground receives";
  EXPECT_EQ(r.find(0, 0)->lit_area, 1.0);
  int lit_cells = 0;
  for (const Fragment& f : r.fragments) {
    if (!f.lit) continue;
    ++lit_cells;
    for (const glm::dvec3& v : f.polygon) {
      EXPECT_TRUE(v.x == -1.0 || v.x == 0.0) << v.x;  // the hole moved by -(1, 0) * 2 / 2
      EXPECT_TRUE(v.y == 0.0 || v.y == 1.0) << v.y;
    }
  }
  EXPECT_EQ(lit_cells, 1);
}

TEST(AnalyticShadows, NonConvexCasterOnNonConvexReceiver) {
  Scene scene;
  // An L-shaped receiver (area 3) and an L-shaped caster above it (area 3) under an overhead
  // sun: the shadow is the overlap of the two Ls.
  add_mesh(scene, "floor", {{{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}}});
  add_mesh(scene, "awning", {{{1, 0, 1}, {3, 0, 1}, {3, 2, 1}, {2, 2, 1}, {2, 1, 1}, {1, 1, 1}}});
  scene.lights.push_back(directional_light("sun", {0, 0, 1}));
  const ShadowResult r = compute(scene);
  EXPECT_EQ(r.find(0, 0)->area, 3.0);
  EXPECT_EQ(r.find(0, 0)->shadow_area, 1.0);  // the overlap is [1,2]x[0,1]
  EXPECT_EQ(r.find(1, 0)->area, 3.0);
}

TEST(AnalyticShadows, AShadowTouchingTheReceiversEdgeAtOnePointLeavesSimpleLitCells) {
  // The lit part is the square minus a triangle whose apex touches the square's edge: CGAL
  // returns it as one boundary that visits the apex twice; the output must be simple cells.
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(0, 0, 2, 2, 0)});
  add_mesh(scene, "sail", {{{0, 1, 1}, {1, 0.5, 1}, {1, 1.5, 1}}});
  scene.lights.push_back(directional_light("sun", {0, 0, 1}));
  const ShadowResult r = compute(scene);
  EXPECT_EQ(r.find(0, 0)->lit_area, 3.5);
  for (const Fragment& f : r.fragments) {
    for (std::size_t a = 0; a < f.polygon.size(); ++a)
      for (std::size_t b = a + 1; b < f.polygon.size(); ++b)
        EXPECT_NE(f.polygon[a], f.polygon[b]) << "fragment of face " << f.face_id << " repeats a vertex";
  }
  EXPECT_NEAR(fragment_area_sum(r, 0, 0, 1), 3.5, 1e-15);
}

TEST(AnalyticShadows, FragmentsOfEveryFaceAddUpToTheFace) {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "box", box_faces({-1, -1, 0}, {1, 1, 1}));
  add_mesh(scene, "plate", {rectangle_z(0.5, 0.5, 2.5, 2.5, 2)});
  scene.lights.push_back(directional_light("sun", {0.3, 0.2, 1}));
  scene.lights.push_back(point_light("lamp", {3, 3, 4}));
  const ShadowResult r = compute(scene);
  for (const FaceLighting& fl : r.lighting) {
    const double sum = fragment_area_sum(r, fl.face_id, fl.light_id, -1);
    EXPECT_NEAR(sum, fl.area, 1e-12 * fl.area) << "face " << fl.face_id << " light " << fl.light_id;
    EXPECT_NEAR(fragment_area_sum(r, fl.face_id, fl.light_id, 1), fl.lit_area, 1e-12 * fl.area);
    EXPECT_EQ(fl.lit_area + fl.shadow_area, fl.area);
  }
  for (const Fragment& f : r.fragments) {
    EXPECT_NEAR(polygon_area(f.polygon), f.area, 1e-12 * (1 + f.area));
    // Same orientation as the face.
    const glm::dvec3 nf = newell_normal(scene.faces[f.face_id].vertices);
    EXPECT_GT(glm::dot(newell_normal(f.polygon), nf), 0.0);
  }
}

TEST(AnalyticShadows, ThreadCountDoesNotChangeAnyNumber) {
  Scene scene = make_city(60, 80, 7);
  scene.lights.push_back(directional_light("sun", sun_direction(30, 200)));
  scene.lights.push_back(point_light("lamp", {40, 40, 50}));
  const ShadowResult one = compute(scene, 1);
  const ShadowResult two = compute(scene, 3);
  ASSERT_EQ(one.lighting.size(), two.lighting.size());
  for (std::size_t a = 0; a < one.lighting.size(); ++a) {
    EXPECT_EQ(one.lighting[a].lit_area, two.lighting[a].lit_area);
    EXPECT_EQ(one.lighting[a].lit_fraction, two.lighting[a].lit_fraction);
  }
  ASSERT_EQ(one.fragments.size(), two.fragments.size());
  for (std::size_t a = 0; a < one.fragments.size(); ++a) {
    EXPECT_EQ(one.fragments[a].polygon, two.fragments[a].polygon);
    EXPECT_EQ(one.fragments[a].fragment_id, two.fragments[a].fragment_id);
  }
}

TEST(AnalyticShadows, ConvexSolidsCastTheSameShadowAsTheirFacesOneByOne) {
  // Boxes are found as closed convex solids and cast one hull each. With every face in a mesh
  // of its own no solid is found, and each face casts on its own: two exact routes, one answer.
  Scene solids = make_city(80, 70, 11);
  solids.lights.push_back(directional_light("sun", sun_direction(25, 160)));
  Scene faces;
  add_mesh(faces, "ground", {solids.faces[0].vertices});
  for (std::size_t f = 1; f < solids.faces.size(); ++f)
    add_mesh(faces, "face" + std::to_string(f), {solids.faces[f].vertices});
  faces.lights = solids.lights;
  const ShadowResult a = compute(solids, 2);
  const ShadowResult b = compute(faces, 2);
  ASSERT_EQ(a.lighting.size(), b.lighting.size());
  for (std::size_t i = 0; i < a.lighting.size(); ++i) {
    EXPECT_EQ(a.lighting[i].lit_area, b.lighting[i].lit_area) << "face " << a.lighting[i].face_id;
    EXPECT_EQ(a.lighting[i].lit_fraction, b.lighting[i].lit_fraction);
  }
}

TEST(AnalyticShadows, AreasOnlyModeGivesTheSameAreasWithoutPolygons) {
  Scene scene = make_city(30, 50, 3);
  scene.lights.push_back(directional_light("sun", sun_direction(40, 135)));
  validate_scene(scene);
  ShadowOptions options;
  const ShadowResult full = compute_shadows(scene, options);
  options.polygons = false;
  const ShadowResult areas = compute_shadows(scene, options);
  EXPECT_TRUE(areas.fragments.empty());
  ASSERT_EQ(full.lighting.size(), areas.lighting.size());
  for (std::size_t a = 0; a < full.lighting.size(); ++a)
    EXPECT_EQ(full.lighting[a].lit_area, areas.lighting[a].lit_area);
}

/// Boxes on a ground, three in four turned about their vertical axis: walls stay exactly planar
/// (two vertical edges), so every receiver takes the exact engine's rational route when only
/// areas are asked for.
Scene turned_box_city(std::size_t boxes, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  auto uniform = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-40, -40, 40, 40, 0)});
  std::vector<Polygon3> faces;
  for (std::size_t b = 0; b < boxes; ++b) {
    const glm::dvec3 centre(uniform(-30, 30), uniform(-30, 30), 0);
    const double w = uniform(2, 8), d = uniform(2, 8), h = uniform(2, 20), angle = b % 4 == 0 ? 0.0 : uniform(0, 3.2);
    const double c = std::cos(angle), s = std::sin(angle);
    for (Polygon3 f : box_faces({-w / 2, -d / 2, 0}, {w / 2, d / 2, h})) {
      for (glm::dvec3& p : f) p = centre + glm::dvec3(c * p.x - s * p.y, s * p.x + c * p.y, p.z);
      faces.push_back(f);
    }
  }
  add_mesh(scene, "boxes", faces);
  return scene;
}

TEST(AnalyticShadows, TurnedBoxesGiveTheSameExactAreasOnEveryRoute) {
  // Areas only, a convex solid wholly in front of a receiver casts its outline seen from the
  // light, in order (core/solid_outlines.hpp) where the grid found outlines (as many receivers
  // as solids); with polygons the receiver's exact hull is CGAL's, and with the boxes not
  // receiving there are no outlines and the ground takes the rational hull of every vertex. All
  // three are exact: the same areas to the last bit, low suns included. Two suns lie in the
  // planes of the unturned boxes' walls, whose vertices then project onto their outline's edges:
  // those get no outline and take the hull of every vertex on every route.
  Scene scene = turned_box_city(40, 20261207);
  for (const auto& [elevation, azimuth] : std::vector<std::pair<double, double>>{
           {3, 20}, {17, 135}, {40, 200}, {62, 300}, {85, 90}, {30, 0}, {45, 180}})
    scene.lights.push_back(directional_light("sun", sun_direction(elevation, azimuth)));
  scene.lights.push_back(directional_light("along x", {0.8, 0, 0.6}));
  scene.lights.push_back(directional_light("along y", {0, -0.7, 0.7}));
  validate_scene(scene);
  ShadowOptions options;
  options.threads = 2;
  options.planes = false;
  const ShadowResult polygons = compute_shadows(scene, options);
  options.polygons = false;
  const ShadowResult areas = compute_shadows(scene, options);
  ASSERT_EQ(polygons.lighting.size(), areas.lighting.size());
  std::size_t shadowed = 0;
  for (std::size_t a = 0; a < areas.lighting.size(); ++a) {
    EXPECT_EQ(polygons.lighting[a].lit_area, areas.lighting[a].lit_area)
        << "face " << areas.lighting[a].face_id << " light " << areas.lighting[a].light_id;
    shadowed += areas.lighting[a].faces_light && areas.lighting[a].lit_area < areas.lighting[a].area ? 1 : 0;
  }
  EXPECT_GT(shadowed, areas.lighting.size() / 10);
  Scene ground_only = scene;
  ground_only.meshes[1].receiver = false;
  validate_scene(ground_only);
  const ShadowResult ground = compute_shadows(ground_only, options);
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    ASSERT_NE(ground.find(0, l), nullptr);
    EXPECT_EQ(ground.find(0, l)->lit_area, areas.find(0, l)->lit_area) << "light " << l;
    EXPECT_LT(ground.find(0, l)->lit_area, ground.find(0, l)->area);
  }
}

TEST(AnalyticShadows, EngineReusesOneSceneForManySunPositions) {
  Scene scene = square_over_ground(directional_light("sun", {0, 0, 1}));
  validate_scene(scene);
  const ShadowEngine engine(scene);
  for (double x : {-1.0, 0.0, 0.5, 2.0}) {
    const ShadowResult r = engine.compute(directional_light("sun", {x, 0, 1}), 0);
    EXPECT_EQ(r.find(0, 0)->shadow_area, 1.0) << x;
  }
  EXPECT_EQ(engine.face_area(0), 100.0);
}

// ShadowStats::operator+= adds every counter (the engine sums its workers' counts with it).
TEST(ShadowStats, PlusEqualsAddsEveryCounter) {
  ShadowStats a;
  a.receivers = 1;
  a.back_facing = 2;
  a.candidate_pairs = 3;
  a.casting_pairs = 4;
  a.unshadowed = 5;
  a.fast_exact_fallbacks = 6;
  a.fast_collapsed = 7;
  a.tiled_receivers = 8;
  a.tiles = 9;
  a.item_seconds = 0.5;
  a.longest_item_seconds = 0.25;
  ShadowStats b = a;
  b += a;
  b += ShadowStats{};
  ShadowStats longer;
  longer.longest_item_seconds = 0.375;
  ShadowStats c = a;
  c += longer;
  EXPECT_EQ(b.receivers, 2u);
  EXPECT_EQ(b.back_facing, 4u);
  EXPECT_EQ(b.candidate_pairs, 6u);
  EXPECT_EQ(b.casting_pairs, 8u);
  EXPECT_EQ(b.unshadowed, 10u);
  EXPECT_EQ(b.fast_exact_fallbacks, 12u);
  EXPECT_EQ(b.fast_collapsed, 14u);
  EXPECT_EQ(b.tiled_receivers, 16u);
  EXPECT_EQ(b.tiles, 18u);
  EXPECT_EQ(b.item_seconds, 1.0);
  EXPECT_EQ(b.longest_item_seconds, 0.25);  // the longest item: a maximum, not a sum
  EXPECT_EQ(c.longest_item_seconds, 0.375);
}

// The total over threads equals the single-threaded count (the workers' stats summed with +=).
TEST(ShadowStats, ThreadsSumToTheSingleThreadedCounts) {
  Scene scene = square_over_ground(directional_light("sun", {0.3, 0.2, 1.0}));
  const ShadowStats one = compute(scene, 1).stats;
  const ShadowStats four = compute(scene, 4).stats;
  EXPECT_GT(one.receivers, 0u);
  EXPECT_EQ(four.receivers, one.receivers);
  EXPECT_EQ(four.back_facing, one.back_facing);
  EXPECT_EQ(four.candidate_pairs, one.candidate_pairs);
  EXPECT_EQ(four.casting_pairs, one.casting_pairs);
  EXPECT_EQ(four.unshadowed, one.unshadowed);
}

}  // namespace
}  // namespace shadow::test
