// SPDX-License-Identifier: GPL-3.0-or-later
// The hard cases of numerical stability (architecture.md, "Hard cases"), one named test each.
//
// Where an exact answer exists it is checked exactly: the engine computes areas as exact
// rationals from the input doubles and rounds each once to the nearest double, so when the
// exact answer is a double (1.0, 2.25, 12 * 1e-6 computed by one IEEE operation on exact
// inputs, ...) the test uses EXPECT_EQ. Irrational answers (sqrt 2) are compared with the
// correctly rounded double (IEEE sqrt) or, where the reference itself takes two roundings,
// within two ulps. Where no closed form exists, two independent methods must agree: the
// double-precision ray caster on points sampled inside the fragments, fragment areas adding up
// to the face area, and lit areas that never grow when an occluder is added.
#include "support/polygon_tools.hpp"
#include "support/ray_caster.hpp"
#include "support/scene_builders.hpp"

#include <shadow/shadow.hpp>
#include <shadow/testing/gtest.hpp>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace shadow::test {
namespace {

constexpr double kPi = 3.14159265358979323846;
/// Two ulps relative: the tolerance for a reference value that is itself rounded twice.
constexpr double kTwoUlps = 4.5e-16;

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

ShadowResult compute(Scene& scene, unsigned threads = 1, bool polygons = true) {
  validate_scene(scene);
  ShadowOptions options;
  options.threads = threads;
  options.polygons = polygons;
  return compute_shadows(scene, options);
}

/// The lighting of (face, light); throws (and so fails the test) when it was not computed.
const FaceLighting& at(const ShadowResult& r, std::size_t face, std::size_t light = 0) {
  const FaceLighting* fl = r.find(face, light);
  if (fl == nullptr)
    throw std::out_of_range("no lighting for face " + std::to_string(face) + " light " +
                            std::to_string(light));
  return *fl;
}

/// Sum of fragment areas of (face, light); lit: 1 lit only, 0 shadowed only, -1 all.
double fragment_area(const ShadowResult& r, std::size_t face, std::size_t light, int lit) {
  double sum = 0;
  for (const Fragment& f : r.fragments)
    if (f.face_id == face && f.light_id == light && (lit < 0 || f.lit == (lit == 1))) sum += f.area;
  return sum;
}

/// Distinct fragment_ids (connected regions) of (face, light) that are lit (or shadowed).
std::set<std::size_t> regions(const ShadowResult& r, std::size_t face, std::size_t light, bool lit) {
  std::set<std::size_t> ids;
  for (const Fragment& f : r.fragments)
    if (f.face_id == face && f.light_id == light && f.lit == lit) ids.insert(f.fragment_id);
  return ids;
}

/// Every (face, light) entry: lit + shadow = area (each rounded once from exact values), the
/// fragments add up to the face and the lit ones to lit_area, every fragment's polygon has its
/// stated area and the face's orientation (libshadow::testing's check_partition).
void expect_fragments_tile_faces(const Scene& scene, const ShadowResult& r) {
  EXPECT_PRED_FORMAT2(shadow::testing::Partitions, scene, r);
}

struct RayTally {
  int decided = 0;
  int disagreements = 0;
  std::string first;  ///< the first disagreement, for the failure message
};

/// Casts the independent double-precision shadow ray from points sampled inside every fragment
/// (at least `margin` from its boundary) and counts where it contradicts the fragment's lit flag.
RayTally check_with_rays(const Scene& scene, const ShadowResult& r, int per_fragment, double margin,
                         std::uint64_t seed = 1) {
  RayTally tally;
  std::mt19937_64 rng(seed);
  for (const Fragment& f : r.fragments) {
    for (const glm::dvec3& p : sample_interior(f.polygon, per_fragment, margin, rng)) {
      const RayVerdict v = cast_shadow_ray(scene, f.face_id, p, scene.lights[f.light_id], margin);
      if (v == RayVerdict::Unsure) continue;
      ++tally.decided;
      if ((v == RayVerdict::Lit) != f.lit) {
        if (tally.disagreements++ == 0) {
          std::ostringstream out;
          out.precision(17);
          out << "face " << f.face_id << " light " << f.light_id << " point (" << p.x << ", " << p.y
              << ", " << p.z << "): fragment says " << (f.lit ? "lit" : "shadowed")
              << ", the ray says " << (v == RayVerdict::Lit ? "lit" : "shadowed");
          tally.first = out.str();
        }
      }
    }
  }
  return tally;
}

#define EXPECT_RAYS_AGREE(scene, result, per_fragment, margin, min_decided)             \
  do {                                                                                   \
    const RayTally tally_ = check_with_rays(scene, result, per_fragment, margin);        \
    EXPECT_EQ(tally_.disagreements, 0) << tally_.first;                                  \
    EXPECT_GE(tally_.decided, min_decided) << "too few points decided by the ray caster"; \
  } while (0)

Polygon3 reversed(Polygon3 p) {
  std::reverse(p.begin(), p.end());
  return p;
}

/// A straight strip of half-width vector `half` (horizontal, to the left of start -> end) whose
/// height rises linearly from z_start to z_end: an exactly planar parallelogram facing up.
Polygon3 slanted_strip(glm::dvec2 start, glm::dvec2 end, glm::dvec2 half, double z_start, double z_end) {
  return {{start.x - half.x, start.y - half.y, z_start},
          {end.x - half.x, end.y - half.y, z_end},
          {end.x + half.x, end.y + half.y, z_end},
          {start.x + half.x, start.y + half.y, z_start}};
}

/// Three strips around the triangle (0,0), (4,0), (0,4), each extended 1 (in its own direction)
/// past both corners and rising from z = 1 to z = 2: at every corner the strip arriving (high
/// end) lies above the strip leaving (low end), so 0 is over 1, 1 over 2 and 2 over 0. No depth
/// order exists. All coordinates are small binary fractions: every strip is exactly planar.
std::vector<Polygon3> cyclic_strips() {
  return {
      slanted_strip({-1, 0}, {5, 0}, {0, 0.5}, 1, 2),          // along +x
      slanted_strip({5, -1}, {-1, 5}, {-0.5, -0.5}, 1, 2),     // along the diagonal
      slanted_strip({0, 5}, {0, -1}, {0.5, 0}, 1, 2),          // along -y
  };
}

// ---------------------------------------------------------------------------------------------
// Grazing light
// ---------------------------------------------------------------------------------------------

TEST(GrazingLight, SunAtOneHundredthOfADegreeCastsTheExactElevenKilometreShadowOfABox) {
  // Hard: the projection divides by sin(0.01 deg) ~ 1.7e-4; the shadow is 10^4 box heights long.
  const double e = 0.01 * kPi / 180.0;
  const glm::dvec3 to_light(std::cos(e), 0.0, std::sin(e));
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-12000, -10, 10, 10, 0)});
  add_mesh(scene, "box", box_faces({0, 0, 0}, {1, 1, 2}));
  scene.lights.push_back(directional_light("sun", to_light));
  const ShadowResult r = compute(scene);

  // Footprint plus the 1 m wide roof swept 2 x / z toward -x, from the light's own doubles.
  // The long double reference carries 64 bits: it may differ from the correctly rounded value
  // by one rounding, hence two ulps.
  const long double sweep = 2.0L * static_cast<long double>(to_light.x) / to_light.z;
  const double expected = static_cast<double>(1.0L + sweep);
  EXPECT_NEAR(at(r, 0).shadow_area, expected, kTwoUlps * expected);
  EXPECT_GT(expected, 11459.0);
  EXPECT_TRUE(at(r, 0).faces_light);
  EXPECT_EQ(at(r, 1).lit_fraction, 1.0);  // top: grazing, nothing in front
  EXPECT_FALSE(at(r, 2).faces_light);     // bottom
  EXPECT_FALSE(at(r, 3).faces_light);     // south: edge-on (to_light.y == 0)
  EXPECT_FALSE(at(r, 4).faces_light);     // north: edge-on
  EXPECT_EQ(at(r, 5).lit_area, 2.0);      // east faces the sun
  EXPECT_EQ(at(r, 6).shadow_area, 2.0);   // west: attached shadow
  expect_fragments_tile_faces(scene, r);
  EXPECT_RAYS_AGREE(scene, r, 30, 1e-6, 20);
}

