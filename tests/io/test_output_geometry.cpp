// SPDX-License-Identifier: GPL-3.0-or-later
// The geometry libshadow writes is the exact geometry rounded once to nearest
// (docs/numeric-contract.md, "Vertices"): input vertices come back bit for bit, shadow vertices
// are the exact points' nearest doubles (checked against rationals computed here, apart from the
// engine), the result does not depend on the thread count or on what a worker computed before,
// and every fragment written is a polygon with a non-zero area in doubles.
#include "support/scene_builders.hpp"

#include <shadow/shadow.hpp>
#include <shadow/testing.hpp>

#include <glm/geometric.hpp>
#include <gmpxx.h>
#include <gtest/gtest.h>
#include <mpfr.h>

#include <cmath>
#include <cstring>
#include <set>
#include <string>
#include <tuple>
#include <vector>

namespace shadow::test {
namespace {

/// The double nearest to q (ties to even), with MPFR: the reference rounding.
double nearest(const mpq_class& q) {
  mpfr_t r;
  mpfr_init2(r, 53);
  mpfr_set_q(r, q.get_mpq_t(), MPFR_RNDN);
  const double d = mpfr_get_d(r, MPFR_RNDN);
  mpfr_clear(r);
  return d;
}

using Key = std::tuple<double, double, double>;
Key key(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

bool same_bits(const glm::dvec3& a, const glm::dvec3& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

ShadowResult compute(const Scene& scene, unsigned threads, bool polygons = true) {
  ShadowOptions options;
  options.threads = threads;
  options.polygons = polygons;
  return compute_shadows(scene, options);
}

/// Twice the area of a 3D polygon in doubles, from its Newell normal (what a reader of the file
/// gets with the usual formula).
double newell_twice_area(const std::vector<glm::dvec3>& p) {
  glm::dvec3 n(0.0);
  for (std::size_t a = 0; a < p.size(); ++a) {
    const glm::dvec3& u = p[a];
    const glm::dvec3& v = p[(a + 1) % p.size()];
    n += glm::dvec3((u.y - v.y) * (u.z + v.z), (u.z - v.z) * (u.x + v.x), (u.x - v.x) * (u.y + v.y));
  }
  return glm::length(n);
}

/// Fragments equal bit for bit: same count, order, ids, flags, areas and vertices.
void expect_same_fragments(const ShadowResult& a, const ShadowResult& b, const std::string& what) {
  ASSERT_EQ(a.fragments.size(), b.fragments.size()) << what;
  std::size_t differing = 0;
  for (std::size_t i = 0; i < a.fragments.size(); ++i) {
    const Fragment& x = a.fragments[i];
    const Fragment& y = b.fragments[i];
    ASSERT_EQ(x.face_id, y.face_id) << what;
    ASSERT_EQ(x.light_id, y.light_id) << what;
    ASSERT_EQ(x.lit, y.lit) << what;
    ASSERT_EQ(x.polygon.size(), y.polygon.size()) << what << " fragment " << i;
    EXPECT_EQ(x.area, y.area) << what;
    for (std::size_t v = 0; v < x.polygon.size(); ++v) differing += same_bits(x.polygon[v], y.polygon[v]) ? 0 : 1;
  }
  EXPECT_EQ(differing, 0u) << what << ": vertices whose bits differ";
}

// A terraced-houses scene in UTM-like coordinates: a flat ground at z = 301.234 and a wall
// through (4.2, 5.6), partly shadowed by a box. Every fragment vertex at an input vertex of its
// face is that vertex bit for bit, and every ground vertex has z = 301.234 exactly (they once
// came out as 4.199999999999999 and 301.23400000000004).
TEST(OutputGeometry, InputVerticesComeBackBitForBit) {
  const double g = 301.234;
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(0, 0, 20.3, 20.7, g)});
  // A vertical wall (exactly planar: its vertices pair up in x and y), facing the sun and the box.
  add_mesh(scene, "wall", {{{4.2, 5.6, g}, {4.2, 5.6, g + 3.3}, {12.3, 1.1, g + 3.3}, {12.3, 1.1, g}}});
  add_mesh(scene, "box", box_faces({6.1, 7.3, g}, {7.9, 9.4, g + 2.7}));
  scene.lights.push_back(directional_light("sun", {0.35, 0.62, 0.71}));
  scene.lights.push_back(point_light("lamp", {9.1, 12.7, g + 6.3}));
  validate_scene(scene);
  const ShadowResult r = compute(scene, 2);
  std::size_t matched = 0, ground_vertices = 0;
  for (const Fragment& f : r.fragments) {
    const std::vector<glm::dvec3>& input = scene.faces[f.face_id].vertices;
    for (const glm::dvec3& v : f.polygon) {
      for (const glm::dvec3& u : input)
        if (glm::length(v - u) < 1e-6) {
          EXPECT_TRUE(same_bits(v, u)) << "face " << f.face_id << ": (" << v.x << ", " << v.y << ", " << v.z
                                        << ") written for the input vertex (" << u.x << ", " << u.y << ", " << u.z << ")";
          ++matched;
        }
      if (f.face_id == 0) {
        EXPECT_EQ(v.z, g);
        ++ground_vertices;
      }
    }
  }
  EXPECT_GT(matched, 8u);
  EXPECT_GT(ground_vertices, 8u);
  // The wall is partly in the box's shadow under one of the lights.
  std::set<bool> wall_states;
  for (const Fragment& f : r.fragments)
    if (f.face_id == 1) wall_states.insert(f.lit);
  EXPECT_EQ(wall_states.size(), 2u);
}

// A box on a flat ground at z = g under a sun: the shadow is one simple polygon whose vertices are
// the box's base corners and its top corners projected along the sun, p - (p_z - g) / d_z d. Each
// written vertex is the nearest double to one of those rationals, computed here in GMP.
TEST(OutputGeometry, ShadowVerticesAreTheExactPointsRoundedToNearest) {
  const double g = 0.1;  // not a dyadic number: the projections are not doubles
  const glm::dvec3 lo(1.3, 2.7, g), hi(2.9, 3.1, 1.7);
  for (const glm::dvec3& d : {glm::dvec3(0.3, 0.7, 1.1), glm::dvec3(-0.37, 0.21, 0.93), glm::dvec3(1.0 / 3, -0.2, 0.6)}) {
    Scene scene;
    add_mesh(scene, "ground", {rectangle_z(-10, -10, 10, 10, g)});
    add_mesh(scene, "box", box_faces(lo, hi));
    scene.lights.push_back(directional_light("sun", d));
    validate_scene(scene);
    std::set<Key> expected;
    for (const double x : {lo.x, hi.x})
      for (const double y : {lo.y, hi.y}) {
        expected.insert({x, y, g});  // a base corner, on the ground
        const mpq_class t = (mpq_class(hi.z) - mpq_class(g)) / mpq_class(d.z);
        expected.insert({nearest(mpq_class(x) - t * mpq_class(d.x)), nearest(mpq_class(y) - t * mpq_class(d.y)), g});
      }
    for (const unsigned threads : {1u, 2u}) {
      const ShadowResult r = compute(scene, threads);
      std::size_t checked = 0;
      for (const Fragment& f : r.fragments) {
        if (f.face_id != 0 || f.lit) continue;
        for (const glm::dvec3& v : f.polygon) {
          EXPECT_EQ(expected.count(key(v)), 1u) << "sun (" << d.x << ", " << d.y << ", " << d.z << "): vertex ("
                                                << v.x << ", " << v.y << ", " << v.z << ") is no exact shadow corner rounded";
          ++checked;
        }
      }
      EXPECT_GE(checked, 6u);
    }
  }
}

// Rotated scenes (faces not exactly planar: the lazy exact route, lifted vertices) write the same
// bits with 1 and 2 threads, and from an engine that computed other lights first: the rounding
// must not depend on which exact values a worker had evaluated before.
TEST(OutputGeometry, FragmentsAreTheSameBitsForAnyThreadCountAndHistory) {
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    Scene scene = transformed(random_scene(seed), 1.7, {0.3, -0.5, 0.8}, 0.61, {1e3, -2e3, 301.234});
    validate_scene(scene);
    const ShadowResult one = compute(scene, 1);
    const ShadowResult two = compute(scene, 2);
    expect_same_fragments(one, two, "seed " + std::to_string(seed) + ", 1 and 2 threads");
    // The same light from an engine whose workers computed another light first.
    const ShadowEngine engine(scene, 2);
    ShadowOptions options;
    options.threads = 2;
    Light other = scene.lights[0];
    if (other.type == LightType::Directional) other.to_light += glm::dvec3(0.05, -0.03, 0.0);
    else other.position += glm::dvec3(0.3, 0.2, 0.1);
    (void)engine.compute(other, 0, options);
    const ShadowResult again = engine.compute(scene.lights[0], 0, options);
    expect_same_fragments(one, again, "seed " + std::to_string(seed) + ", after another light");
  }
}

// No fragment written collapses in doubles: each has at least 3 vertices and a non-zero area by
// Newell's formula on its absolute coordinates. Rotated cities placed at UTM-like coordinates
// (4e6 m, where an ulp is 5e-10 m) have slivers thinner than that: they once came out as cells
// with a zero normal (64 of 9,419 here); now they are left out, counted in stats.dropped_cells,
// and their exact area is in dropped_area, so fragments and dropped_area still add up.
TEST(OutputGeometry, NoFragmentCollapsesInDoubles) {
  std::size_t fragments = 0;
  std::uint64_t dropped = 0;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    Scene city = make_city(30, 60.0, seed);
    city.lights.push_back(directional_light("sun", {0.3, 0.4, 0.8}));
    city.lights.push_back(point_light("lamp", {10, 12, 30}));
    Scene scene = transformed(city, 1.0, {0.3, 0.5, 0.8}, 0.3 * static_cast<double>(seed), {5e5, 4e6, 301.234});
    validate_scene(scene);
    const ShadowResult r = compute(scene, 2);
    dropped += r.stats.dropped_cells;
    for (const Fragment& f : r.fragments) {
      ++fragments;
      ASSERT_GE(f.polygon.size(), 3u);
      EXPECT_GT(newell_twice_area(f.polygon), 0.0) << "seed " << seed << ": face " << f.face_id << " fragment "
                                                   << f.fragment_id << " area " << f.area;
    }
    const testing::Verdict partition = testing::check_partition(scene, r);
    EXPECT_TRUE(partition.ok) << "seed " << seed << ": " << partition.message;
  }
  EXPECT_GT(fragments, 5000u);
  EXPECT_GT(dropped, 0u);
}

}  // namespace
}  // namespace shadow::test
