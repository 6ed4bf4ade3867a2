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
    std::vector<unsigned> seen;                 // per face: the query that last looked at it
    unsigned query = 0;
  };

  /// Appends to `out` (cleared first) every face other than `a_face` and `b_face` that may meet
  /// a segment from a point of polygon `a` to a point of polygon `b`: the faces that meet the
  /// open convex hull of the two (doubles, conservative up to 1e-12 of the distances; a face that
  /// only touches the hull, or whose plane leaves both polygons on one side, is left out).
  /// Returns true when one convex candidate alone hides all of `b` from all of `a` (every
  /// segment between their vertices crosses it well inside): nothing is then seen, and `out` is
  /// left empty.
  bool candidates(const std::vector<glm::dvec3>& a, std::size_t a_face, const std::vector<glm::dvec3>& b,
                  std::size_t b_face, Scratch& scratch, std::vector<std::size_t>& out) const;

  /// Whether some face other than `p_face` and `q_face` crosses the open segment from p to q
  /// well inside (its plane crossed strictly between the two, 1e-9 of the length away from
  /// either, at a point inside the face): a ray test for the visibility of far links, walking
  /// the grid's cells along the segment.
  bool blocked(const glm::dvec3& p, std::size_t p_face, const glm::dvec3& q, std::size_t q_face, Scratch& scratch) const;

  /// The face that the segment from p to q crosses nearest to p (as blocked() counts crossings,
  /// face `p_face` left out), or SIZE_MAX when none.
  std::size_t first_hit(const glm::dvec3& p, std::size_t p_face, const glm::dvec3& q, Scratch& scratch) const;

  /// The unit front normals of the faces (zero for a degenerate face).
  const std::vector<glm::dvec3>& normals() const { return normals_; }

  const std::vector<glm::dvec3>& vertices(std::size_t f) const { return scene_.faces[f].vertices; }

 private:
  /// Whether convex face f crosses every segment between a vertex of `a` and one of `b` inside
  /// it, away from its edges by 1e-9 of the lengths (then it crosses every segment between the
  /// two convex polygons: the crossings are convex combinations of those).
  bool hides_all(std::size_t f, const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b) const;

  /// Walks the grid's cells along the segment from p to q, calling visit(f, t) for each face f
  /// (not p_face or q_face) that it crosses well inside at parameter t, and visit(SIZE_MAX, t)
  /// before entering the next cell (t: where it starts); a true return ends the walk.
  template <class Visit>
  void walk(const glm::dvec3& p, std::size_t p_face, const glm::dvec3& q, std::size_t q_face, Scratch& scratch,
            const Visit& visit) const;

  /// Whether face f may meet the open hull (box `box`, facets in `s.planes`).
  bool consider(std::size_t f, const std::array<double, 6>& box, double tol, const Scratch& s) const;
  std::size_t cell_x(double x) const;
  std::size_t cell_y(double y) const;

  const Scene& scene_;
  std::vector<std::array<double, 6>> boxes_;  // per face (empty for a degenerate one)
  std::vector<glm::dvec3> normals_;
  std::vector<char> convex_;
  // A uniform grid over the faces' boxes in x and y (cities spread in plan): each cell lists
  // the faces whose box meets it.
  double grid_x0_ = 0.0, grid_y0_ = 0.0, cell_ = 1.0;
  std::size_t grid_nx_ = 1, grid_ny_ = 1;
  std::vector<std::vector<std::size_t>> cells_;
};

}  // namespace shadow::radiosity