TEST(GrazingLight, WallExactlyParallelToTheSunIsEdgeOnAndCastsNoShadowOnTheGround) {
  // Hard: the wall's projection is a segment (zero area); n . d is exactly 0 for the wall.
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  const Polygon3 wall{{0, 0, 0}, {2, 2, 0}, {2, 2, 3}, {0, 0, 3}};  // the vertical plane x = y
  add_mesh(scene, "wall", {wall, reversed(wall)});                   // both sides
  scene.lights.push_back(directional_light("sun", {1, 1, 1}));
  scene.lights.push_back(directional_light("low sun", {-2, -2, 0.5}));
  const ShadowResult r = compute(scene);
  for (std::size_t light : {0u, 1u}) {
    SCOPED_TRACE("light " + std::to_string(light));
    EXPECT_EQ(at(r, 0, light).shadow_area, 0.0);
    EXPECT_EQ(at(r, 0, light).lit_area, 100.0);
    for (std::size_t face : {1u, 2u}) {
      EXPECT_FALSE(at(r, face, light).faces_light) << "face " << face;
      EXPECT_EQ(at(r, face, light).lit_area, 0.0);
      EXPECT_EQ(at(r, face, light).shadow_area, at(r, face, light).area);
    }
  }
  EXPECT_EQ(r.stats.casting_pairs, 0u);
  expect_fragments_tile_faces(scene, r);
}

TEST(GrazingLight, WallOneMicroradianOffParallelCastsASliverOfExactArea) {
  // Hard: n . d = 1e-6; the shadow is a 3e-6 wide parallelogram 4 long.
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  const Polygon3 south{{0, 0, 0}, {4, 0, 0}, {4, 0, 3}, {0, 0, 3}};  // front -y
  add_mesh(scene, "wall", {south, reversed(south)});
  scene.lights.push_back(directional_light("sun", {1, 1e-6, 1}));
  const ShadowResult r = compute(scene);
  // The wall (x in [0, 4], z in [0, 3]) moves by -(1, 1e-6) z: base 4, height 3e-6.
  EXPECT_EQ(at(r, 0).shadow_area, 12.0 * 1e-6);
  EXPECT_FALSE(at(r, 1).faces_light);  // front -y looks away by 1e-6
  EXPECT_EQ(at(r, 1).shadow_area, 12.0);
  EXPECT_TRUE(at(r, 2).faces_light);   // front +y: grazing but lit
  EXPECT_EQ(at(r, 2).lit_area, 12.0);  // its coincident twin lies in its plane: casts nothing
  expect_fragments_tile_faces(scene, r);
}

TEST(GrazingLight, SunOnTheHorizonLeavesTheGroundInAttachedShadowAndStillCastsBetweenWalls) {
  // Hard: the ground is exactly edge-on, and its projection onto walls is a line.
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "tall", box_faces({0, 0, 0}, {1, 1, 2}));
  add_mesh(scene, "small", box_faces({3, 0.25, 0}, {4, 0.75, 1}));
  scene.lights.push_back(directional_light("sun", {1, 0, 0}));
  const ShadowResult r = compute(scene);
  EXPECT_FALSE(at(r, 0).faces_light);
  EXPECT_EQ(at(r, 0).shadow_area, 100.0);
  EXPECT_FALSE(at(r, 1).faces_light);   // tall top: edge-on
  // The tall box's east wall (1 x 2) loses the small box's 0.5 x 1 cross-section.
  EXPECT_EQ(at(r, 5).shadow_area, 0.5);
  EXPECT_EQ(at(r, 5).lit_area, 1.5);
  EXPECT_EQ(at(r, 11).lit_fraction, 1.0);  // small box's east wall
  EXPECT_EQ(at(r, 12).lit_fraction, 0.0);  // small box's west wall: back to the sun
  expect_fragments_tile_faces(scene, r);
}

TEST(GrazingLight, SunAlmostOnTheHorizonStretchesTheShadowAcrossTheWholeGround) {
  // Hard: elevations of 1e-300 and of a denormal: the exact shift l_x / s~(l) is ~1e300 (or
  // ~1e323), and only the clip to the receiver keeps the shadow finite.
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "box", box_faces({0, 0, 0}, {1, 1, 2}));
  scene.lights.push_back(directional_light("sun", {1, 0, 1e-300}));
  scene.lights.push_back(directional_light("sun", {1, 0, std::numeric_limits<double>::denorm_min()}));
  const ShadowResult r = compute(scene);
  for (std::size_t light : {0u, 1u}) {
    SCOPED_TRACE("light " + std::to_string(light));
    EXPECT_TRUE(at(r, 0, light).faces_light);
    EXPECT_EQ(at(r, 0, light).shadow_area, 6.0);  // x in [-5, 1], y in [0, 1]
    EXPECT_EQ(at(r, 5, light).lit_area, 2.0);     // east wall
    EXPECT_EQ(at(r, 1, light).lit_area, 1.0);     // roof: grazing, nothing in front
  }
  expect_fragments_tile_faces(scene, r);
}

