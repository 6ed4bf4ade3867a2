// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: the faces that may stand between two polygons (shaft culling, Haines and Wallace
// 1991), so that form factors between them look at those faces only.
#pragma once

#include <shadow/scene.hpp>

#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <vector>

namespace shadow::radiosity {

/// The scene's faces with their boxes and planes, for shaft queries from many threads at once.
class ShaftCuller {
 public:
  explicit ShaftCuller(const Scene& scene);

  /// Working storage of one thread.
  struct Scratch {
    std::vector<glm::dvec3> points;
    std::vector<std::array<double, 4>> planes;  // outward normal (x, y, z) and offset
  };

  /// Appends to `out` (cleared first) every face other than `a_face` and `b_face` that may meet
  /// a segment from a point of polygon `a` to a point of polygon `b`: the faces that meet the
  /// open convex hull of the two (doubles, conservative up to 1e-12 of the distances; a face that
  /// only touches the hull, or whose plane leaves both polygons on one side, is left out).
  void candidates(const std::vector<glm::dvec3>& a, std::size_t a_face, const std::vector<glm::dvec3>& b,
                  std::size_t b_face, Scratch& scratch, std::vector<std::size_t>& out) const;

  const std::vector<glm::dvec3>& vertices(std::size_t f) const { return scene_.faces[f].vertices; }

 private:
  const Scene& scene_;
  std::vector<std::array<double, 6>> boxes_;  // per face (empty for a degenerate one)
  std::vector<glm::dvec3> normals_;
  // Faces sorted by their box's lower x, so that a query skips those beyond its box.
  std::vector<std::size_t> by_x_;
  std::vector<double> lower_x_;
  double widest_x_ = 0.0;  // the largest box width in x
};

}  // namespace shadow::radiosity
