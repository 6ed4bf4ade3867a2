// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: form factors from points to one source polygon (a face or an element of it), with
// exact visibility (arealight/light_visibility.cpp) where another face may stand between.
#pragma once

#include "arealight/light_visibility.hpp"

#include <shadow/area_lights.hpp>
#include <shadow/scene.hpp>

#include <array>
#include <cstddef>
#include <vector>

namespace shadow::radiosity {

/// A source polygon seen from points. set_shooter() then evaluate() from up to `workers`
/// threads at once (distinct worker indices).
class ShooterView {
 public:
  ShooterView(const Scene& scene, unsigned workers);
  /// The source: `polygon` (counter-clockwise seen from its front) on face `face`. `pieces`, when
  /// given, tile it (a patch's elements): where the whole source is in part hidden from a point,
  /// the pieces are tried one by one before the exact machinery is called.
  void set_shooter(std::size_t face, const std::vector<glm::dvec3>& polygon,
                   std::vector<std::vector<glm::dvec3>> pieces = {});
  /// The form factor from the differential area at `point` (facing its face's normal) to the
  /// source's part that the point sees. Where no face other than the point's own and the
  /// source's has a bounding box that meets the box of the source and the point, nothing can
  /// hide it and Lambert's contour is summed in doubles here; otherwise the exact machinery
  /// removes what the faces hide (LightQuery).
  double evaluate(unsigned worker, const SurfacePoint& point) const;
  /// How many evaluations took the exact route (for the benchmarks).
  std::size_t exact_evaluations() const;
  /// The unit front normal of face f (zero for a degenerate face).
  const glm::dvec3& normal(std::size_t f) const { return normals_[f]; }

 private:
  enum class Seen { None, All, Part };  // from the point: none of it, all of it, maybe part
  /// What the faces leave of `poly` (on the source's plane) from `point`, by double tests that
  /// are conservative up to rounding (a face that may enter the pyramid gives Part).
  Seen classify(const SurfacePoint& point, const glm::dvec3& nr, const std::vector<glm::dvec3>& poly) const;
  /// The unoccluded form factor to `poly` (cut to the front of the point's plane), doubles.
  static double contour(const glm::dvec3& x, const glm::dvec3& nr, const std::vector<glm::dvec3>& poly);

  const Scene& scene_;
  detail::LightQuery query_;
  std::vector<std::array<double, 6>> boxes_;  // per face, widened a little
  std::vector<glm::dvec3> normals_;
  std::vector<char> convex_;  // per face: convex in its plane (doubles)
  std::size_t face_ = 0;
  std::vector<glm::dvec3> polygon_;
  std::vector<std::vector<glm::dvec3>> pieces_;
  glm::dvec3 source_normal_{0.0}, source_point_{0.0};
  std::array<double, 6> source_box_{};
  bool exact_ok_ = false;
  mutable std::vector<std::size_t> exact_count_;
};

}  // namespace shadow::radiosity