TEST(GrazingLight, SunVectorsOfAnyScaleGiveTheSameShadow) {
  // Hard: to_light need not be unit length; squaring 1e-200 (or a denormal) underflows and 1e200
  // overflows, so a double-precision normalisation (as used for culling) breaks these valid
  // directions into infinities or a zero vector.
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "box", box_faces({0, 0, 0}, {1, 1, 2}));
  add_mesh(scene, "square", {rectangle_z(-3, -3, -2, -2, 1)});
  for (const double scale : {1.0, 1e-200, 1e200, 0x1p-1070})
    scene.lights.push_back(directional_light("sun", glm::dvec3(1, 0.5, 1) * scale));
  const ShadowResult r = compute(scene);
  // Box: footprint 1 plus the roof swept 2 (1, 0.5): 1 + 2 (1 + 0.5); the square casts 1 more.
  for (std::size_t light = 0; light < scene.lights.size(); ++light) {
    std::ostringstream name;
    name << "to_light (1, 0.5, 1) x " << scene.lights[light].to_light.x;
    SCOPED_TRACE(name.str());
    EXPECT_EQ(at(r, 0, light).shadow_area, 5.0);
    for (std::size_t face = 0; face < scene.faces.size(); ++face) {
      EXPECT_EQ(at(r, face, light).lit_area, at(r, face, 0).lit_area) << "face " << face;
      EXPECT_EQ(at(r, face, light).faces_light, at(r, face, 0).faces_light) << "face " << face;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Shared edges and coincident faces
// ---------------------------------------------------------------------------------------------

TEST(SharedAndCoincidentFaces, StackedBoxesShadowTheLowerRoofByExactlyItsArea) {
  // Hard: the lower roof is coincident with the upper floor (opposite fronts), and the upper
  // walls stand on the receiver's plane: only the upper roof and walls may cast.
  Scene scene;
  add_mesh(scene, "lower", box_faces({0, 0, 0}, {2, 2, 1}));
  add_mesh(scene, "upper", box_faces({0, 0, 1}, {2, 2, 2}));
  scene.lights.push_back(directional_light("overhead", {0, 0, 1}));
  scene.lights.push_back(directional_light("oblique", {1, 0.5, 1}));
  const ShadowResult r = compute(scene);
  for (std::size_t light : {0u, 1u}) {
    SCOPED_TRACE("light " + std::to_string(light));
    EXPECT_TRUE(at(r, 0, light).faces_light);
    EXPECT_EQ(at(r, 0, light).shadow_area, 4.0);
    EXPECT_EQ(at(r, 0, light).lit_area, 0.0);
    EXPECT_FALSE(at(r, 7, light).faces_light);  // upper floor looks down
    EXPECT_EQ(at(r, 6, light).lit_area, 4.0);   // upper roof
  }
  // Under the oblique sun the lower east wall (2 x 1) has nothing in front of it.
  EXPECT_EQ(at(r, 4, 1).lit_area, 2.0);
  expect_fragments_tile_faces(scene, r);
}

TEST(SharedAndCoincidentFaces, SmallerBoxOnABoxShadowsTheRoofBelowByAKnownArea) {
  // Hard: the upper box's floor lies inside the lower roof; its walls start on that plane.
  Scene scene;
  add_mesh(scene, "lower", box_faces({0, 0, 0}, {2, 2, 1}));
  add_mesh(scene, "upper", box_faces({0.5, 0.5, 1}, {1.5, 1.5, 2}));
  scene.lights.push_back(directional_light("overhead", {0, 0, 1}));
  scene.lights.push_back(directional_light("oblique", {1, 0, 1}));
  const ShadowResult r = compute(scene);
  EXPECT_EQ(at(r, 0, 0).shadow_area, 1.0);
  // Footprint swept 1 toward -x: [-0.5, 1.5] x [0.5, 1.5], clipped to x >= 0.
  EXPECT_EQ(at(r, 0, 1).shadow_area, 1.5);
  EXPECT_EQ(at(r, 0, 1).lit_area, 2.5);
  expect_fragments_tile_faces(scene, r);
  EXPECT_RAYS_AGREE(scene, r, 20, 1e-6, 20);
}

TEST(SharedAndCoincidentFaces, BoxRestingOnTheGroundShadowsExactlyItsFootprint) {
  // Hard: the box's floor is coincident with the ground (opposite fronts); the walls share the
  // ground's plane along their bottom edges.
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "box", box_faces({1, -1, 0}, {3, 2, 1.5}));
  scene.lights.push_back(directional_light("overhead", {0, 0, 1}));
  scene.lights.push_back(directional_light("oblique", {1, 0.5, 1}));
  const ShadowResult r = compute(scene);
  EXPECT_EQ(at(r, 0, 0).shadow_area, 6.0);
  EXPECT_EQ(at(r, 0, 0).lit_area, 94.0);
  EXPECT_EQ(at(r, 0, 0).lit_fraction, 0.94);
  // Footprint 2 x 3 plus the roof swept by 1.5 (1, 0.5): 6 + 1.5 (3 + 0.5 x 2).
  EXPECT_EQ(at(r, 0, 1).shadow_area, 12.0);
  EXPECT_FALSE(at(r, 2, 0).faces_light);  // the floor
  expect_fragments_tile_faces(scene, r);
  EXPECT_RAYS_AGREE(scene, r, 20, 1e-6, 20);
}

TEST(SharedAndCoincidentFaces, FloorAndWallsStandingOnTheGroundCastNothingUnderAnOverheadSun) {
  // Hard: every caster lies in the receiver's plane or is edge-on: all projections are empty.
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  std::vector<Polygon3> open_box = box_faces({0, 0, 0}, {2, 2, 1});
  open_box.erase(open_box.begin());  // no roof
  add_mesh(scene, "open box", open_box);
  scene.lights.push_back(directional_light("overhead", {0, 0, 1}));
  const ShadowResult r = compute(scene);
  EXPECT_EQ(at(r, 0).lit_area, 100.0);
  EXPECT_EQ(at(r, 0).lit_fraction, 1.0);
  EXPECT_EQ(r.stats.casting_pairs, 0u);
}

TEST(SharedAndCoincidentFaces, CoincidentFacesFacingTheSameWayDoNotShadowEachOther) {
  // Hard: the receivers share their plane with the casters exactly (all signs are zero).
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "mats", {rectangle_z(0, 0, 1, 1, 0), rectangle_z(0, 0, 1, 1, 0)});
  add_mesh(scene, "panels", {rectangle_z(0, 0, 1, 1, 2), rectangle_z(0.5, 0, 1.5, 1, 2)});
  scene.lights.push_back(directional_light("overhead", {0, 0, 1}));
  scene.lights.push_back(directional_light("oblique", {1, 0.5, 1}));
  scene.lights.push_back(point_light("lamp", {0.3, 0.2, 4}));
  const ShadowResult r = compute(scene);
  for (std::size_t light : {0u, 1u, 2u}) {
    SCOPED_TRACE("light " + std::to_string(light));
    EXPECT_EQ(at(r, 3, light).lit_fraction, 1.0);  // overlapping coplanar panels
    EXPECT_EQ(at(r, 4, light).lit_fraction, 1.0);
  }
  // Overhead: the mats lie under the first panel; the ground under the union of the panels.
  EXPECT_EQ(at(r, 1, 0).lit_area, 0.0);
  EXPECT_EQ(at(r, 2, 0).lit_area, 0.0);
  EXPECT_EQ(at(r, 0, 0).shadow_area, 1.5);
  // Oblique: the panels (height 2) move by (-2, -1): the mats are clear and fully lit.
  EXPECT_EQ(at(r, 1, 1).lit_fraction, 1.0);
  EXPECT_EQ(at(r, 2, 1).lit_fraction, 1.0);
  EXPECT_EQ(at(r, 0, 1).shadow_area, 1.5);
  // The lamp at height 4 over the panels at 2 doubles their shadow on the ground: 4 x 1.5.
  EXPECT_EQ(at(r, 0, 2).shadow_area, 6.0);
  expect_fragments_tile_faces(scene, r);
  EXPECT_RAYS_AGREE(scene, r, 20, 1e-6, 40);
}

TEST(SharedAndCoincidentFaces, CasterTriangulatedIntoAFanLeavesNoCracksInItsShadow) {
  // Hard: eight triangles share edges and a centre vertex; in doubles their projections leave
  // cracks or overlaps along the shared edges. The receiver is split along a shared edge too.
  const glm::dvec3 c(0.5, 0.5, 1);
  const Polygon3 ring{{0, 0, 1}, {0.5, 0, 1}, {1, 0, 1}, {1, 0.5, 1},
                      {1, 1, 1}, {0.5, 1, 1}, {0, 1, 1}, {0, 0.5, 1}};
  std::vector<Polygon3> fan;
  for (std::size_t a = 0; a < ring.size(); ++a) fan.push_back({c, ring[a], ring[(a + 1) % ring.size()]});
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 0.5, 5, 0), rectangle_z(0.5, -5, 5, 5, 0)});
  add_mesh(scene, "fan", fan);
  scene.lights.push_back(directional_light("sun", {0.25, 0.75, 1}));
  scene.lights.push_back(point_light("lamp", {0.5, 0.5, 3}));
  const ShadowResult r = compute(scene);
  // The square moves to [-0.25, 0.75] x [-0.75, 0.25]: 0.75 left of x = 0.5, 0.25 right of it.
  EXPECT_EQ(at(r, 0, 0).shadow_area, 0.75);
  EXPECT_EQ(at(r, 1, 0).shadow_area, 0.25);
  EXPECT_EQ(regions(r, 0, 0, false).size(), 1u);  // one shadow, no cracks
  EXPECT_EQ(regions(r, 0, 0, true).size(), 1u);
  // The lamp scales the square by 3/2 about (0.5, 0.5): 2.25, split in half by x = 0.5.
  EXPECT_EQ(at(r, 0, 1).shadow_area, 1.125);
  EXPECT_EQ(at(r, 1, 1).shadow_area, 1.125);
  EXPECT_EQ(regions(r, 1, 1, false).size(), 1u);
  expect_fragments_tile_faces(scene, r);
}

