// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: how far a face is from planar, measured the one way validation decides it, so that
// a reader which splits non-planar surfaces (CityJSON) keeps whole exactly what validation passes.
#pragma once

#include <glm/vec3.hpp>

#include <vector>

namespace shadow::detail {

/// The farthest vertex's distance from the plane through the centroid with the Newell normal
/// (long double, relative to the first vertex), and what validation allows.
struct PlaneDeviation {
  double worst = 0.0;     ///< 0 when the normal is lost in rounding (a face of zero area)
  double diameter = 0.0;  ///< largest extent of the bounding box
  /// max(tolerance x diameter, 8 ulps of the largest coordinate): input rounding alone moves a
  /// vertex by half an ulp, so a tiny face far from the origin cannot be flatter than that.
  double allowed = 0.0;
};

/// What the message of a face rejected by validation (or by a model reader, for a surface it
/// cannot make faces of) ends with, so that the user learns how to go on without it.
inline constexpr const char* skip_invalid_hint = " (--skip-invalid skips such faces; skip_invalid=True in Python)";

/// Measures `vertices` (at least one) against `tolerance` (LoadOptions::planarity_tolerance).
PlaneDeviation plane_deviation(const std::vector<glm::dvec3>& vertices, double tolerance);

}  // namespace shadow::detail
