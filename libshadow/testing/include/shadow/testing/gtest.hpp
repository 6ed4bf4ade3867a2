// SPDX-License-Identifier: GPL-3.0-or-later
/// @file testing/gtest.hpp
/// @brief GoogleTest assertions for libshadow::testing: predicate-formatters for
/// EXPECT_PRED_FORMAT1/2/3 and ASSERT_PRED_FORMAT*, returning ::testing::AssertionResult with
/// the checkers' readable verdicts. Header-only; needs GoogleTest in the including project.
///
/// @code
///   EXPECT_PRED_FORMAT2(shadow::testing::Partitions, scene, result);
///   EXPECT_PRED_FORMAT3(shadow::testing::LitClaimsHold, scene, result, seed);
///   EXPECT_PRED_FORMAT1(shadow::testing::WithinTolerance,
///                       shadow::testing::compare_lit_fractions(scene, my_method, 0.05, seed));
///   EXPECT_TRUE(shadow::testing::to_assertion(shadow::testing::check_invariance(scene, s, 0)));
/// @endcode
#pragma once

#include <shadow/testing.hpp>

#include <gtest/gtest.h>

#include <cstdint>

namespace shadow::testing {

/// A Verdict as a GoogleTest assertion result (its message on failure).
inline ::testing::AssertionResult to_assertion(const Verdict& v) {
  if (v.ok) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << v.message;
}

/// EXPECT_PRED_FORMAT2(Partitions, scene, result): check_partition.
inline ::testing::AssertionResult Partitions(const char* scene_expr, const char* result_expr, const Scene& scene,
                                             const ShadowResult& result) {
  const Verdict v = check_partition(scene, result);
  if (v.ok) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "check_partition(" << scene_expr << ", " << result_expr << "): " << v.message;
}

/// EXPECT_PRED_FORMAT3(LitClaimsHold, scene, result, seed): check_lit_claims (3 points per
/// fragment).
inline ::testing::AssertionResult LitClaimsHold(const char* scene_expr, const char* result_expr, const char*,
                                                const Scene& scene, const ShadowResult& result, std::uint64_t seed) {
  const Verdict v = check_lit_claims(scene, result, seed);
  if (v.ok) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "check_lit_claims(" << scene_expr << ", " << result_expr << "): " << v.message;
}

/// EXPECT_PRED_FORMAT1(WithinTolerance, compare_lit_fractions(...)): passes when every pair is
/// within tolerance; otherwise prints the report (worst face, its error, the seed).
inline ::testing::AssertionResult WithinTolerance(const char* expr, const Comparison& c) {
  if (c.ok) return ::testing::AssertionSuccess() << c.report();
  return ::testing::AssertionFailure() << expr << ":\n" << c.report();
}

/// EXPECT_PRED_FORMAT3(IsLitAt, scene, point, light_id): the exact oracle as an assertion.
inline ::testing::AssertionResult IsLitAt(const char*, const char* point_expr, const char* light_expr,
                                          const Scene& scene, glm::dvec3 point, std::size_t light_id) {
  if (is_lit(scene, point, light_id)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "point " << point_expr << " = (" << point.x << ", " << point.y << ", "
                                       << point.z << ") is not lit by light " << light_expr << " = " << light_id
                                       << " (exact)";
}

/// EXPECT_PRED_FORMAT3(IsShadowedAt, scene, point, light_id): the negation of IsLitAt.
inline ::testing::AssertionResult IsShadowedAt(const char*, const char* point_expr, const char* light_expr,
                                               const Scene& scene, glm::dvec3 point, std::size_t light_id) {
  if (!is_lit(scene, point, light_id)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "point " << point_expr << " = (" << point.x << ", " << point.y << ", "
                                       << point.z << ") is lit by light " << light_expr << " = " << light_id
                                       << " (exact)";
}

}  // namespace shadow::testing