TEST(SharedAndCoincidentFaces, TJunctionVerticesOnSharedEdgesChangeNothing) {
  // Hard: a vertex in the middle of an edge (collinear, a T-junction with the neighbours) gives
  // zero-length turns that charts, convex pieces and unions must tolerate.
  Scene scene;
  // Two receivers sharing the edge x = 1; the left one has extra vertices on it and on its base.
  add_mesh(scene, "floor", {{{0, 0, 0}, {0.5, 0, 0}, {1, 0, 0}, {1, 0.25, 0}, {1, 1, 0}, {0, 1, 0}},
                            rectangle_z(1, 0, 2, 1, 0)});
  // Two casters sharing the edge y = 0.5 with a T-junction: the upper one is split at x = 1.
  add_mesh(scene, "casters", {{{0, 0, 1}, {2, 0, 1}, {2, 0.5, 1}, {1, 0.5, 1}, {0, 0.5, 1}},
                              rectangle_z(0, 0.5, 1, 0.75, 1), rectangle_z(1, 0.5, 2, 0.75, 1)});
  scene.lights.push_back(directional_light("overhead", {0, 0, 1}));
  scene.lights.push_back(directional_light("oblique", {0, 0.25, 1}));
  const ShadowResult r = compute(scene);
  EXPECT_EQ(at(r, 0, 0).area, 1.0);
  EXPECT_EQ(at(r, 0, 0).shadow_area, 0.75);  // [0, 1] x [0, 0.75]
  EXPECT_EQ(at(r, 1, 0).shadow_area, 0.75);
  // Oblique: the casters move by (0, -0.25): [0, 1] x [-0.25, 0.5] on each receiver.
  EXPECT_EQ(at(r, 0, 1).shadow_area, 0.5);
  EXPECT_EQ(at(r, 1, 1).shadow_area, 0.5);
  EXPECT_EQ(regions(r, 0, 1, false).size(), 1u);
  expect_fragments_tile_faces(scene, r);
  EXPECT_RAYS_AGREE(scene, r, 20, 1e-6, 30);
}

TEST(SharedAndCoincidentFaces, BoxesSideBySideSeeTheirSharedWallOnlyFromInside) {
  // Hard: two coincident walls with opposite fronts; the lit one is enclosed by its neighbour.
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "a", box_faces({0, 0, 0}, {1, 1, 1}));
  add_mesh(scene, "b", box_faces({1, 0, 0}, {2, 1, 1}));
  scene.lights.push_back(directional_light("sun", {1, 0.5, 2}));
  scene.lights.push_back(directional_light("overhead", {0, 0, 1}));
  const ShadowResult r = compute(scene);
  // a's east wall (face 5) faces the sun but every ray from it runs through b.
  EXPECT_TRUE(at(r, 5, 0).faces_light);
  EXPECT_EQ(at(r, 5, 0).shadow_area, 1.0);
  EXPECT_EQ(at(r, 5, 0).lit_area, 0.0);
  EXPECT_FALSE(at(r, 12, 0).faces_light);  // b's west wall
  // The joint box [0,2] x [0,1] x [0,1] swept by (-0.5, -0.25): 2 + 0.5 x 1 + 0.25 x 2.
  EXPECT_EQ(at(r, 0, 0).shadow_area, 3.0);
  EXPECT_EQ(at(r, 0, 1).shadow_area, 2.0);
  // The coplanar roofs share an edge and are both fully lit.
  EXPECT_EQ(at(r, 1, 0).lit_fraction, 1.0);
  EXPECT_EQ(at(r, 7, 0).lit_fraction, 1.0);
  expect_fragments_tile_faces(scene, r);
  EXPECT_RAYS_AGREE(scene, r, 20, 1e-6, 40);
}

// ---------------------------------------------------------------------------------------------
// Interpenetration and cyclic overlap
// ---------------------------------------------------------------------------------------------

TEST(Interpenetration, TwoQuadsCrossingLikeAnXHaveTheLitAreasComputedByHand) {
  // Hard: each quad is partly in front of and partly behind the other; neither is "above".
  Scene scene;
  add_mesh(scene, "a", {{{0, 0, 0}, {2, 0, 2}, {2, 1, 2}, {0, 1, 0}}});  // z = x, front (-1, 0, 1)
  add_mesh(scene, "b", {{{0, 0, 2}, {2, 0, 0}, {2, 1, 0}, {0, 1, 2}}});  // z = 2 - x, front (1, 0, 1)
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  scene.lights.push_back(directional_light("sun", {0.5, 0, 1}));
  const ShadowResult r = compute(scene);
  // On a, b's upper-left arm (x < 1) projects to a's x in [-2, 1]: a's half x < 1 is shadowed.
  // a's area is 2 sqrt 2: both halves are sqrt 2, correctly rounded by IEEE sqrt.
  EXPECT_EQ(at(r, 0).lit_area, std::sqrt(2.0));
  EXPECT_EQ(at(r, 0).shadow_area, std::sqrt(2.0));
  EXPECT_EQ(at(r, 0).lit_fraction, 0.5);
  // On b, a's upper-right arm (x > 1) projects to b's x in (1, 4/3]: a third of a unit of x.
  EXPECT_EQ(at(r, 1).lit_fraction, 5.0 / 6.0);
  EXPECT_NEAR(at(r, 1).shadow_area, std::sqrt(2.0) / 3.0, kTwoUlps);
  EXPECT_NEAR(at(r, 1).lit_area, 5.0 * std::sqrt(2.0) / 3.0, 2 * kTwoUlps);
  // On the ground: a covers x in [0, 1], b covers x in [-1, 2].
  EXPECT_EQ(at(r, 2).shadow_area, 3.0);
  expect_fragments_tile_faces(scene, r);
  EXPECT_RAYS_AGREE(scene, r, 40, 1e-6, 60);
}

TEST(Interpenetration, BoxSunkHalfwayIntoTheGroundCastsOnlyFromAboveIt) {
  // Hard: the ground cuts every wall; the half below the ground must neither cast on the ground
  // nor be lit, and the ground itself shadows the buried half of the sunlit wall.
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "box", box_faces({0, 0, -1}, {1, 1, 1}));
  scene.lights.push_back(directional_light("sun", {1, 0, 1}));
  const ShadowResult r = compute(scene);
  EXPECT_EQ(at(r, 0).shadow_area, 2.0);  // footprint 1 plus the upper half swept by 1
  EXPECT_EQ(at(r, 5).shadow_area, 1.0);  // east wall: the buried half, under the ground
  EXPECT_EQ(at(r, 5).lit_area, 1.0);
  EXPECT_EQ(at(r, 1).lit_area, 1.0);     // top
  expect_fragments_tile_faces(scene, r);
  EXPECT_RAYS_AGREE(scene, r, 20, 1e-6, 20);
}

TEST(Interpenetration, ThreeStripsInCyclicOverlapHaveNoDepthOrderYetExactShadows) {
  // Hard: 0 is over 1, 1 over 2 and 2 over 0: no painter's order exists.
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-10, -10, 10, 10, 0)});
  add_mesh(scene, "strips", cyclic_strips());
  scene.lights.push_back(directional_light("overhead", {0, 0, 1}));
  const ShadowResult r = compute(scene);
  // Plan areas: strips 6, 12, 6; overlaps 1.875 (0 over 1), 1.875 (1 over 2), 1 (2 over 0).
  EXPECT_EQ(at(r, 0).shadow_area, 6 + 12 + 6 - 1.875 - 1.875 - 1.0);
  // Charts are the plan view, so lit fractions are ratios of plan areas.
  EXPECT_EQ(at(r, 1).lit_fraction, 5.0 / 6.0);      // under strip 2 over 1 of 6
  EXPECT_EQ(at(r, 2).lit_fraction, 1 - 1.875 / 12);  // under strip 0 over 1.875 of 12
  EXPECT_EQ(at(r, 3).lit_fraction, 1 - 1.875 / 6);   // under strip 1 over 1.875 of 6
  EXPECT_NEAR(at(r, 1).shadow_area, std::sqrt(37.0) / 6, kTwoUlps);  // slope 1/6: sqrt(37)/6
  expect_fragments_tile_faces(scene, r);
  EXPECT_RAYS_AGREE(scene, r, 20, 1e-6, 40);
}

