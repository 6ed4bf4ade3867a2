// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: the form factor from a point to the part of a source polygon that the point sees past
// a few candidate occluders, in doubles (docs/radiosity.md, "Visibility in doubles").
#pragma once

#include <polyclipping/clipper.hpp>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <vector>

namespace shadow::radiosity {

/// Working storage of one thread (kept between calls so that they do not allocate).
struct VisibleScratch {
  std::vector<glm::dvec3> front, clipped, next, r;
  std::vector<glm::dvec2> flat, flat_next, front_flat;
  std::vector<std::vector<glm::dvec2>> shadows;  // the occluders' shadows on the source's plane
  std::vector<glm::dvec4> shadow_boxes;
  std::vector<std::vector<glm::dvec2>> pieces, next_pieces;  // the visible part, convex pieces
  ClipperLib::Path subject;
  ClipperLib::Paths clips, visible;
  ClipperLib::Clipper clipper;
};

/// A source polygon (convex or not, counter-clockwise seen from its front) in a chart of its
/// plane: the occluders' shadows from a point are cut out of it there, on an integer grid of
/// about 1e-9 of its size (Clipper), and Lambert's contour is summed over what is left.
class SourceChart {
 public:
  explicit SourceChart(const std::vector<glm::dvec3>& polygon);

  /// F from the differential area at `x` (unit normal `nr`) to the part of the source that x sees
  /// past `occluders` (polygons; any face not among them must be known not to hide any of the
  /// source from x). 0 when x is not in front of the source or the source not in front of x.
  double form_factor(const glm::dvec3& x, const glm::dvec3& nr,
                     const std::vector<const std::vector<glm::dvec3>*>& occluders, VisibleScratch& scratch) const;

  /// The same without occluders: Lambert's contour over the source cut to x's front.
  double unoccluded(const glm::dvec3& x, const glm::dvec3& nr, VisibleScratch& scratch) const;

  const glm::dvec3& normal() const { return normal_; }
  bool usable() const { return usable_; }

 private:
  glm::dvec2 to_chart(const glm::dvec3& p) const;
  enum class Shadows { Disjoint, Convex, General };  // convex with disjoint boxes, convex, any
  Shadows classify_shadows(VisibleScratch& s, std::size_t shadows) const;
  /// Signed F of the front part minus convex shadows, kept as disjoint convex pieces; false
  /// when the pieces grow too many (the caller then takes subtract_union).
  bool subtract_pieces(const glm::dvec3& x, const glm::dvec3& nr, VisibleScratch& s, std::size_t shadows,
                       double& f) const;
  /// Signed F of the front part minus the shadows, one convex clipping per shadow.
  double subtract_each(const glm::dvec3& x, const glm::dvec3& nr, VisibleScratch& s, std::size_t shadows) const;
  /// Signed F of the front part minus the union of the shadows (Clipper on the grid).
  double subtract_union(const glm::dvec3& x, const glm::dvec3& nr, VisibleScratch& s, std::size_t shadows) const;
  glm::dvec3 from_grid(const ClipperLib::IntPoint& p) const;

  std::vector<glm::dvec3> polygon_;
  glm::dvec3 normal_{0.0}, origin_{0.0}, u_{0.0}, v_{0.0};
  glm::dvec2 lo_{0.0}, hi_{0.0};  // the source's box in the chart
  double scale_ = 1.0;            // chart units to grid units
  bool usable_ = false;
};

/// Signed form factor from x (unit normal nr) to a polygon lying in front of x's plane:
/// positive for counter-clockwise seen from x (Lambert's contour, -1/(2 pi) times its sum).
double signed_contour(const glm::dvec3& x, const glm::dvec3& nr, const std::vector<glm::dvec3>& polygon,
                      std::vector<glm::dvec3>& r);

/// `polygon` cut to the half-space n . (y - o) > 0 (Sutherland-Hodgman) into `out`.
void clip_half_space(const std::vector<glm::dvec3>& polygon, const glm::dvec3& n, const glm::dvec3& o,
                     std::vector<glm::dvec3>& out);

}  // namespace shadow::radiosity
