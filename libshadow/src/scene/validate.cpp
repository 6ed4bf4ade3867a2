// SPDX-License-Identifier: GPL-3.0-or-later
// Validation of a scene's geometry, for scenes read from files and scenes built in code alike.
//
// Cheap floating-point checks (finite values, planarity within the tolerance) come first, then
// the exact shape check (zero area, self-intersection) from the exact kernel.
#include <shadow/scene_io.hpp>

#include <glm/common.hpp>

#include "core/input_checks.hpp"
#include "core/lights.hpp"
#include "exact/face_shape.hpp"
#include "geometry/newell_normal.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>
#include <string>
#include <vector>

namespace shadow {

namespace {

using detail::face_location;
using detail::finite;
using detail::format_number;
using detail::in_range;

/// Removes consecutive duplicate vertices, including the last one repeating the first.
void remove_consecutive_duplicates(std::vector<glm::dvec3>& vertices) {
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  while (vertices.size() > 1 && vertices.back() == vertices.front()) vertices.pop_back();
}

/// Checks that every vertex lies within `tolerance * diameter` of the plane through the
/// centroid with the Newell normal (the plane the exact kernel lifts the face onto).
void check_planarity(const std::vector<glm::dvec3>& vertices, double tolerance,
                     const SourceLocation& where) {
  using Real = long double;
  const std::size_t n = vertices.size();
  glm::dvec3 lo = vertices[0], hi = vertices[0];
  for (const glm::dvec3& v : vertices) {
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
  const glm::dvec3 extent = hi - lo;
  const double diameter = std::max({extent.x, extent.y, extent.z});
  if (!(diameter > 0) || !std::isfinite(diameter)) return;  // coincident vertices: zero area

  // Newell normal and centroid relative to the first vertex, so the sums do not lose the
  // face's small size against large coordinates.
  Real nx = 0, ny = 0, nz = 0, cx = 0, cy = 0, cz = 0;
  const glm::dvec3 origin = vertices[0];
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3& a = vertices[i];
    const glm::dvec3& b = vertices[(i + 1) % n];
    const Real ax = Real(a.x) - origin.x, ay = Real(a.y) - origin.y, az = Real(a.z) - origin.z;
    const Real bx = Real(b.x) - origin.x, by = Real(b.y) - origin.y, bz = Real(b.z) - origin.z;
    const std::array<Real, 3> term = geometry::newell_term(ax, ay, az, bx, by, bz);
    nx += term[0];
    ny += term[1];
    nz += term[2];
    cx += ax;
    cy += ay;
    cz += az;
  }
  const Real length = std::sqrt(nx * nx + ny * ny + nz * nz);
  // The normal's rounding error is about n * eps * diameter^2. Where that could tilt the plane
  // by more than a tenth of the tolerance, the normal says nothing about planarity: the face is
  // (numerically) of zero area, which the exact shape check handles.
  const Real d = diameter;
  const Real noise = Real(n) * std::numeric_limits<Real>::epsilon() * d * d;
  if (!(length > noise * 10 / Real(tolerance))) return;

  cx /= Real(n);
  cy /= Real(n);
  cz /= Real(n);
  Real worst = 0;
  for (const glm::dvec3& v : vertices) {
    const Real px = Real(v.x) - origin.x - cx, py = Real(v.y) - origin.y - cy, pz = Real(v.z) - origin.z - cz;
    worst = std::max(worst, std::fabs((px * nx + py * ny + pz * nz) / length));
  }
  const double allowed = tolerance * diameter;
  // Rounding the input to doubles alone moves a vertex by up to half an ulp of its largest
  // coordinate; a tiny face far from the origin cannot be flatter than that.
  double magnitude = 0;
  for (const glm::dvec3& v : vertices)
    magnitude = std::max({magnitude, std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
  const double representable = 8 * std::numeric_limits<double>::epsilon() * magnitude;
  if (static_cast<double>(worst) > std::max(allowed, representable))
    throw InputError(where, "face is not planar: a vertex is " + format_number(static_cast<double>(worst)) +
                                " off its plane (tolerance " + format_number(tolerance) + " x diameter " +
                                format_number(diameter) + " = " + format_number(allowed) + ")");
}

void validate_face(Scene& scene, std::size_t face_id, const LoadOptions& options,
                   std::vector<Warning>& warnings) {
  Face& face = scene.faces[face_id];
  const SourceLocation where = face_location(scene, face_id);
  detail::check_face_numbers(scene, face_id);
  remove_consecutive_duplicates(face.vertices);
  if (face.vertices.size() < 3)
    throw InputError(where, "face has " + std::to_string(face.vertices.size()) + " distinct " +
                                (face.vertices.size() == 1 ? "vertex" : "vertices") +
                                "; at least 3 are needed");
  check_planarity(face.vertices, options.planarity_tolerance, where);
  switch (detail::classify_face_shape(face.vertices)) {
    case detail::FaceShape::Simple:
      face.degenerate = false;
      break;
    case detail::FaceShape::ZeroArea:
      face.degenerate = true;
      warnings.push_back({where, "face has zero area; it keeps its face_id but casts no shadow and receives no light"});
      break;
    case detail::FaceShape::SelfIntersecting:
      throw InputError(where, "face boundary intersects itself");
  }
}

}  // namespace

namespace {

/// A mesh's edges, keyed by their two end points (exact coordinates), lowest first.
struct EdgeKey {
  glm::dvec3 a, b;
  bool operator<(const EdgeKey& o) const {
    auto less = [](const glm::dvec3& p, const glm::dvec3& q) {
      return p.x != q.x ? p.x < q.x : p.y != q.y ? p.y < q.y : p.z < q.z;
    };
    if (a != o.a) return less(a, o.a);
    return less(b, o.b);
  }
};

/// Warns about the closed parts of a mesh (faces joined by shared edges, every edge shared by
/// exactly two faces of the part) whose faces point inward or are oriented inconsistently; a
/// face wound the wrong way otherwise reads silently as attached shadow. Parts are checked one by
/// one, so one inward box among a mesh of a thousand outward ones is still found. Open parts (a
/// ground plane, a single wall, a box without a lid) say nothing about inside and outside and are
/// left alone. At most one warning of each kind per mesh, with the number of parts and the first.
void check_orientation(const Scene& scene, std::size_t mesh_index, std::vector<Warning>& warnings) {
  const Mesh& mesh = scene.meshes[mesh_index];
  struct Use {
    EdgeKey key;
    bool forward;       // run from key.a to key.b
    std::size_t face;   // index into `faces`
  };
  // Every edge with the way it is run, sorted so that the uses of one edge are adjacent: a sort
  // is several times faster than a map on big meshes.
  std::vector<Use> edges;
  std::vector<std::size_t> faces;  // face_ids of the mesh's non-degenerate faces
  for (std::size_t f = mesh.first_face; f < mesh.first_face + mesh.face_count && f < scene.faces.size(); ++f) {
    const Face& face = scene.faces[f];
    if (face.mesh != mesh_index || face.degenerate) continue;
    const std::vector<glm::dvec3>& v = face.vertices;
    for (std::size_t i = 0; i < v.size(); ++i) {
      const glm::dvec3& p = v[i];
      const glm::dvec3& q = v[(i + 1) % v.size()];
      const bool forward = EdgeKey{p, q} < EdgeKey{q, p};
      edges.push_back({forward ? EdgeKey{p, q} : EdgeKey{q, p}, forward, faces.size()});
    }
    faces.push_back(f);
  }
  if (faces.size() < 2) return;
  std::sort(edges.begin(), edges.end(), [](const Use& x, const Use& y) { return x.key < y.key; });

  // Parts: union-find over faces that share an edge.
  std::vector<std::size_t> parent(faces.size());
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = i;
  auto root = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::vector<char> open(faces.size(), 0), inconsistent(faces.size(), 0);  // by face, folded to roots below
  auto same = [](const EdgeKey& x, const EdgeKey& y) { return x.a == y.a && x.b == y.b; };
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && same(edges[i].key, edges[j].key)) ++j;
    for (std::size_t k = i + 1; k < j; ++k) parent[root(edges[k].face)] = root(edges[i].face);
    // Closed: every edge exactly twice (once: a border; three times or more: non-manifold).
    if (j - i != 2) open[edges[i].face] = 1;
    else if (edges[i].forward == edges[i + 1].forward) inconsistent[edges[i].face] = 1;
    i = j;
  }
  std::vector<char> part_open(faces.size(), 0), part_inconsistent(faces.size(), 0);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    part_open[root(f)] |= open[f];
    part_inconsistent[root(f)] |= inconsistent[f];
  }
  // Signed volume of each part (divergence theorem over fan triangles), relative to one vertex
  // of the part to keep digits.
  using Real = long double;
  std::vector<Real> volume(faces.size(), 0);
  std::vector<std::size_t> first_face(faces.size(), faces.size());  // smallest face of each part
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const std::size_t r = root(f);
    first_face[r] = std::min(first_face[r], f);
  }
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const std::size_t r = root(f);
    if (part_open[r] || part_inconsistent[r]) continue;
    const glm::dvec3 origin = scene.faces[faces[first_face[r]]].vertices[0];
    const std::vector<glm::dvec3>& v = scene.faces[faces[f]].vertices;
    auto rel = [&](const glm::dvec3& p, int k) { return Real(p[k]) - Real(origin[k]); };
    for (std::size_t i = 1; i + 1 < v.size(); ++i) {
      const glm::dvec3 &a = v[0], &b = v[i], &c = v[i + 1];
      const Real ax = rel(a, 0), ay = rel(a, 1), az = rel(a, 2);
      const Real bx = rel(b, 0), by = rel(b, 1), bz = rel(b, 2);
      const Real cx = rel(c, 0), cy = rel(c, 1), cz = rel(c, 2);
      volume[r] += ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
    }
  }
  std::size_t parts = 0, inward = 0, mixed = 0, first_inward = faces.size(), first_mixed = faces.size();
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (root(f) != f) continue;
    ++parts;
    if (part_open[f]) continue;
    if (part_inconsistent[f]) {
      ++mixed;
      first_mixed = std::min(first_mixed, first_face[f]);
    } else if (volume[f] < 0) {
      ++inward;
      first_inward = std::min(first_inward, first_face[f]);
    }
  }
  const std::string file = scene.source.string();
  const SourceLocation where{file, "meshes[" + std::to_string(mesh_index) + "]"};
  // A mesh that is one part: "mesh "m" is closed, <single>"; else how many parts, and the first.
  auto describe = [&](std::size_t count, std::size_t first, const std::string& single, const std::string& plural) {
    if (parts == 1) return "mesh \"" + mesh.name + "\" is closed, " + single;
    const std::string at = scene.faces[faces[first]].source.to_string();
    return "mesh \"" + mesh.name + "\" has " + std::to_string(count) + " closed part" + (count == 1 ? "" : "s") +
           " (of " + std::to_string(parts) + "; the first has face " + std::to_string(faces[first]) +
           (at.empty() ? std::string() : ", " + at) + ") " + plural;
  };
  if (mixed > 0)
    warnings.push_back({where, describe(mixed, first_mixed, "with inconsistent face orientation", "with inconsistent face orientation") +
                                   ": some edge is run the same way by both of its faces, so some faces' fronts point "
                                   "inward and those faces will be in their own (attached) shadow; check the vertex "
                                   "order of its faces"});
  if (inward > 0)
    warnings.push_back({where, describe(inward, first_inward, "and its faces point inward", "whose faces point inward") +
                                   " (negative signed volume): they are lit only from inside, as for a room seen from "
                                   "within; if it is a solid seen from outside, reverse the vertex order of its faces "
                                   "(this is only a warning)"});
}

}  // namespace

void validate_scene(Scene& scene, const LoadOptions& options) {
  // Zero cannot be checked in floating point: rounding alone puts vertices off the plane.
  if (!(options.planarity_tolerance > 0) || !std::isfinite(options.planarity_tolerance))
    throw InputError({}, "the planarity tolerance must be a positive finite number, got " +
                             format_number(options.planarity_tolerance));
  for (std::size_t i = 0; i < scene.lights.size(); ++i)
    detail::check_light(scene.lights[i], scene.source.string(), "lights[" + std::to_string(i) + "]");
  for (std::size_t i = 0; i < scene.planes.size(); ++i) detail::check_plane(scene, i);
  std::vector<Warning> warnings;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) validate_face(scene, f, options, warnings);
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) check_orientation(scene, m, warnings);
  // Validating twice (load_scene, then the caller) must not repeat warnings.
  for (Warning& w : warnings) {
    const bool known = std::any_of(scene.warnings.begin(), scene.warnings.end(), [&](const Warning& old) {
      return old.where.file == w.where.file && old.where.place == w.where.place && old.message == w.message;
    });
    if (!known) scene.warnings.push_back(std::move(w));
  }
}

}  // namespace shadow