TEST(Interpenetration, CyclicStripsUnderAnObliqueSunAgreeWithRaysAndOnlyLoseLightToEachOther) {
  // Hard: cyclic overlap under a slanted projection; no closed form, so two methods must agree.
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-10, -10, 10, 10, 0)});
  add_mesh(scene, "strips", cyclic_strips());
  scene.lights.push_back(directional_light("sun", {0.3, -0.2, 1}));
  scene.lights.push_back(point_light("lamp", {1.5, 1.2, 6}));
  const ShadowResult r = compute(scene, /*threads=*/2);
  expect_fragments_tile_faces(scene, r);
  EXPECT_RAYS_AGREE(scene, r, 20, 1e-6, 100);
  for (std::size_t light : {0u, 1u})
    for (std::size_t strip : {1u, 2u, 3u}) {
      EXPECT_GT(at(r, strip, light).shadow_area, 0.0) << "strip " << strip << " light " << light;
      EXPECT_LT(at(r, strip, light).shadow_area, at(r, strip, light).area);
    }
  // Without strip 2 nothing is above strip 0, and no face gains light by adding a strip.
  Scene two;
  add_mesh(two, "ground", {rectangle_z(-10, -10, 10, 10, 0)});
  add_mesh(two, "strips", {cyclic_strips()[0], cyclic_strips()[1]});
  two.lights = scene.lights;
  const ShadowResult r2 = compute(two, /*threads=*/2, /*polygons=*/false);
  for (std::size_t light : {0u, 1u}) {
    for (std::size_t face : {0u, 1u, 2u})
      EXPECT_LE(at(r, face, light).lit_area, at(r2, face, light).lit_area) << face << " " << light;
  }
  EXPECT_EQ(at(r2, 1, 0).lit_fraction, 1.0);
}

// ---------------------------------------------------------------------------------------------
// Slivers and near-degenerate geometry
// ---------------------------------------------------------------------------------------------

TEST(Slivers, OccluderOneNanometreWideCastsExactlyItsArea) {
  // Hard: the shadow is 1e-9 wide, ten orders of magnitude below the receiver's size.
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "sliver", {rectangle_z(0, 0, 1e-9, 1, 1)});
  // A diagonal sliver: (2,0) (3,1) (3, 1+1e-9) (2, 1e-9), rounded as doubles (a trapezoid).
  const double top = 1.0 + 1e-9;
  add_mesh(scene, "diagonal", {{{2, 0, 1}, {3, 1, 1}, {3, top, 1}, {2, 1e-9, 1}}});
  scene.lights.push_back(directional_light("overhead", {0, 0, 1}));
  scene.lights.push_back(directional_light("oblique", {1, 0.5, 1}));
  const ShadowResult r = compute(scene);
  // Trapezoid: parallel vertical sides 1e-9 and (top - 1) (exact in double), width 1.
  const long double diagonal = (static_cast<long double>(1e-9) + (top - 1.0)) / 2;
  // Both sums are exact in long double's 64 bits: the casts round once.
  const double expected = static_cast<double>(static_cast<long double>(1e-9) + diagonal);
  for (std::size_t light : {0u, 1u}) {
    SCOPED_TRACE("light " + std::to_string(light));
    EXPECT_EQ(at(r, 0, light).shadow_area, expected);
    EXPECT_EQ(at(r, 1, light).lit_area, 1e-9);
    EXPECT_EQ(at(r, 1, light).area, 1e-9);
    EXPECT_EQ(at(r, 2, light).area, static_cast<double>(diagonal));
  }
  expect_fragments_tile_faces(scene, r);
}

TEST(Slivers, VertexOneUlpOffASharedEdgeOpensAGapOfExactlyThatArea) {
  // Hard: two casters should tile a square but one vertex is one ulp off the shared edge.
  for (const bool gap : {true, false}) {
    SCOPED_TRACE(gap ? "one ulp apart" : "one ulp overlapping");
    const double x = std::nextafter(0.5, gap ? 1.0 : 0.0);
    Scene scene;
    add_mesh(scene, "receiver", {rectangle_z(0, 0, 1, 1, 0)});
    add_mesh(scene, "left", {rectangle_z(0, 0, 0.5, 1, 1)});
    add_mesh(scene, "right", {{{x, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0.5, 1, 1}}});
    scene.lights.push_back(directional_light("overhead", {0, 0, 1}));
    const ShadowResult r = compute(scene);
    if (gap) {
      // The gap is the triangle (0.5, 0) (0.5 + 2^-53, 0) (0.5, 1): area 2^-54.
      const double sliver = std::ldexp(1.0, -54);
      EXPECT_EQ(at(r, 0).lit_area, sliver);
      EXPECT_EQ(at(r, 0).lit_fraction, sliver);
      EXPECT_EQ(at(r, 0).shadow_area, 1.0);  // 1 - 2^-54 rounds (ties to even) to 1
      ASSERT_EQ(regions(r, 0, 0, true).size(), 1u);
      EXPECT_EQ(fragment_area(r, 0, 0, 1), sliver);
    } else {
      EXPECT_EQ(at(r, 0).lit_area, 0.0);
      EXPECT_EQ(at(r, 0).shadow_area, 1.0);
      EXPECT_TRUE(regions(r, 0, 0, true).empty());
    }
  }
}

TEST(Slivers, CasterVertexOneUlpAboveTheReceiverPlaneCastsItsWholeTriangle) {
  // Hard: a triangle lying on the receiver casts nothing; lifting one vertex by one ulp makes
  // it strictly in front, and its shadow is the whole (sheared) triangle.
  for (const bool lifted : {false, true}) {
    SCOPED_TRACE(lifted ? "lifted one ulp" : "lying on the plane");
    Scene scene;
    add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 1)});
    const double z = lifted ? std::nextafter(1.0, 2.0) : 1.0;
    add_mesh(scene, "triangle", {{{0, 0, 1}, {1, 0, 1}, {0, 1, z}}});
    scene.lights.push_back(directional_light("overhead", {0, 0, 1}));
    scene.lights.push_back(directional_light("oblique", {1, 0, 1}));
    const ShadowResult r = compute(scene);
    for (std::size_t light : {0u, 1u}) {
      EXPECT_EQ(at(r, 0, light).shadow_area, lifted ? 0.5 : 0.0) << "light " << light;
      EXPECT_EQ(at(r, 1, light).lit_area, 0.5) << "light " << light;
    }
  }
}

TEST(Slivers, NeedleTriangleWithATenthOfAMicroradianAngleCastsAndReceivesExactly) {
  // Hard: an angle of 1e-7 rad; the needle is 1 long and 1e-7 wide at its base.
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "needle", {{{0, 0, 1}, {1, 0, 1}, {1, 1e-7, 1}}});
  add_mesh(scene, "cover", {rectangle_z(-1, -1, 0.5, 1, 2)});
  scene.lights.push_back(directional_light("overhead", {0, 0, 1}));
  const ShadowResult r = compute(scene);
  EXPECT_EQ(at(r, 1).area, 0.5 * 1e-7);
  // The cover hides the needle's part x <= 0.5: a similar triangle of a quarter of its area.
  EXPECT_EQ(at(r, 1).shadow_area, 0.125 * 1e-7);
  EXPECT_EQ(at(r, 1).lit_fraction, 0.75);
  // The ground: the cover (3) plus the needle's part beyond it (3/8 of 0.5e-7).
  EXPECT_NEAR(at(r, 0).shadow_area, 3.0 + 0.375 * 1e-7, kTwoUlps * 3);
  expect_fragments_tile_faces(scene, r);
}

// ---------------------------------------------------------------------------------------------
// Zero-area faces
// ---------------------------------------------------------------------------------------------

