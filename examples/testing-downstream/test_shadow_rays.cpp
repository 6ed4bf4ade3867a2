// SPDX-License-Identifier: GPL-3.0-or-later
// Property tests of simple_shadow_rays.hpp against libshadow's exact lit fractions, with the
// generators, comparison helper and GoogleTest assertions of libshadow::testing.
#include "simple_shadow_rays.hpp"

#include <shadow/shadow.hpp>
#include <shadow/testing.hpp>
#include <shadow/testing/generators.hpp>
#include <shadow/testing/gtest.hpp>

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <iostream>

namespace {

namespace kit = shadow::testing;

// 1000 rays per face: a sampled fraction is within 0.1 of the truth with 6 standard deviations
// to spare, so a correct implementation passes and a systematic error does not.
constexpr int samples = 1000;
constexpr double tolerance = 0.1;

kit::LitFractionMethod rays(std::uint64_t seed, double bias) {
  return [=](const shadow::Scene& scene, std::size_t face, std::size_t light) {
    return simple::lit_fraction(scene, face, light, samples, seed + face, bias);
  };
}

// The scene for a seed: the same box city every time (rapidcheck's random source, keyed).
shadow::Scene city(std::uint64_t seed) {
  shadow::Scene scene = kit::gen::box_city(6)(rc::Random(seed), 20).value();
  shadow::validate_scene(scene);
  return scene;
}

RC_GTEST_PROP(SimpleShadowRays, AgreeWithLibshadowOnBoxCities, ()) {
  shadow::Scene scene = *kit::gen::box_city(6);  // shrinks to a small city on failure
  shadow::validate_scene(scene);
  const auto seed = *rc::gen::inRange<std::uint64_t>(0, 1u << 30);
  const kit::Comparison c = kit::compare_lit_fractions(scene, rays(seed, 1e-6), tolerance, seed);
  if (!c.ok) RC_FAIL(c.report());
}

TEST(SimpleShadowRays, AgreeWithLibshadowOnSeededCities) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed)
    EXPECT_PRED_FORMAT1(kit::WithinTolerance, kit::compare_lit_fractions(city(seed), rays(seed, 1e-6), tolerance, seed));
}

// The bug: the bias is applied with the wrong sign, so every shadow ray starts just behind its
// own face and hits it ("shadow acne" everywhere). The comparison names the worst face, its
// error and the seed that rebuilds the scene and the rays.
TEST(SimpleShadowRays, BiasBugIsCaughtWithACounterexampleReport) {
  const std::uint64_t seed = 3;
  const kit::Comparison c = kit::compare_lit_fractions(city(seed), rays(seed, -1e-6), tolerance, seed);
  std::cout << "counterexample report for the bias bug:\n" << c.report();
  EXPECT_FALSE(c.ok);
  EXPECT_GT(c.error, 0.5);         // a lit face reported dark
  EXPECT_EQ(c.approximate, 0.0);   // every ray hits its own face
  EXPECT_EQ(c.seed, seed);
  EXPECT_NE(c.report().find("worst face " + std::to_string(c.worst_face)), std::string::npos);
  // And as a property: rapidcheck finds it and shrinks the city (its report is printed too).
  const bool holds = rc::check("the biased rays agree with libshadow", [] {
    shadow::Scene scene = *kit::gen::box_city(6);
    shadow::validate_scene(scene);
    const kit::Comparison d = kit::compare_lit_fractions(scene, rays(1, -1e-6), tolerance, 1);
    if (!d.ok) RC_FAIL(d.report());
  });
  EXPECT_FALSE(holds);
}

}  // namespace
