// SPDX-License-Identifier: GPL-3.0-or-later
// Properties of the exact shadows on seeded random scenes (rapidcheck), checked with the
// libshadow::testing kit's oracles and checkers. The seed and the number
// of cases come from RC_PARAMS, set by CTest so that every run checks the same scenes.
#include "support/polygon_tools.hpp"
#include "support/scene_builders.hpp"

#include <shadow/shadow.hpp>
#include <shadow/testing.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <map>
#include <random>

namespace shadow::test {
namespace {

namespace kit = shadow::testing;

ShadowResult run(Scene& scene, bool polygons = true) {
  validate_scene(scene);
  ShadowOptions options;
  options.threads = 2;
  options.polygons = polygons;
  return compute_shadows(scene, options);
}

Scene generated_scene() {
  const auto seed = *rc::gen::inRange<std::uint64_t>(0, 1u << 30);
  RC_TAG(seed % 2);  // spread of light kinds shows in the tag counts
  Scene scene = random_scene(seed);
  RC_LOG() << "random_scene(" << seed << ")\n";
  return scene;
}

RC_GTEST_PROP(ShadowProperties, FragmentsCoverEachFaceExactlyOnce, ()) {
  Scene scene = generated_scene();
  const ShadowResult r = run(scene);
  // Each cell's polygon has its area; lit + shadowed = area to an ulp or two (each rounded once
  // from exact values); the cells (and any dropped slivers) add up to the face, the lit ones to
  // the lit area.
  const kit::Verdict partition = kit::check_partition(scene, r);
  if (!partition.ok) RC_FAIL(partition.message);
  // No overlap: pieces of a face that add up to its area and lie inside it cannot overlap;
  // check they lie inside by sampling their interiors.
  std::mt19937_64 rng(1);
  for (const Fragment& f : r.fragments) {
    for (const glm::dvec3& p : sample_interior(f.polygon, 3, 1e-7, rng)) {
      double d = 0;
      const bool inside = inside_polygon(scene.faces[f.face_id].vertices, p, &d);
      RC_ASSERT(inside || d < 1e-6);
    }
  }
}

RC_GTEST_PROP(ShadowProperties, LitPointsSeeTheLightAndShadowedPointsDoNot, ()) {
  // Points inside each fragment against the kit's exact segment test (a second method: no
  // projection, no Boolean operations), which is never unsure.
  Scene scene = generated_scene();
  const ShadowResult r = run(scene);
  const kit::Verdict claims = kit::check_lit_claims(scene, r, 2, 4);
  if (!claims.ok) RC_FAIL(claims.message);
}

/// Both polygons lie on one plane (tested in doubles on axis-aligned grid coordinates, where
/// the arithmetic is exact; random panels are never coplanar with anything).
bool exactly_coplanar(const Polygon3& a, const Polygon3& b) {
  const glm::dvec3 n = newell_normal(a);
  for (const glm::dvec3& v : b)
    if (glm::dot(n, v - a[0]) != 0.0) return false;
  return true;
}

std::vector<double> lit_fractions(const ShadowResult& r) {
  std::vector<double> out;
  for (const FaceLighting& fl : r.lighting) out.push_back(fl.lit_fraction);
  return out;
}

RC_GTEST_PROP(ShadowProperties, LitFractionsAreInvariantUnderTranslationRotationAndScale, ()) {
  Scene scene = generated_scene();
  const std::vector<double> base = lit_fractions(run(scene, false));
  struct Move {
    double scale;
    glm::dvec3 axis;
    double angle;
    glm::dvec3 shift;
    double tolerance;
  };
  const Move moves[] = {
      {1.0, {0, 0, 1}, 0.0, {1e6, -2e6, 3e5}, 1e-6},   // georeferenced: far from the origin
      {0.37, {1, 2, 3}, 1.1, {5, -7, 2}, 1e-7},        // arbitrary similarity
  };
  // Faces exactly coplanar with another face (overlapping boxes) are ill-posed under rotation:
  // rounding the rotated coordinates tilts one against the other by ~1e-16 and, computed
  // exactly, one then shadows part of the other. Rotations are checked on the other faces.
  const ShadowResult base_result = run(scene, false);
  std::vector<bool> coplanar(scene.faces.size(), false);
  for (std::size_t f = 0; f < scene.faces.size(); ++f)
    for (std::size_t g = 0; g < scene.faces.size() && !coplanar[f]; ++g)
      coplanar[f] = g != f && exactly_coplanar(scene.faces[f].vertices, scene.faces[g].vertices);
  // Quarter turns and a power-of-two scale are exact in doubles: the same scene, to the bit.
  kit::Similarity exact;
  exact.quarter_turns_x = 1;
  exact.quarter_turns_z = 3;
  exact.scale_exponent = 2;
  const kit::Verdict same = kit::check_invariance(scene, exact, 0.0);
  if (!same.ok) RC_FAIL(same.message);
  for (const Move& m : moves) {
    Scene moved = transformed(scene, m.scale, m.axis, m.angle, m.shift);
    const std::vector<double> fractions = lit_fractions(run(moved, false));
    RC_ASSERT(fractions.size() == base.size());
    for (std::size_t a = 0; a < base.size(); ++a) {
      if (m.angle != 0.0 && coplanar[base_result.lighting[a].face_id]) continue;
      if (std::abs(fractions[a] - base[a]) > m.tolerance)
        RC_FAIL("lit fraction moved from " + std::to_string(base[a]) + " to " +
                std::to_string(fractions[a]) + " (entry " + std::to_string(a) + ")");
    }
  }
}

RC_GTEST_PROP(ShadowProperties, AddingAnOccluderNeverAddsLight, ()) {
  Scene scene = generated_scene();
  validate_scene(scene);
  const auto x = *rc::gen::inRange(-10, 10);
  const auto y = *rc::gen::inRange(-10, 10);
  const auto h = *rc::gen::inRange(1, 9);
  const kit::Verdict v = kit::check_monotone_occluder(
      scene, {rectangle_z(x, y, x + 3, y + 2, h), rectangle_z(x, y, x + 3, y + 2, h, false)});
  if (!v.ok) RC_FAIL(v.message);
}

RC_GTEST_PROP(ShadowProperties, WithoutOccludersEveryFrontFacingFaceIsFullyLit, ()) {
  Scene scene = generated_scene();
  // Each face alone with the light.
  for (std::size_t f = 0; f < scene.faces.size(); f += 3) {
    Scene alone;
    add_mesh(alone, "one", {scene.faces[f].vertices});
    alone.lights = scene.lights;
    const ShadowResult r = run(alone);
    const FaceLighting& fl = r.lighting.at(0);
    RC_ASSERT(fl.lit_fraction == (fl.faces_light ? 1.0 : 0.0));
  }
}

}  // namespace
}  // namespace shadow::test