TEST(DegenerateFaces, ZeroAreaFacesKeepTheirIdsButReceiveAndCastNothing) {
  // Hard: collinear faces have no plane; they must neither crash nor shift face numbering.
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "flat", {{{0, 0, 1}, {1, 1, 1}, {2, 2, 1}},                // collinear triangle
                           {{-1, 0, 1}, {0, 0, 1}, {1, 0, 1}, {2, 0, 1}},    // collinear quad
                           {{0, 0, 0.5}, {0, 0, 1.5}, {0, 0, 3}}});          // vertical line
  add_mesh(scene, "square", {rectangle_z(0, 0, 1, 1, 1)});
  scene.lights.push_back(directional_light("overhead", {0, 0, 1}));
  scene.lights.push_back(point_light("lamp", {0.5, 0.5, 3}));
  validate_scene(scene);
  EXPECT_FALSE(scene.faces[0].degenerate);
  EXPECT_TRUE(scene.faces[1].degenerate);
  EXPECT_TRUE(scene.faces[2].degenerate);
  EXPECT_TRUE(scene.faces[3].degenerate);
  EXPECT_FALSE(scene.faces[4].degenerate);
  EXPECT_EQ(scene.warnings.size(), 3u);
  const ShadowResult r = compute(scene);
  ASSERT_EQ(r.lighting.size(), 5u * 2u);
  for (std::size_t face : {1u, 2u, 3u})
    for (std::size_t light : {0u, 1u}) {
      EXPECT_EQ(at(r, face, light).area, 0.0);
      EXPECT_EQ(at(r, face, light).lit_area, 0.0);
      EXPECT_EQ(at(r, face, light).shadow_area, 0.0);
      EXPECT_EQ(at(r, face, light).lit_fraction, 0.0);
      EXPECT_FALSE(at(r, face, light).faces_light);
    }
  for (const Fragment& f : r.fragments) EXPECT_FALSE(f.face_id >= 1 && f.face_id <= 3) << f.face_id;
  EXPECT_EQ(at(r, 0, 0).shadow_area, 1.0);   // only the square casts
  EXPECT_EQ(at(r, 0, 1).shadow_area, 2.25);  // scaled by 3 / 2
  EXPECT_EQ(at(r, 4, 0).lit_area, 1.0);      // the square keeps face_id 4
  expect_fragments_tile_faces(scene, r);
}

TEST(DegenerateFaces, NearlyCollinearTriangleIsNotDegenerateAndCastsItsTinyArea) {
  // Hard: 1e-30 off collinear: double-precision tests call it flat, exact ones must not.
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "almost flat", {{{0, 0, 1}, {2, 0, 1}, {1, 1e-30, 1}}});
  scene.lights.push_back(directional_light("overhead", {0, 0, 1}));
  validate_scene(scene);
  EXPECT_FALSE(scene.faces[1].degenerate);
  const ShadowResult r = compute(scene);
  EXPECT_EQ(at(r, 1).area, 1e-30);
  EXPECT_EQ(at(r, 1).lit_area, 1e-30);
  EXPECT_EQ(at(r, 0).shadow_area, 1e-30);
  EXPECT_EQ(at(r, 0).lit_area, 100.0);
}

// ---------------------------------------------------------------------------------------------
// Far from the origin
// ---------------------------------------------------------------------------------------------

Scene square_over_ground_at(glm::dvec3 o) {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(o.x - 5, o.y - 5, o.x + 5, o.y + 5, o.z)});
  add_mesh(scene, "square", {rectangle_z(o.x, o.y, o.x + 1, o.y + 1, o.z + 1)});
  scene.lights.push_back(directional_light("overhead", {0, 0, 1}));
  scene.lights.push_back(directional_light("oblique", {1, 0.5, 1}));
  scene.lights.push_back(point_light("lamp", o + glm::dvec3(0.5, 0.5, 3)));
  return scene;
}

TEST(FarFromOrigin, SquareOverGroundAtAMillionMetresGivesTheSameExactAreasAsAtTheOrigin) {
  // Hard: coordinates of 1e6 and 2e6 leave 2^-33 m resolution; every number here is exact.
  Scene far = square_over_ground_at({1e6, 2e6, 0});
  Scene near = square_over_ground_at({0, 0, 0});
  const ShadowResult rf = compute(far, /*threads=*/2);
  const ShadowResult rn = compute(near);
  EXPECT_EQ(at(rf, 0, 0).shadow_area, 1.0);
  EXPECT_EQ(at(rf, 0, 1).shadow_area, 1.0);
  EXPECT_EQ(at(rf, 0, 2).shadow_area, 2.25);
  EXPECT_EQ(at(rf, 0, 2).lit_area, 97.75);
  ASSERT_EQ(rf.lighting.size(), rn.lighting.size());
  for (std::size_t a = 0; a < rf.lighting.size(); ++a) {
    EXPECT_EQ(rf.lighting[a].area, rn.lighting[a].area) << a;
    EXPECT_EQ(rf.lighting[a].lit_area, rn.lighting[a].lit_area) << a;
    EXPECT_EQ(rf.lighting[a].lit_fraction, rn.lighting[a].lit_fraction) << a;
  }
  expect_fragments_tile_faces(far, rf);
  EXPECT_RAYS_AGREE(far, rf, 20, 1e-6, 40);
}

TEST(FarFromOrigin, CentimetreBoxNearAMillionMetresCastsTheAreaOfItsOwnDoubles) {
  // Hard: 1 cm features at 1e6 m; 1e6 + 0.37 is not 0.37 away from 1e6, so the exact answer is
  // the one of the rounded doubles, whose differences (Sterbenz) and product are exact/IEEE.
  const double x0 = 1e6 + 0.37, x1 = 1e6 + 0.38, y0 = 2e6 + 0.11, y1 = 2e6 + 0.13, h = 0.05;
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(1e6 - 1, 2e6 - 1, 1e6 + 1, 2e6 + 1, 0)});
  add_mesh(scene, "box", box_faces({x0, y0, 0}, {x1, y1, h}));
  scene.lights.push_back(directional_light("overhead", {0, 0, 1}));
  scene.lights.push_back(directional_light("oblique", {1, 0.5, 1}));
  scene.lights.push_back(point_light("lamp", {1e6 + 0.3, 2e6 + 0.2, 0.4}));
  const ShadowResult r = compute(scene);
  const double w = x1 - x0, d = y1 - y0;  // exact
  EXPECT_EQ(at(r, 0, 0).shadow_area, w * d);
  EXPECT_NEAR(w * d, 0.01 * 0.02, 4e-10 * (0.01 + 0.02));  // within an ulp of 1e6 per side
  // Footprint plus the roof swept by h (1, 0.5): w d + h (d + 0.5 w).
  const long double oblique = static_cast<long double>(w) * d + static_cast<long double>(h) * (d + 0.5L * w);
  EXPECT_NEAR(at(r, 0, 1).shadow_area, static_cast<double>(oblique), kTwoUlps * static_cast<double>(oblique));
  EXPECT_EQ(at(r, 1, 0).area, w * d);  // roof
  expect_fragments_tile_faces(scene, r);
  EXPECT_RAYS_AGREE(scene, r, 20, 1e-7, 40);
}

// ---------------------------------------------------------------------------------------------
// Point light placement
// ---------------------------------------------------------------------------------------------

TEST(PointLightPlacement, LightOnAFacesPlaneLeavesItInAttachedShadowAndItCastsNothing) {
  // Hard: s~(l) = 0 exactly for that face; from the light it is seen edge-on.
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "square", {rectangle_z(0, 0, 1, 1, 1), rectangle_z(0, 0, 1, 1, 1, false)});
  scene.lights.push_back(point_light("lamp", {3, 0.5, 1}));
  const ShadowResult r = compute(scene);
  for (std::size_t face : {1u, 2u}) {
    EXPECT_FALSE(at(r, face).faces_light) << face;
    EXPECT_EQ(at(r, face).shadow_area, 1.0) << face;
  }
  EXPECT_EQ(at(r, 0).lit_area, 100.0);
  EXPECT_EQ(at(r, 0).shadow_area, 0.0);
  expect_fragments_tile_faces(scene, r);
}

/// A lamp at (0, 0, 2) over the ground, and one face through the lamp.
Scene lamp_on_face(const Polygon3& face) {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "face", {face});
  scene.lights.push_back(point_light("lamp", {0, 0, 2}));
  return scene;
}

