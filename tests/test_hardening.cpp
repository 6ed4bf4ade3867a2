// SPDX-License-Identifier: GPL-3.0-or-later
// Regression tests for the engine defects of issue 11: conservative culling of thin tilted
// receivers, simple double polygons in the fragments, and very large single faces.
#include "support/polygon_tools.hpp"

#include <shadow/shadow.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace shadow::test {
namespace {

using L2 = std::array<long double, 2>;

/// Area of a polygon in long double (shoelace).
long double area2(const std::vector<L2>& p) {
  long double a = 0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const L2& u = p[k];
    const L2& v = p[(k + 1) % p.size()];
    a += u[0] * v[1] - u[1] * v[0];
  }
  return a / 2;
}

/// Convex polygon `subject` (counter-clockwise) clipped to convex counter-clockwise `clip`.
std::vector<L2> clip_convex(std::vector<L2> subject, const std::vector<L2>& clip) {
  for (std::size_t e = 0; e < clip.size() && !subject.empty(); ++e) {
    const L2 a = clip[e], b = clip[(e + 1) % clip.size()];
    auto side = [&](const L2& p) { return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]); };
    std::vector<L2> out;
    for (std::size_t k = 0; k < subject.size(); ++k) {
      const L2 p = subject[k], q = subject[(k + 1) % subject.size()];
      const long double sp = side(p), sq = side(q);
      if (sp >= 0) out.push_back(p);
      if ((sp >= 0) != (sq >= 0)) {
        const long double t = sp / (sp - sq);
        out.push_back({p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])});
      }
    }
    subject = std::move(out);
  }
  return subject;
}

// ---------------------------------------------------------------------------------------------
// Item 1: culling must never drop a caster that is exactly in front of a thin tilted receiver
// ---------------------------------------------------------------------------------------------

/// A thin tilted receiver (a needle triangle about 1 km long and under 0.5 um wide, in a random
/// orientation) and a small triangle parallel to it, h above its far end, lit straight down its
/// normal. In the receiver's own frame (t along it, y across) the shadow is the receiver triangle
/// clipped by the caster triangle: `expected` is that area, computed here in long double.
struct ThinScene {
  Scene scene;
  long double expected = 0;
  double height = 0;
};

ThinScene thin_tilted_scene(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1, 1), u01(0, 1);
  glm::dvec3 e1;
  do e1 = {unit(rng), unit(rng), unit(rng)};
  while (glm::length(e1) < 0.2 || glm::length(e1) > 1);
  e1 = glm::normalize(e1);
  glm::dvec3 helper{unit(rng), unit(rng), unit(rng)};
  const glm::dvec3 e2 = glm::normalize(glm::cross(e1, glm::normalize(helper)));
  const glm::dvec3 n = glm::cross(e1, e2);
  const glm::dvec3 base{200 * unit(rng), 200 * unit(rng), 200 * unit(rng)};
  const double length = 800 + 400 * u01(rng);
  const double width = 1e-7 + 4e-7 * u01(rng);
  // Heights from 10 nm to 0.1 mm, log-uniform: far above the vertices' rounding (1e-13 m), far
  // below the plane offset error of a unit normal rounded from the thin face's edges.
  const double h = std::pow(10.0, -8 + 4 * u01(rng));
  const double t0 = (0.8 + 0.15 * u01(rng)) * length, t1 = t0 + 0.02 * length;
  const double half = 1e-3;  // the caster's half width across the receiver
  auto at = [&](double t, double y, double z) { return base + t * e1 + y * e2 + z * n; };
  ThinScene out;
  out.height = h;
  add_mesh(out.scene, "receiver", {{at(0, 0, 0), at(length, 0, 0), at(length / 2, width, 0)}});
  add_mesh(out.scene, "caster", {{at(t0, -half, h), at(t1, -half, h), at(t0, half, h)}});
  out.scene.meshes[1].receiver = false;
  out.scene.lights.push_back(directional_light("sun", n));
  // The reference in the receiver's frame: the vertices as rounded, expressed in (e1, e2).
  auto frame = [&](const glm::dvec3& p) {
    long double t = 0, y = 0;
    for (int c = 0; c < 3; ++c) {
      t += (static_cast<long double>(p[c]) - base[c]) * e1[c];
      y += (static_cast<long double>(p[c]) - base[c]) * e2[c];
    }
    return L2{t, y};
  };
  std::vector<L2> receiver, caster;
  for (const glm::dvec3& p : out.scene.faces[0].vertices) receiver.push_back(frame(p));
  for (const glm::dvec3& p : out.scene.faces[1].vertices) caster.push_back(frame(p));
  out.expected = std::abs(area2(clip_convex(receiver, caster)));
  return out;
}

TEST(CullingThinReceivers, CasterExactlyInFrontOfANeedleReceiverIsNeverCulled) {
  for (std::uint64_t seed = 1; seed <= 60; ++seed) {
    ThinScene t = thin_tilted_scene(seed);
    SCOPED_TRACE("seed " + std::to_string(seed) + " height " + std::to_string(t.height));
    validate_scene(t.scene);
    for (Arithmetic arithmetic : {Arithmetic::Exact, Arithmetic::Fast}) {
      ShadowOptions options;
      options.threads = 1;
      options.polygons = false;
      options.arithmetic = arithmetic;
      const ShadowResult r = compute_shadows(t.scene, options);
      const FaceLighting* fl = r.find(0, 0);
      ASSERT_NE(fl, nullptr);
      ASSERT_TRUE(fl->faces_light);
      EXPECT_GE(r.stats.candidate_pairs, 1u);
      const double expected = static_cast<double>(t.expected);
      EXPECT_NEAR(fl->shadow_area, expected, 1e-5 * expected + fl->lit_area_error_bound)
          << (arithmetic == Arithmetic::Exact ? "exact" : "fast");
    }
  }
}

}  // namespace
}  // namespace shadow::test
