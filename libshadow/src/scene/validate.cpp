// SPDX-License-Identifier: GPL-3.0-or-later
// Validation of a scene's geometry, for scenes read from files and scenes built in code alike.
//
// Cheap floating-point checks (finite values, planarity within the tolerance) come first, then
// the exact shape check (zero area, self-intersection) from the exact kernel.
#include <shadow/scene_io.hpp>

#include <glm/common.hpp>

#include "core/input_checks.hpp"
#include "core/lights.hpp"
#include "core/parallel.hpp"
#include "exact/face_shape.hpp"
#include "geometry/newell_normal.hpp"
#include "scene/planarity.hpp"
#include "scene/validate_reference.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>
#include <utility>
#include <string>
#include <vector>

namespace shadow {

namespace detail {

PlaneDeviation plane_deviation(const std::vector<glm::dvec3>& vertices, double tolerance) {
  using Real = long double;
  PlaneDeviation out;
  const std::size_t n = vertices.size();
  glm::dvec3 lo = vertices[0], hi = vertices[0];
  for (const glm::dvec3& v : vertices) {
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
  const glm::dvec3 extent = hi - lo;
  const double diameter = std::max({extent.x, extent.y, extent.z});
  out.diameter = diameter;
  // Rounding the input to doubles alone moves a vertex by up to half an ulp of its largest
  // coordinate; a tiny face far from the origin cannot be flatter than that.
  double magnitude = 0;
  for (const glm::dvec3& v : vertices)
    magnitude = std::max({magnitude, std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
  out.allowed = std::max(tolerance * diameter, 8 * std::numeric_limits<double>::epsilon() * magnitude);
  if (!(diameter > 0) || !std::isfinite(diameter)) return out;  // coincident vertices: zero area

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
  if (!(length > noise * 10 / Real(tolerance))) return out;

  cx /= Real(n);
  cy /= Real(n);
  cz /= Real(n);
  Real worst = 0;
  for (const glm::dvec3& v : vertices) {
    const Real px = Real(v.x) - origin.x - cx, py = Real(v.y) - origin.y - cy, pz = Real(v.z) - origin.z - cz;
    worst = std::max(worst, std::fabs((px * nx + py * ny + pz * nz) / length));
  }
  out.worst = static_cast<double>(worst);
  return out;
}

}  // namespace detail

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
  const detail::PlaneDeviation d = detail::plane_deviation(vertices, tolerance);
  if (d.worst > d.allowed) {
    const double allowed = tolerance * d.diameter;
    throw InputError(where, "face is not planar: a vertex is " + format_number(d.worst) +
                                " off its plane (tolerance " + format_number(tolerance) + " x diameter " +
                                format_number(d.diameter) + " = " + format_number(allowed) + ")");
  }
}

using Classifier = detail::FaceShape (*)(const std::vector<glm::dvec3>&);

void validate_face(Scene& scene, std::size_t face_id, const LoadOptions& options,
                   std::vector<Warning>& warnings, Classifier classify = detail::classify_face_shape) {
  Face& face = scene.faces[face_id];
  const SourceLocation where = face_location(scene, face_id);
  detail::check_face_numbers(scene, face_id);
  remove_consecutive_duplicates(face.vertices);
  if (face.vertices.size() < 3)
    throw InputError(where, "face has " + std::to_string(face.vertices.size()) + " distinct " +
                                (face.vertices.size() == 1 ? "vertex" : "vertices") +
                                "; at least 3 are needed");
  check_planarity(face.vertices, options.planarity_tolerance, where);
  switch (classify(face.vertices)) {
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

/// validate_face for every face, on `threads` threads, with the serial loop's outcome: the
/// warnings in face order, or the error of the first face (in face order) that has one. Each
/// face's check reads the scene and changes only that face. Faces are handed out in chunks, each
/// checked in order and stopped at its first error; faces after an error already found are
/// skipped (only faces before the first error matter). (Unlike the serial loop, faces after
/// the failing one may have been cleaned up too when the error is thrown.)
void validate_faces(Scene& scene, const LoadOptions& options, unsigned threads, std::vector<Warning>& warnings) {
  const std::size_t n = scene.faces.size();
  constexpr std::size_t kChunk = 256;
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  struct ChunkOutcome {
    std::vector<Warning> warnings;
    std::exception_ptr error;
  };
  std::vector<ChunkOutcome> outcome(chunks);
  std::atomic<std::size_t> first_error{n};
  core::parallel_for_blocks(n, kChunk, threads, [&](unsigned, std::size_t c, std::size_t begin, std::size_t end) {
    ChunkOutcome& o = outcome[c];
    for (std::size_t f = begin; f < end; ++f) {
      if (f > first_error.load(std::memory_order_relaxed)) return;
      try {
        validate_face(scene, f, options, o.warnings);
      } catch (...) {
        o.error = std::current_exception();
        std::size_t seen = first_error.load();
        while (f < seen && !first_error.compare_exchange_weak(seen, f)) {
        }
        return;
      }
    }
  });
  for (ChunkOutcome& o : outcome) {
    if (o.error) std::rethrow_exception(o.error);
    for (Warning& w : o.warnings) warnings.push_back(std::move(w));
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

/// "faces 3 (\"wall\"), 4, 7 (\"roof\") and 12 more": the first few faces of a part by id and name.
std::string list_faces(const Scene& scene, const std::vector<std::size_t>& ids) {
  constexpr std::size_t kShown = 5;
  std::string text = ids.size() == 1 ? "face " : "faces ";
  for (std::size_t i = 0; i < ids.size() && i < kShown; ++i) {
    if (i > 0) text += ", ";
    text += std::to_string(ids[i]);
    const Face& face = scene.faces[ids[i]];
    if (!face.name.empty()) text += " (\"" + face.name + "\")";
  }
  if (ids.size() > kShown) text += " and " + std::to_string(ids.size() - kShown) + " more";
  const std::string at = scene.faces[ids[0]].source.to_string();
  if (!at.empty()) text += "; the first at " + at;
  return text;
}

/// Checks the closed parts of a mesh (faces joined by shared edges, every edge shared by exactly
/// two faces of the part): faces that point inward, or neighbours that disagree, read silently as
/// attached shadow, so each such part gets a warning naming the mesh and its first faces. With
/// `orient` (Mesh::orient_outward, LoadOptions::orient_outward), such parts are fixed instead: the
/// faces of an inconsistent part are made to agree with its first face (breadth-first over shared
/// edges), then a part with negative signed volume is reversed; the warning says what changed.
/// Open parts (a ground plane, a single wall, a box without a lid) say nothing about inside and
/// outside and are left alone.
/// `reference`: the edges sorted by their coordinates as before (validate_scene_reference).
void check_orientation(Scene& scene, std::size_t mesh_index, bool orient, std::vector<Warning>& warnings,
                       bool reference = false) {
  const Mesh& mesh = scene.meshes[mesh_index];
  // Each distinct vertex (by ==, so -0.0 is 0.0) gets its rank in EdgeKey's lexicographic
  // order; an edge's key is then its two ranks, which compare exactly as the EdgeKeys of its
  // coordinates do. The sort below therefore makes the same comparisons with the same outcomes
  // as a sort of the EdgeKeys, and so the same permutation (ties included: the union-find roots
  // below, and with them the order of the warnings, depend on it), only far cheaper.
  std::vector<std::size_t> faces;  // face_ids of the mesh's non-degenerate faces
  std::size_t corners = 0;
  for (std::size_t f = mesh.first_face; f < mesh.first_face + mesh.face_count && f < scene.faces.size(); ++f) {
    const Face& face = scene.faces[f];
    if (face.mesh != mesh_index || face.degenerate) continue;
    faces.push_back(f);
    corners += face.vertices.size();
  }
  // An edge's key: the ranks of its end points, lowest first, as rank_a * 2^32 + rank_b (so
  // integer order is their lexicographic order); 16 bytes a use, cheap to move in the sort.
  using Key = std::uint64_t;
  struct Use {
    Key key;
    std::uint32_t face;  // index into `faces`
    bool forward;        // run from the lower rank to the higher
  };
  std::vector<Use> edges;
  if (faces.size() < 2) return;
  // Beyond 2^32 corners ranks and face indices would not fit: the coordinate sort then.
  if (corners >= (std::size_t{1} << 32)) reference = true;
  if (reference) {
    // The sort as it was, on the coordinates; then numbered by group, in the sorted order.
    struct OldUse {
      EdgeKey key;
      bool forward;
      std::size_t face;
    };
    std::vector<OldUse> old;
    for (std::size_t i = 0; i < faces.size(); ++i) {
      const std::vector<glm::dvec3>& v = scene.faces[faces[i]].vertices;
      for (std::size_t a = 0; a < v.size(); ++a) {
        const glm::dvec3& p = v[a];
        const glm::dvec3& q = v[(a + 1) % v.size()];
        const bool forward = EdgeKey{p, q} < EdgeKey{q, p};
        old.push_back({forward ? EdgeKey{p, q} : EdgeKey{q, p}, forward, i});
      }
    }
    std::sort(old.begin(), old.end(), [](const OldUse& x, const OldUse& y) { return x.key < y.key; });
    std::size_t group = 0;
    for (std::size_t i = 0; i < old.size(); ++i) {
      if (i > 0 && !(old[i].key.a == old[i - 1].key.a && old[i].key.b == old[i - 1].key.b)) ++group;
      edges.push_back({Key{group}, static_cast<std::uint32_t>(old[i].face), old[i].forward});
    }
  } else {
    std::vector<std::uint32_t> corner_vertex(corners);  // distinct vertex of each corner, face by face
    std::vector<glm::dvec3> distinct;
    {
      std::size_t size = 16;
      while (size < 2 * corners) size *= 2;
      std::vector<std::uint32_t> table(size, UINT32_MAX);
      auto hash = [](const glm::dvec3& v) {
        std::uint64_t h = 0x9e3779b97f4a7c15ULL;
        for (int c = 0; c < 3; ++c) {
          const double x = v[c] + 0.0;  // -0.0 == 0.0
          std::uint64_t b;
          std::memcpy(&b, &x, sizeof b);
          h ^= b + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
          h *= 0xff51afd7ed558ccdULL;
          h ^= h >> 33;
        }
        return static_cast<std::size_t>(h);
      };
      std::size_t c = 0;
      for (std::size_t f : faces)
        for (const glm::dvec3& v : scene.faces[f].vertices) {
          std::size_t h = hash(v) & (size - 1);
          while (table[h] != UINT32_MAX && distinct[table[h]] != v) h = (h + 1) & (size - 1);
          if (table[h] == UINT32_MAX) {
            table[h] = static_cast<std::uint32_t>(distinct.size());
            distinct.push_back(v);
          }
          corner_vertex[c++] = table[h];
        }
    }
    std::vector<std::uint64_t> rank(distinct.size());
    {
      // Distinct points: no ties, so any sort gives the same ranks. Sorted with their index
      // beside them (no indirection in the comparisons).
      struct Ranked {
        glm::dvec3 p;
        std::size_t index;
      };
      std::vector<Ranked> order(distinct.size());
      for (std::size_t i = 0; i < order.size(); ++i) order[i] = {distinct[i], i};
      std::sort(order.begin(), order.end(), [](const Ranked& x, const Ranked& y) {  // EdgeKey's order on points
        return x.p.x != y.p.x ? x.p.x < y.p.x : x.p.y != y.p.y ? x.p.y < y.p.y : x.p.z < y.p.z;
      });
      for (std::size_t i = 0; i < order.size(); ++i) rank[order[i].index] = i;
    }
    edges.reserve(corners);
    for (std::size_t i = 0, c = 0; i < faces.size(); ++i) {
      const std::size_t m = scene.faces[faces[i]].vertices.size();
      for (std::size_t a = 0; a < m; ++a) {
        const std::uint64_t p = rank[corner_vertex[c + a]], q = rank[corner_vertex[c + (a + 1) % m]];
        const bool forward = p < q;
        edges.push_back({forward ? (p << 32 | q) : (q << 32 | p), static_cast<std::uint32_t>(i), forward});
      }
      c += m;
    }
    // Sorted so that the uses of one edge are adjacent: a sort is several times faster than a map.
    std::sort(edges.begin(), edges.end(), [](const Use& x, const Use& y) { return x.key < y.key; });
  }
  std::vector<std::size_t> parent(faces.size());
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = i;
  auto root = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::vector<char> open(faces.size(), 0), inconsistent(faces.size(), 0);
  // Manifold edges: (other face, same direction) for each face, for the breadth-first fix.
  std::vector<std::vector<std::pair<std::size_t, bool>>> neighbours(orient ? faces.size() : 0);
  auto same = [](const Key& x, const Key& y) { return x == y; };
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && same(edges[i].key, edges[j].key)) ++j;
    for (std::size_t k = i + 1; k < j; ++k) parent[root(edges[k].face)] = root(edges[i].face);
    // Closed: every edge exactly twice (once: a border; three times or more: non-manifold).
    if (j - i != 2) {
      open[edges[i].face] = 1;
    } else {
      const bool same_way = edges[i].forward == edges[i + 1].forward;
      if (same_way) inconsistent[edges[i].face] = 1;
      if (orient) {
        neighbours[edges[i].face].push_back({edges[i + 1].face, same_way});
        neighbours[edges[i + 1].face].push_back({edges[i].face, same_way});
      }
    }
    i = j;
  }
  std::vector<char> part_open(faces.size(), 0), part_inconsistent(faces.size(), 0);
  std::vector<std::vector<std::size_t>> members(faces.size());  // by root: the part's face ids
  for (std::size_t f = 0; f < faces.size(); ++f) {
    part_open[root(f)] |= open[f];
    part_inconsistent[root(f)] |= inconsistent[f];
    members[root(f)].push_back(f);
  }
  auto face_ids = [&](const std::vector<std::size_t>& local) {
    std::vector<std::size_t> ids;
    for (std::size_t f : local) ids.push_back(faces[f]);
    return ids;
  };
  auto reverse_face = [&](std::size_t f) {
    std::vector<glm::dvec3>& v = scene.faces[faces[f]].vertices;
    std::reverse(v.begin(), v.end());
  };
  // Signed volume of a part (divergence theorem over fan triangles), relative to one vertex of
  // the part to keep digits.
  using Real = long double;
  auto volume_of = [&](const std::vector<std::size_t>& part) {
    const glm::dvec3 origin = scene.faces[faces[part.front()]].vertices[0];
    Real volume = 0;
    for (std::size_t f : part) {
      const std::vector<glm::dvec3>& v = scene.faces[faces[f]].vertices;
      auto rel = [&](const glm::dvec3& p, int k) { return Real(p[k]) - Real(origin[k]); };
      for (std::size_t i = 1; i + 1 < v.size(); ++i) {
        const glm::dvec3 &a = v[0], &b = v[i], &c = v[i + 1];
        const Real ax = rel(a, 0), ay = rel(a, 1), az = rel(a, 2);
        const Real bx = rel(b, 0), by = rel(b, 1), bz = rel(b, 2);
        const Real cx = rel(c, 0), cy = rel(c, 1), cz = rel(c, 2);
        volume += ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
      }
    }
    return volume;
  };
  std::size_t parts = 0;
  for (std::size_t f = 0; f < faces.size(); ++f) parts += root(f) == f ? 1 : 0;
  const SourceLocation where{scene.source.string(), "meshes[" + std::to_string(mesh_index) + "]"};
  const std::string name = "mesh \"" + mesh.name + "\"";
  auto part_text = [&](const std::vector<std::size_t>& part) {
    return parts == 1 ? name + " (closed, " + list_faces(scene, face_ids(part)) + ")"
                      : name + ": the closed part of " + list_faces(scene, face_ids(part));
  };
  std::size_t inward_parts = 0, mixed_parts = 0;
  std::vector<std::size_t> first_inward, first_mixed;
  // Allocated once: a part's search touches only its own faces, reset before it starts, so a
  // mesh of many inconsistent parts costs O(faces), not O(parts x faces).
  std::vector<int> flip(faces.size(), -1);
  for (std::size_t r = 0; r < faces.size(); ++r) {
    if (root(r) != r || part_open[r]) continue;
    const std::vector<std::size_t>& part = members[r];
    if (part_inconsistent[r]) {
      if (!orient) {
        if (mixed_parts++ == 0) first_mixed = part;
        continue;
      }
      // Breadth-first from the part's first face: a neighbour across an edge run the same way is
      // flipped relative to the face it was reached from.
      for (std::size_t f : part) flip[f] = -1;
      std::vector<std::size_t> queue{part.front()};
      flip[part.front()] = 0;
      bool orientable = true;
      for (std::size_t q = 0; q < queue.size(); ++q) {
        const std::size_t f = queue[q];
        for (const auto& [g, same_way] : neighbours[f]) {
          const int want = flip[f] ^ (same_way ? 1 : 0);
          if (flip[g] < 0) {
            flip[g] = want;
            queue.push_back(g);
          } else if (flip[g] != want) {
            orientable = false;
          }
        }
      }
      if (!orientable) {
        warnings.push_back({where, part_text(part) + " cannot be oriented consistently (a one-sided surface, like a "
                                                     "Moebius strip); its faces were left as they are"});
        continue;
      }
      std::vector<std::size_t> flipped;
      for (std::size_t f : part)
        if (flip[f] == 1) {
          reverse_face(f);
          flipped.push_back(f);
        }
      warnings.push_back({where, part_text(part) + " had inconsistent face orientation (orient outward): to agree "
                                     "with face " + std::to_string(faces[part.front()]) + ", reversed " +
                                     list_faces(scene, face_ids(flipped))});
    }
    if (volume_of(part) < 0) {
      if (orient) {
        for (std::size_t f : part) reverse_face(f);
        warnings.push_back({where, part_text(part) + " pointed inward (negative signed volume): its " +
                                       std::to_string(part.size()) + " faces were reversed (orient outward)"});
      } else if (inward_parts++ == 0) {
        first_inward = part;
      }
    }
  }
  // One part: "mesh "m" is closed, <single> (faces ...)"; else how many parts, and the first's faces.
  auto describe = [&](std::size_t count, const std::vector<std::size_t>& first, const std::string& single,
                      const std::string& plural) {
    const std::string listed = list_faces(scene, face_ids(first));
    if (parts == 1) return name + " is closed, " + single + " (" + listed + ")";
    return name + " has " + std::to_string(count) + " closed part" + (count == 1 ? "" : "s") + " (of " +
           std::to_string(parts) + "; the first has " + listed + ") " + plural;
  };
  if (mixed_parts > 0)
    warnings.push_back({where, describe(mixed_parts, first_mixed, "with inconsistent face orientation",
                                        "with inconsistent face orientation") +
                                   ": some edge is run the same way by both of its faces, so some faces' fronts point "
                                   "inward and those faces will be in their own (attached) shadow; check the vertex "
                                   "order of its faces, or orient it (\"orient\": \"outward\", --orient-outward)"});
  if (inward_parts > 0)
    warnings.push_back({where, describe(inward_parts, first_inward, "and its faces point inward", "whose faces point inward") +
                                   " (negative signed volume): they are lit only from inside, as for a room seen from "
                                   "within; if it is a solid seen from outside, reverse the vertex order of its faces, "
                                   "or orient it (\"orient\": \"outward\", --orient-outward) (this is only a warning)"});
}

}  // namespace

namespace {

/// validate_scene; `reference`: the faces one after the other with classify_face_shape_exact.
void validate_scene_impl(Scene& scene, const LoadOptions& options, bool reference) {
  // Zero cannot be checked in floating point: rounding alone puts vertices off the plane.
  if (!(options.planarity_tolerance > 0) || !std::isfinite(options.planarity_tolerance))
    throw InputError({}, "the planarity tolerance must be a positive finite number, got " +
                             format_number(options.planarity_tolerance));
  for (std::size_t i = 0; i < scene.lights.size(); ++i)
    detail::check_light(scene.lights[i], scene.source.string(), "lights[" + std::to_string(i) + "]");
  for (std::size_t i = 0; i < scene.planes.size(); ++i) detail::check_plane(scene, i);
  std::vector<Warning> warnings;
  if (options.threads > core::kMaxThreads)
    throw InputError({"", "LoadOptions::threads"}, "must be 0 (every hardware thread) to " +
                                                       std::to_string(core::kMaxThreads) + ", got " +
                                                       std::to_string(options.threads));
  if (reference) {
    for (std::size_t f = 0; f < scene.faces.size(); ++f)
      validate_face(scene, f, options, warnings, detail::classify_face_shape_exact);
  } else {
    validate_faces(scene, options, core::resolve_threads(options.threads), warnings);
  }
  for (std::size_t m = 0; m < scene.meshes.size(); ++m)
    check_orientation(scene, m, options.orient_outward || scene.meshes[m].orient_outward, warnings, reference);
  // Validating twice (load_scene, then the caller) must not repeat warnings.
  for (Warning& w : warnings) {
    const bool known = std::any_of(scene.warnings.begin(), scene.warnings.end(), [&](const Warning& old) {
      return old.where.file == w.where.file && old.where.place == w.where.place && old.message == w.message;
    });
    if (!known) scene.warnings.push_back(std::move(w));
  }
}

}  // namespace

void validate_scene(Scene& scene, const LoadOptions& options) { validate_scene_impl(scene, options, false); }

void detail::validate_scene_reference(Scene& scene, const LoadOptions& options) {
  validate_scene_impl(scene, options, true);
}

}  // namespace shadow