/// Every open segment from the ground to the lamp misses the face (it ends on it), and the face
/// sees the lamp edge-on.
void expect_lamp_on_face_casts_nothing(Scene& scene) {
  const ShadowResult r = compute(scene);
  EXPECT_EQ(at(r, 0).lit_area, 100.0);
  EXPECT_EQ(at(r, 0).shadow_area, 0.0);
  EXPECT_FALSE(at(r, 1).faces_light);
  EXPECT_EQ(at(r, 1).shadow_area, at(r, 1).area);
  expect_fragments_tile_faces(scene, r);
}

TEST(PointLightPlacement, LightInsideALevelFaceCastsNothingFromThatFace) {
  // Hard: the face lies in the plane through the light parallel to the receiver, where the
  // central projection onto the receiver is undefined (the denominator s~ - s vanishes).
  Scene scene = lamp_on_face(rectangle_z(-0.5, -0.5, 0.5, 0.5, 2));
  expect_lamp_on_face_casts_nothing(scene);
}

TEST(PointLightPlacement, LightInsideATiltedFaceCastsNothingFromThatFace) {
  // Hard: the face crosses the light; clipped to the pyramid below the light, it keeps the
  // light itself as a vertex, whose projection is undefined.
  Scene scene = lamp_on_face({{-1, -1, 1.5}, {1, -1, 2.5}, {1, 1, 2.5}, {-1, 1, 1.5}});  // z = 2 + x/2
  expect_lamp_on_face_casts_nothing(scene);
}

TEST(PointLightPlacement, LightOnAnEdgeOfAFaceCastsNothingFromThatFace) {
  // Hard: as above, with the light on the face's boundary (a vertical wall hanging below it).
  Scene scene = lamp_on_face({{-1, 0, 1}, {1, 0, 1}, {1, 0, 2}, {-1, 0, 2}});
  expect_lamp_on_face_casts_nothing(scene);
}

TEST(PointLightPlacement, LightAtAVertexOfAFaceCastsNothingFromThatFace) {
  // Hard: as above, with the light at a corner of a tilted triangle below it.
  Scene scene = lamp_on_face({{0, 0, 2}, {1, 0, 1}, {0, 1, 1.5}});
  expect_lamp_on_face_casts_nothing(scene);
}

TEST(PointLightPlacement, VeryDistantPointLightCastsAlmostTheParallelShadow) {
  // Hard: a lamp 1e12 away: the central projection's scale differs from 1 by 1e-12.
  Scene scene = lamp_on_face(rectangle_z(0, 0, 1, 1, 1));
  scene.lights[0] = point_light("far lamp", {0.5, 0.5, 1e12});
  const ShadowResult r = compute(scene);
  // The unit square at height 1 grows by H / (H - 1) in each direction.
  const long double H = 1e12L, k = H / (H - 1);
  const double expected = static_cast<double>(k * k);
  EXPECT_NEAR(at(r, 0).shadow_area, expected, kTwoUlps * expected);
  EXPECT_GT(at(r, 0).shadow_area, 1.0);
  EXPECT_EQ(at(r, 1).lit_area, 1.0);
}

TEST(PointLightPlacement, LampInsideAClosedBoxDarkensEveryFaceOfTheRoomExactly) {
  // Hard: geometry on all sides of the light: the six projections must tile each room face.
  Scene scene;
  add_mesh(scene, "room", room_faces({0, 0, 0}, {8, 6, 3}));
  add_mesh(scene, "lantern", box_faces({3.5, 2.5, 1}, {4.5, 3.5, 2}));
  scene.lights.push_back(point_light("lamp", {4.1, 2.9, 1.3}));
  const ShadowResult r = compute(scene, /*threads=*/2);
  for (std::size_t face = 0; face < 6; ++face) {
    EXPECT_TRUE(at(r, face).faces_light) << face;
    EXPECT_EQ(at(r, face).lit_area, 0.0) << face;
    EXPECT_EQ(at(r, face).shadow_area, at(r, face).area) << face;
  }
  for (std::size_t face = 6; face < 12; ++face) EXPECT_FALSE(at(r, face).faces_light) << face;
  expect_fragments_tile_faces(scene, r);
}

TEST(PointLightPlacement, LampInAFurnishedRoomLightsEveryInwardFaceAndAgreesWithRays) {
  // Hard: geometry on every side of the lamp, legs and shelves sharing planes and edges.
  Scene scene = make_furnished_room(2, 11);
  const ShadowResult r = compute(scene, /*threads=*/2);
  for (std::size_t face = 0; face < 6; ++face) EXPECT_TRUE(at(r, face).faces_light) << face;
  EXPECT_EQ(at(r, 0).lit_fraction, 1.0);  // the ceiling: nothing between it and the lamp
  EXPECT_LT(at(r, 1).lit_fraction, 1.0);  // the floor: tables and shelves cast on it
  expect_fragments_tile_faces(scene, r);
  EXPECT_RAYS_AGREE(scene, r, 6, 1e-6, 200);
  // The serial path gives the same numbers.
  const ShadowResult serial = compute(scene, /*threads=*/1, /*polygons=*/false);
  ASSERT_EQ(serial.lighting.size(), r.lighting.size());
  for (std::size_t a = 0; a < r.lighting.size(); ++a)
    EXPECT_EQ(serial.lighting[a].lit_area, r.lighting[a].lit_area) << a;
}

TEST(PointLightPlacement, GeometryBehindThePointLightCastsNothing) {
  // Hard: the big square is in front of the ground's plane but beyond the light; projecting it
  // would put its image on the wrong side (or at infinity).
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "below lamp", {rectangle_z(-0.25, -0.25, 0.25, 0.25, 1)});
  add_mesh(scene, "above lamp", {rectangle_z(-1, -1, 1, 1, 3, false)});  // front faces down
  scene.lights.push_back(point_light("lamp", {0, 0, 2}));
  const ShadowResult r = compute(scene);
  EXPECT_EQ(at(r, 0).shadow_area, 1.0);  // only the lower square, scaled by 2: 0.25 x 4
  EXPECT_EQ(at(r, 1).lit_area, 0.25);    // the upper square is behind the lamp from here
  EXPECT_EQ(at(r, 2).lit_area, 4.0);     // and the lower one is behind it from up there
  expect_fragments_tile_faces(scene, r);
  EXPECT_RAYS_AGREE(scene, r, 20, 1e-6, 20);
}

TEST(PointLightPlacement, WallStraddlingTheLampsHeightCastsOnlyFromBelowIt) {
  // Hard: the wall reaches past the lamp's level; its image runs to infinity at that level,
  // and the part above it would project to the opposite side.
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "wall", {{{2, -1, 0.5}, {2, 1, 0.5}, {2, 1, 3}, {2, -1, 3}}});  // plane x = 2
  scene.lights.push_back(point_light("lamp", {0, 0, 2}));
  const ShadowResult r = compute(scene);
  // (2, y, z) maps to (4, 2y) / (2 - z): for z in [0.5, 2) the image is x' >= 8/3,
  // |y'| <= x' / 2, clipped by the ground at x' = 5: area (25 - 64/9) / 2 = 161/18.
  EXPECT_EQ(at(r, 0).shadow_area, 161.0 / 18.0);
  EXPECT_EQ(at(r, 0).lit_area, 1639.0 / 18.0);
  expect_fragments_tile_faces(scene, r);
  EXPECT_RAYS_AGREE(scene, r, 40, 1e-6, 30);
}

TEST(PointLightPlacement, GeometryBelowAReceivingFaceCastsNothingOnIt) {
  // Hard: casters behind the receiver's plane, and a wall crossing it: only its upper half casts.
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(scene, "cellar", {rectangle_z(-2, -2, 2, 2, -1)});
  add_mesh(scene, "wall", {{{2, 0, -1}, {0, 0, -1}, {0, 0, 1}, {2, 0, 1}}});  // front +y
  scene.lights.push_back(directional_light("sun", {0, 1, 1}));
  scene.lights.push_back(point_light("lamp", {0, 0, 4}));
  const ShadowResult r = compute(scene);
  // Sun: the wall's upper half (x in [0, 2], z in [0, 1]) moves by (0, -z): area 2.
  EXPECT_EQ(at(r, 0, 0).shadow_area, 2.0);
  EXPECT_EQ(at(r, 2, 0).shadow_area, 2.0);  // the wall's buried half, under the ground
  EXPECT_EQ(at(r, 2, 0).lit_area, 2.0);
  EXPECT_EQ(at(r, 1, 0).lit_area, 0.0);  // the cellar, under the ground
  // Lamp: the wall's plane y = 0 contains the lamp: edge-on, it casts nothing on the ground.
  EXPECT_EQ(at(r, 0, 1).lit_area, 100.0);
  EXPECT_FALSE(at(r, 2, 1).faces_light);
  EXPECT_EQ(at(r, 1, 1).shadow_area, 16.0);
  expect_fragments_tile_faces(scene, r);
  EXPECT_RAYS_AGREE(scene, r, 20, 1e-6, 30);
}

// ---------------------------------------------------------------------------------------------
// Non-convex receivers
// ---------------------------------------------------------------------------------------------

TEST(NonConvexReceivers, UShapedReceiverUnderACasterOverItsMiddleKeepsBothArmsLit) {
  // Hard: the receiver is not its chart box, and the lit part falls apart into two regions.
  Scene scene;
  add_mesh(scene, "u", {{{0, 0, 0}, {3, 0, 0}, {3, 2, 0}, {2, 2, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}}});
  add_mesh(scene, "beam", {rectangle_z(1, 0, 2, 2, 1)});
  scene.lights.push_back(directional_light("overhead", {0, 0, 1}));
  scene.lights.push_back(directional_light("oblique", {0.5, 0, 1}));
  const ShadowResult r = compute(scene);
  EXPECT_EQ(at(r, 0, 0).area, 5.0);
  EXPECT_EQ(at(r, 0, 0).shadow_area, 1.0);  // only [1, 2] x [0, 1]: the notch is not receiver
  EXPECT_EQ(at(r, 0, 0).lit_area, 4.0);
  EXPECT_EQ(regions(r, 0, 0, true).size(), 2u);
  // Oblique: the beam moves to [0.5, 1.5] x [0, 2]: 1 under the base, 0.5 on the left arm.
  EXPECT_EQ(at(r, 0, 1).shadow_area, 1.5);
  EXPECT_EQ(at(r, 0, 1).lit_area, 3.5);
  EXPECT_EQ(regions(r, 0, 1, true).size(), 2u);
  EXPECT_EQ(regions(r, 0, 1, false).size(), 1u);
  expect_fragments_tile_faces(scene, r);
  EXPECT_RAYS_AGREE(scene, r, 30, 1e-6, 60);
}

// ---------------------------------------------------------------------------------------------
// Faces that are planar only within tolerance
// ---------------------------------------------------------------------------------------------

/// Number of quads whose fourth vertex is off the plane of the first three in long double
/// arithmetic (far above its rounding error): faces that are not exactly planar in doubles.
int count_non_coplanar_quads(const Scene& scene) {
  int count = 0;
  for (const Face& f : scene.faces) {
    if (f.vertices.size() != 4) continue;
    using L = long double;
    const glm::dvec3 &a = f.vertices[0], &b = f.vertices[1], &c = f.vertices[2], &d = f.vertices[3];
    const L u[3] = {L(b.x) - a.x, L(b.y) - a.y, L(b.z) - a.z};
    const L v[3] = {L(c.x) - a.x, L(c.y) - a.y, L(c.z) - a.z};
    const L w[3] = {L(d.x) - a.x, L(d.y) - a.y, L(d.z) - a.z};
    const L det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                  u[2] * (v[0] * w[1] - v[1] * w[0]);
    const L scale = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]) *
                    std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) *
                    std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    if (std::abs(det) > 1e-17L * scale) ++count;
  }
  return count;
}

TEST(NonPlanarInDoubles, RotatedSceneWhoseQuadsAreNotExactlyPlanarAgreesWithTheUnrotatedOne) {
  // Hard: after rotation the quads' vertices are off their planes by ~1e-16; the engine lifts
  // them onto a plane, and the answers must move by no more than that.
  Scene base;
  add_mesh(base, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  add_mesh(base, "box", box_faces({0, 0, 0}, {1, 1, 2}));
  add_mesh(base, "panel", {rectangle_z(-2, -2, -1, -0.5, 1)});
  add_mesh(base, "u", {{{2, -3, 0.5}, {4, -3, 0.5}, {4, -1, 0.5}, {3.5, -1, 0.5}, {3.5, -2.5, 0.5},
                        {2.5, -2.5, 0.5}, {2.5, -1, 0.5}, {2, -1, 0.5}}});
  base.lights.push_back(directional_light("sun", {0.3, 0.2, 1}));
  base.lights.push_back(point_light("lamp", {2, 2, 5}));
  Scene rotated = transformed(base, 1.0, {1, 2, 3}, 0.7, {0, 0, 0});
  validate_scene(rotated);  // within the default planarity tolerance
  ASSERT_GT(count_non_coplanar_quads(rotated), 0) << "the rotation left every quad exactly planar";
  const ShadowResult rb = compute(base, /*threads=*/2, /*polygons=*/false);
  const ShadowResult rr = compute(rotated, /*threads=*/2);
  ASSERT_EQ(rb.lighting.size(), rr.lighting.size());
  for (std::size_t a = 0; a < rb.lighting.size(); ++a) {
    const FaceLighting &b = rb.lighting[a], &o = rr.lighting[a];
    SCOPED_TRACE("face " + std::to_string(b.face_id) + " light " + std::to_string(b.light_id));
    EXPECT_EQ(b.faces_light, o.faces_light);
    EXPECT_NEAR(o.area, b.area, 1e-9 * b.area);
    EXPECT_NEAR(o.lit_area, b.lit_area, 1e-9 * b.area);
    EXPECT_NEAR(o.lit_fraction, b.lit_fraction, 1e-9);
  }
  expect_fragments_tile_faces(rotated, rr);
  EXPECT_RAYS_AGREE(rotated, rr, 10, 1e-6, 50);
}

// ---------------------------------------------------------------------------------------------
// The parallel path
// ---------------------------------------------------------------------------------------------

TEST(ParallelPath, TwoThreadsGiveTheSameHardCaseResultsAsOne) {
  // Hard: per-thread exact state; coincident faces, slivers and cyclic strips in one scene.
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-10, -10, 10, 10, 0)});
  add_mesh(scene, "strips", cyclic_strips());
  add_mesh(scene, "stack", box_faces({6, 6, 0}, {8, 8, 1}));
  add_mesh(scene, "stack top", box_faces({6, 6, 1}, {8, 8, 2}));
  add_mesh(scene, "sliver", {rectangle_z(-6, -6, -6 + 1e-9, -5, 1)});
  scene.lights.push_back(directional_light("sun", sun_direction(0.01, 200)));
  scene.lights.push_back(directional_light("overhead", {0, 0, 1}));
  scene.lights.push_back(point_light("lamp", {1, 1, 1.5}));
  const ShadowResult one = compute(scene, 1);
  const ShadowResult two = compute(scene, 2);
  ASSERT_EQ(one.lighting.size(), two.lighting.size());
  for (std::size_t a = 0; a < one.lighting.size(); ++a) {
    EXPECT_EQ(one.lighting[a].lit_area, two.lighting[a].lit_area) << a;
    EXPECT_EQ(one.lighting[a].lit_fraction, two.lighting[a].lit_fraction) << a;
  }
  ASSERT_EQ(one.fragments.size(), two.fragments.size());
  for (std::size_t a = 0; a < one.fragments.size(); ++a) {
    EXPECT_EQ(one.fragments[a].polygon, two.fragments[a].polygon) << a;
    EXPECT_EQ(one.fragments[a].lit, two.fragments[a].lit) << a;
  }
  expect_fragments_tile_faces(scene, two);
  EXPECT_RAYS_AGREE(scene, two, 10, 1e-6, 100);
}

}  // namespace
}  // namespace shadow::test
