// SPDX-License-Identifier: GPL-3.0-or-later
// Validation of a scene's geometry, for scenes read from files and scenes built in code alike.
//
// Cheap floating-point checks (finite values, planarity within the tolerance) come first, then
// the exact shape check (zero area, self-intersection) from the exact kernel.
#include <shadow/validation.hpp>

#include <glm/common.hpp>

#include "core/input_checks.hpp"
#include "core/lights.hpp"
#include "core/parallel.hpp"
#include "exact/face_shape.hpp"
#include "geometry/newell_normal.hpp"
#include "geometry/point_hash.hpp"
#include "validation/planarity.hpp"
#include "validation/validate_reference.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
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

/// The checks of one face; an invalid face throws.
void check_face(Scene& scene, std::size_t face_id, const LoadOptions& options, std::vector<Warning>& warnings,
                Classifier classify) {
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

/// Checks face `face_id`. An invalid face is an InputError whose message says how to skip it;
/// with `options.skip_invalid` its problem is returned instead (empty: the face is kept).
std::string validate_face(Scene& scene, std::size_t face_id, const LoadOptions& options,
                          std::vector<Warning>& warnings, Classifier classify = detail::classify_face_shape) {
  // A face of a mesh that does not exist is a scene built wrongly in code, not a bad face: never
  // skipped (and the skipped face's record needs its mesh).
  if (scene.faces[face_id].mesh >= scene.meshes.size()) detail::check_face_numbers(scene, face_id);
  try {
    check_face(scene, face_id, options, warnings, classify);
  } catch (const InputError& e) {
    if (!options.skip_invalid) throw InputError(e.where(), e.problem() + detail::skip_invalid_hint);
    return e.problem();
  }
  return {};
}

/// A face found invalid with LoadOptions::skip_invalid: its id and the problem.
using Rejected = std::vector<std::pair<std::size_t, std::string>>;

/// validate_face for every face, on `threads` threads, with the serial loop's outcome: the
/// warnings in face order, or the error of the first face (in face order) that has one. Each
/// face's check reads the scene and changes only that face. Faces are handed out in chunks, each
/// checked in order and stopped at its first error; faces after an error already found are
/// skipped (only faces before the first error matter). (Unlike the serial loop, faces after
/// the failing one may have been cleaned up too when the error is thrown.) With skip_invalid
/// nothing is thrown for a bad face: `rejected` gets every invalid face, in face order.
void validate_faces(Scene& scene, const LoadOptions& options, unsigned threads, std::vector<Warning>& warnings,
                    Rejected& rejected) {
  const std::size_t n = scene.faces.size();
  constexpr std::size_t kChunk = 256;
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  struct ChunkOutcome {
    std::vector<Warning> warnings;
    Rejected rejected;
    std::exception_ptr error;
  };
  std::vector<ChunkOutcome> outcome(chunks);
  std::atomic<std::size_t> first_error{n};
  core::parallel_for_blocks(n, kChunk, threads, [&](unsigned, std::size_t c, std::size_t begin, std::size_t end) {
    ChunkOutcome& o = outcome[c];
    for (std::size_t f = begin; f < end; ++f) {
      if (f > first_error.load(std::memory_order_relaxed)) return;
      try {
        std::string problem = validate_face(scene, f, options, o.warnings);
        if (!problem.empty()) o.rejected.emplace_back(f, std::move(problem));
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
    for (auto& r : o.rejected) rejected.push_back(std::move(r));
  }
}

/// Removes the rejected faces (ascending ids) from the scene, recording each in
/// Scene::skipped_faces; the faces after them move down, and every mesh's first_face and
/// face_count follow (a mesh may be left with none).
void remove_rejected(Scene& scene, const Rejected& rejected) {
  if (rejected.empty()) return;
  std::vector<char> drop(scene.faces.size(), 0);
  for (const auto& [f, problem] : rejected) {
    const Face& face = scene.faces[f];
    drop[f] = 1;
    scene.skipped_faces.push_back({face.name, scene.meshes[face.mesh].name, face_location(scene, f), problem});
  }
  // New first_face of each mesh: the number of faces kept before its old first face.
  std::vector<std::size_t> kept_before(scene.faces.size() + 1, 0);
  for (std::size_t f = 0; f < scene.faces.size(); ++f) kept_before[f + 1] = kept_before[f] + (drop[f] ? 0 : 1);
  for (Mesh& mesh : scene.meshes) {
    const std::size_t begin = std::min(mesh.first_face, scene.faces.size());
    const std::size_t end = std::min(mesh.first_face + mesh.face_count, scene.faces.size());
    mesh.first_face = kept_before[begin];
    mesh.face_count = kept_before[end] - kept_before[begin];
  }
  std::size_t out = 0;
  for (std::size_t f = 0; f < scene.faces.size(); ++f)
    if (!drop[f]) {
      if (out != f) scene.faces[out] = std::move(scene.faces[f]);
      ++out;
    }
  scene.faces.resize(out);
}

/// One warning per skipped face, the first kMaxSkipWarnings of them, then one line for the rest
/// (a broken city model may have thousands; report.json lists them all).
void warn_skipped(const Scene& scene, std::vector<Warning>& warnings) {
  constexpr std::size_t kMaxSkipWarnings = 10;
  const std::vector<SkippedFace>& skipped = scene.skipped_faces;
  for (std::size_t i = 0; i < skipped.size() && i < kMaxSkipWarnings; ++i) {
    const SkippedFace& s = skipped[i];
    const std::string what = s.name.empty() ? "face of mesh \"" + s.mesh + "\""
                                            : "face \"" + s.name + "\" (mesh \"" + s.mesh + "\")";
    warnings.push_back({s.source, "skipped (--skip-invalid): the " + what + " is invalid: " + s.reason});
  }
  if (skipped.size() > kMaxSkipWarnings)
    warnings.push_back({{scene.source.string(), ""},
                        std::to_string(skipped.size() - kMaxSkipWarnings) + " more invalid faces were skipped (" +
                            std::to_string(skipped.size()) + " in all; report.json lists each in skipped_faces)"});
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

/// An edge use of a mesh: the edge's key (equal for the uses of one edge), the face (index into
/// the mesh's list of faces) and whether it runs the edge forward (from its lower end point, in
/// whatever order the keys were made with, to the higher).
struct EdgeUse {
  std::uint64_t key;
  std::uint32_t face;
  bool forward;
};

/// Meshes of this many faces or more are checked on every thread (grouped_edge_uses, parts in
/// parallel); smaller ones many at once, one thread each, with the coordinate sort.
constexpr std::size_t kLargeMesh = 4096;

/// 256 shards, chosen by a hash's top byte: the parallel grouping's unit of work (a fixed
/// number, so that the work does not depend on the thread count).
constexpr std::size_t kShards = 256;

/// The items make(i) for i in [0, n), grouped by shard_of(i) < kShards and in index order within
/// a shard (a counting scatter, in parallel over blocks of indices): shard s is
/// out[start[s], start[s + 1]). Reading the inputs in order and writing each shard's items one
/// after the other keeps the memory traffic sequential.
template <class T, class ShardOf, class Make>
void scatter_by_shard(std::size_t n, unsigned threads, const ShardOf& shard_of, const Make& make, std::vector<T>& out,
                      std::vector<std::size_t>& start) {
  constexpr std::size_t kBlock = std::size_t{1} << 16;
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::size_t> at(blocks * kShards, 0);
  core::parallel_for_blocks(n, kBlock, threads, [&](unsigned, std::size_t b, std::size_t begin, std::size_t end) {
    std::size_t* count = &at[b * kShards];
    for (std::size_t i = begin; i < end; ++i) ++count[shard_of(i)];
  });
  start.assign(kShards + 1, 0);
  std::size_t next = 0;
  for (std::size_t s = 0; s < kShards; ++s) {
    start[s] = next;
    for (std::size_t b = 0; b < blocks; ++b) {
      const std::size_t count = at[b * kShards + s];
      at[b * kShards + s] = next;
      next += count;
    }
  }
  start[kShards] = next;
  out.resize(n);
  core::parallel_for_blocks(n, kBlock, threads, [&](unsigned, std::size_t b, std::size_t begin, std::size_t end) {
    std::size_t* place = &at[b * kShards];
    for (std::size_t i = begin; i < end; ++i) out[place[shard_of(i)]++] = make(i);
  });
}

/// Numbers the `n` items of a shard by first use, items equal by same(a, b) sharing a number:
/// number[i] for i in [0, n), counting up from 0; returns how many numbers. An open-addressing
/// table, slots chosen by the low bits of hash(i), holds each number's first item (n < 2^32).
template <class Hash, class Same>
std::uint32_t number_by_first_use(std::size_t n, const Hash& hash, const Same& same, std::uint32_t* number) {
  std::size_t size = 16;
  while (size < 2 * n) size *= 2;
  std::vector<std::uint32_t> table(size, UINT32_MAX);  // a number's first item
  std::uint32_t next = 0;
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t h = static_cast<std::size_t>(hash(i)) & (size - 1);
    while (table[h] != UINT32_MAX && !same(table[h], i)) h = (h + 1) & (size - 1);
    if (table[h] == UINT32_MAX) {
      table[h] = static_cast<std::uint32_t>(i);
      number[i] = next++;
    } else {
      number[i] = number[table[h]];
    }
  }
  return next;
}

using geometry::mix64;
using geometry::point_hash;  // -0.0 hashed as 0.0, as == compares them

/// The uses of the edges of `faces` (corners in all, below 2^32), grouped so that the uses of
/// one edge are adjacent, on `threads` threads: the corners scattered into shards by their
/// point's hash and numbered in each shard (an open-addressing table, points equal by ==), each
/// edge keyed by its two end points' numbers, the uses scattered into shards by their key's hash
/// and grouped in each shard (a table of its keys). Neither the order of the groups nor the
/// order within a group is the serial sort's; the part search below does not depend on them.
std::vector<EdgeUse> grouped_edge_uses(const Scene& scene, const std::vector<std::size_t>& faces, std::size_t corners,
                                       unsigned threads) {
  std::vector<std::size_t> offset(faces.size() + 1, 0);  // each face's first corner
  std::vector<std::uint32_t> face_of(corners);
  for (std::size_t i = 0; i < faces.size(); ++i) offset[i + 1] = offset[i] + scene.faces[faces[i]].vertices.size();
  constexpr std::size_t kFaceBlock = 4096;
  core::parallel_for_blocks(faces.size(), kFaceBlock, threads, [&](unsigned, std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      std::fill(face_of.begin() + static_cast<std::ptrdiff_t>(offset[i]), face_of.begin() + static_cast<std::ptrdiff_t>(offset[i + 1]),
                static_cast<std::uint32_t>(i));
  });
  auto point = [&](std::size_t c) -> const glm::dvec3& {
    return scene.faces[faces[face_of[c]]].vertices[c - offset[face_of[c]]];
  };
  // Each corner's point with its hash and corner, by shard (the hash's top byte).
  struct Corner {
    glm::dvec3 p;
    std::uint32_t corner, hash;  // the hash's low bits: the slot in the shard's table
  };
  std::vector<Corner> by_shard;
  std::vector<std::size_t> start;
  {
    std::vector<std::uint64_t> hash(corners);
    core::parallel_for_blocks(corners, std::size_t{1} << 16, threads, [&](unsigned, std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t c = begin; c < end; ++c) hash[c] = point_hash(point(c));
    });
    scatter_by_shard(
        corners, threads, [&](std::size_t c) { return static_cast<std::size_t>(hash[c] >> 56); },
        [&](std::size_t c) { return Corner{point(c), static_cast<std::uint32_t>(c), static_cast<std::uint32_t>(hash[c])}; },
        by_shard, start);
  }
  // Vertex numbers: within a shard by first use (number_by_first_use), then offset by the shards before it.
  std::vector<std::uint32_t> local(corners);  // by shard order: the corner's number in its shard
  std::vector<std::size_t> distinct(kShards + 1, 0);
  core::parallel_for(kShards, threads, [&](unsigned, std::size_t s) {
    const Corner* c = by_shard.data() + start[s];
    distinct[s] = number_by_first_use(
        start[s + 1] - start[s], [&](std::size_t i) { return c[i].hash; },
        [&](std::size_t a, std::size_t b) { return c[a].p == c[b].p; }, local.data() + start[s]);
  });
  std::size_t base = 0;
  for (std::size_t s = 0; s < kShards; ++s) {
    const std::size_t n = distinct[s];
    distinct[s] = base;
    base += n;
  }
  std::vector<std::uint32_t> vertex(corners);  // by corner: its point's number
  core::parallel_for(kShards, threads, [&](unsigned, std::size_t s) {
    const auto shift = static_cast<std::uint32_t>(distinct[s]);
    for (std::size_t k = start[s]; k < start[s + 1]; ++k) vertex[by_shard[k].corner] = local[k] + shift;
  });
  by_shard = {};
  local = {};
  // Each corner's edge (to the next corner of its face), by shard of its key's hash.
  auto use = [&](std::size_t c) {
    const std::size_t i = face_of[c];
    const std::uint64_t p = vertex[c], q = vertex[c + 1 < offset[i + 1] ? c + 1 : offset[i]];
    const bool forward = p < q;
    return EdgeUse{forward ? (p << 32 | q) : (q << 32 | p), static_cast<std::uint32_t>(i), forward};
  };
  std::vector<EdgeUse> uses;
  scatter_by_shard(
      corners, threads, [&](std::size_t c) { return static_cast<std::size_t>(mix64(use(c).key) >> 56); }, use, uses,
      start);
  vertex = {};
  face_of = {};
  // Within a shard, the uses of one edge made adjacent: each key's group numbered by first use
  // (number_by_first_use), then the uses placed group after group.
  std::vector<EdgeUse> grouped(corners);
  core::parallel_for(kShards, threads, [&](unsigned, std::size_t s) {
    const std::size_t n = start[s + 1] - start[s];
    const EdgeUse* u = uses.data() + start[s];
    std::vector<std::uint32_t> group(n);  // each use's group
    const std::uint32_t groups = number_by_first_use(
        n, [&](std::size_t i) { return mix64(u[i].key); },
        [&](std::size_t a, std::size_t b) { return u[a].key == u[b].key; }, group.data());
    std::vector<std::uint32_t> place(groups, 0);  // each group's size, then its next place
    for (const std::uint32_t g : group) ++place[g];
    std::uint32_t next = 0;
    for (std::uint32_t& p : place) {
      const std::uint32_t count = p;
      p = next;
      next += count;
    }
    for (std::size_t k = 0; k < n; ++k) grouped[start[s] + place[group[k]]++] = uses[start[s] + k];
  });
  return grouped;
}

/// The uses of the edges of `faces`, sorted by their end points' coordinates, one thread: the
/// serial reference (validate_scene_reference) of grouped_edge_uses. Keys are the group numbers.
std::vector<EdgeUse> sorted_edge_uses(const Scene& scene, const std::vector<std::size_t>& faces) {
  struct CoordinateUse {
    EdgeKey key;
    bool forward;
    std::size_t face;
  };
  std::vector<CoordinateUse> uses;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const std::vector<glm::dvec3>& v = scene.faces[faces[i]].vertices;
    for (std::size_t a = 0; a < v.size(); ++a) {
      const glm::dvec3& p = v[a];
      const glm::dvec3& q = v[(a + 1) % v.size()];
      const bool forward = EdgeKey{p, q} < EdgeKey{q, p};
      uses.push_back({forward ? EdgeKey{p, q} : EdgeKey{q, p}, forward, i});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const CoordinateUse& x, const CoordinateUse& y) { return x.key < y.key; });
  std::vector<EdgeUse> edges;
  edges.reserve(uses.size());
  std::uint64_t group = 0;
  for (std::size_t i = 0; i < uses.size(); ++i) {
    if (i > 0 && !(uses[i].key.a == uses[i - 1].key.a && uses[i].key.b == uses[i - 1].key.b)) ++group;
    edges.push_back({group, static_cast<std::uint32_t>(uses[i].face), uses[i].forward});
  }
  return edges;
}

/// Checks the closed parts of a mesh (faces joined by shared edges, every edge shared by exactly
/// two faces of the part): faces that point inward, or neighbours that disagree, read silently as
/// attached shadow, so each such part gets a warning naming the mesh and its first faces. With
/// `orient` (Mesh::orient_outward, LoadOptions::orient_outward), such parts are fixed instead: the
/// faces of an inconsistent part are made to agree with its first face (breadth-first over shared
/// edges), then a part with negative signed volume is reversed; the warning says what changed.
/// Open parts (a ground plane, a single wall, a box without a lid) say nothing about inside and
/// outside and are left alone.
///
/// Parts are taken in the order of their first faces (each part's union-find root is its lowest
/// face, whatever order the unions come in), so the outcome does not depend on how the edge uses
/// were grouped: on `threads` threads (grouped_edge_uses, the parts checked in parallel) it is
/// the serial `reference`'s (sorted_edge_uses, one thread) for any thread count.
void check_orientation(Scene& scene, std::size_t mesh_index, bool orient, std::vector<Warning>& warnings,
                       bool reference, unsigned threads) {
  const Mesh& mesh = scene.meshes[mesh_index];
  std::vector<std::size_t> faces;  // face_ids of the mesh's non-degenerate faces
  std::size_t corners = 0;
  for (std::size_t f = mesh.first_face; f < mesh.first_face + mesh.face_count && f < scene.faces.size(); ++f) {
    const Face& face = scene.faces[f];
    if (face.mesh != mesh_index || face.degenerate) continue;
    faces.push_back(f);
    corners += face.vertices.size();
  }
  if (faces.size() < 2) return;
  if (reference) threads = 1;
  // The coordinate sort for the reference, for small meshes (where the shards' tables would
  // cost more than the sort) and beyond 2^32 corners (vertex numbers and face indices would not
  // fit); else the parallel grouping.
  const bool grouped = !reference && faces.size() >= kLargeMesh && corners < (std::size_t{1} << 32);
  const std::vector<EdgeUse> edges =
      grouped ? grouped_edge_uses(scene, faces, corners, threads) : sorted_edge_uses(scene, faces);
  const std::size_t n = faces.size();
  std::vector<std::size_t> parent(n);
  for (std::size_t i = 0; i < n; ++i) parent[i] = i;
  auto root = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  // The lower root becomes the root: a part's root is its lowest face, whatever the order.
  auto unite = [&](std::size_t a, std::size_t b) {
    a = root(a);
    b = root(b);
    if (a < b)
      parent[b] = a;
    else if (b < a)
      parent[a] = b;
  };
  std::vector<char> open(n, 0), inconsistent(n, 0);
  // Manifold edges: (other face, same direction) for each face, for the breadth-first fix.
  std::vector<std::vector<std::pair<std::size_t, bool>>> neighbours(orient ? n : 0);
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[i].key == edges[j].key) ++j;
    for (std::size_t k = i + 1; k < j; ++k) unite(edges[i].face, edges[k].face);
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
  // Each part's faces, ascending, by root (a counting sort: members of part r are
  // member[first[r], first[r + 1])).
  std::vector<std::size_t> root_of(n), first(n + 1, 0), member(n);
  std::vector<char> part_open(n, 0), part_inconsistent(n, 0);
  for (std::size_t f = 0; f < n; ++f) {
    root_of[f] = root(f);
    ++first[root_of[f] + 1];
    part_open[root_of[f]] |= open[f];
    part_inconsistent[root_of[f]] |= inconsistent[f];
  }
  for (std::size_t r = 0; r < n; ++r) first[r + 1] += first[r];
  {
    std::vector<std::size_t> next(first.begin(), first.end() - 1);
    for (std::size_t f = 0; f < n; ++f) member[next[root_of[f]]++] = f;
  }
  auto part_of = [&](std::size_t r) {
    return std::vector<std::size_t>(member.begin() + static_cast<std::ptrdiff_t>(first[r]),
                                    member.begin() + static_cast<std::ptrdiff_t>(first[r + 1]));
  };
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
  auto volume_of = [&](std::size_t r) {
    const glm::dvec3 origin = scene.faces[faces[member[first[r]]]].vertices[0];
    Real volume = 0;
    for (std::size_t k = first[r]; k < first[r + 1]; ++k) {
      const std::vector<glm::dvec3>& v = scene.faces[faces[member[k]]].vertices;
      auto rel = [&](const glm::dvec3& p, int c) { return Real(p[c]) - Real(origin[c]); };
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
  // Each closed part on its own (in parallel: a part changes only its own faces): made
  // consistent and outward with `orient`, else only looked at.
  std::vector<std::size_t> closed;  // roots, ascending
  std::size_t parts = 0;
  for (std::size_t r = 0; r < n; ++r) {
    if (root_of[r] != r) continue;
    ++parts;
    if (!part_open[r]) closed.push_back(r);
  }
  enum Outcome : char { kFine, kMixed, kOneSided, kInward };
  struct PartOutcome {
    Outcome outcome = kFine;
    bool made_consistent = false;
    std::vector<std::size_t> flipped;  // made consistent: the faces reversed
  };
  std::vector<PartOutcome> outcome(closed.size());
  // A part's search touches only its own faces, reset before it starts: one array for all.
  std::vector<int> flip(orient ? n : 0, -1);
  core::parallel_for_blocks(closed.size(), 64, threads, [&](unsigned, std::size_t, std::size_t begin, std::size_t end) {
    std::vector<std::size_t> queue;
    for (std::size_t p = begin; p < end; ++p) {
      const std::size_t r = closed[p];
      PartOutcome& o = outcome[p];
      if (part_inconsistent[r]) {
        if (!orient) {
          o.outcome = kMixed;
          continue;
        }
        // Breadth-first from the part's first face: a neighbour across an edge run the same way
        // is flipped relative to the face it was reached from.
        queue.assign(1, r);
        flip[r] = 0;
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
          o.outcome = kOneSided;
          continue;
        }
        o.made_consistent = true;
        for (std::size_t k = first[r]; k < first[r + 1]; ++k)
          if (flip[member[k]] == 1) {
            reverse_face(member[k]);
            o.flipped.push_back(member[k]);
          }
      }
      if (volume_of(r) < 0) {
        o.outcome = kInward;
        if (orient)
          for (std::size_t k = first[r]; k < first[r + 1]; ++k) reverse_face(member[k]);
      }
    }
  });
  const SourceLocation where{scene.source.string(), "meshes[" + std::to_string(mesh_index) + "]"};
  const std::string name = "mesh \"" + mesh.name + "\"";
  auto part_text = [&](const std::vector<std::size_t>& part) {
    return parts == 1 ? name + " (closed, " + list_faces(scene, face_ids(part)) + ")"
                      : name + ": the closed part of " + list_faces(scene, face_ids(part));
  };
  std::size_t inward_parts = 0, mixed_parts = 0;
  std::vector<std::size_t> first_inward, first_mixed;
  for (std::size_t p = 0; p < closed.size(); ++p) {
    const PartOutcome& o = outcome[p];
    const std::size_t r = closed[p];
    if (o.outcome == kMixed) {
      if (mixed_parts++ == 0) first_mixed = part_of(r);
      continue;
    }
    if (o.outcome == kOneSided) {
      warnings.push_back({where, part_text(part_of(r)) + " cannot be oriented consistently (a one-sided surface, like "
                                                         "a Moebius strip); its faces were left as they are"});
      continue;
    }
    if (o.made_consistent)
      warnings.push_back({where, part_text(part_of(r)) + " had inconsistent face orientation (orient outward): to "
                                     "agree with face " + std::to_string(faces[r]) + ", reversed " +
                                     list_faces(scene, face_ids(o.flipped))});
    if (o.outcome == kInward) {
      if (orient)
        warnings.push_back({where, part_text(part_of(r)) + " pointed inward (negative signed volume): its " +
                                       std::to_string(first[r + 1] - first[r]) + " faces were reversed (orient outward)"});
      else if (inward_parts++ == 0)
        first_inward = part_of(r);
    }
  }
  // One part: "mesh "m" is closed, <single> (faces ...)"; else how many parts, and the first's faces.
  auto describe = [&](std::size_t count, const std::vector<std::size_t>& first_part, const std::string& single,
                      const std::string& plural) {
    const std::string listed = list_faces(scene, face_ids(first_part));
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

/// Every mesh's orientation check, the warnings in mesh order. Meshes below kLargeMesh faces
/// (a building each, say) are checked many at once, one thread each; larger ones one after the
/// other on every thread. `reference`: one mesh after the other, one thread, the coordinate sort.
void check_orientations(Scene& scene, const LoadOptions& options, bool reference, unsigned threads,
                        std::vector<Warning>& warnings) {
  std::vector<std::vector<Warning>> per_mesh(scene.meshes.size());
  auto orient = [&](std::size_t m) { return options.orient_outward || scene.meshes[m].orient_outward; };
  if (reference) {
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) check_orientation(scene, m, orient(m), per_mesh[m], true, 1);
  } else {
    core::parallel_for_blocks(scene.meshes.size(), 16, threads, [&](unsigned, std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t m = begin; m < end; ++m)
        if (scene.meshes[m].face_count < kLargeMesh) check_orientation(scene, m, orient(m), per_mesh[m], false, 1);
    });
    for (std::size_t m = 0; m < scene.meshes.size(); ++m)
      if (scene.meshes[m].face_count >= kLargeMesh) check_orientation(scene, m, orient(m), per_mesh[m], false, threads);
  }
  for (std::vector<Warning>& mesh_warnings : per_mesh)
    for (Warning& w : mesh_warnings) warnings.push_back(std::move(w));
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
  Rejected rejected;
  if (reference) {
    for (std::size_t f = 0; f < scene.faces.size(); ++f) {
      std::string problem = validate_face(scene, f, options, warnings, detail::classify_face_shape_exact);
      if (!problem.empty()) rejected.emplace_back(f, std::move(problem));
    }
  } else {
    validate_faces(scene, options, core::resolve_threads(options.threads), warnings, rejected);
  }
  // Skipped faces leave before anything looks at meshes as wholes (orientation), and before any
  // face_id is handed out: ids count the faces kept.
  remove_rejected(scene, rejected);
  if (!rejected.empty() && scene.faces.empty())  // nothing left to compute: not a result to write
    throw InputError(scene.skipped_faces.front().source,
                     "every face of the scene is invalid (" + std::to_string(scene.skipped_faces.size()) +
                         " skipped with --skip-invalid); this one: " + scene.skipped_faces.front().reason);
  warn_skipped(scene, warnings);
  check_orientations(scene, options, reference, core::resolve_threads(options.threads), warnings);
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

std::vector<Warning> detail::check_mesh_orientation(Scene& scene, const LoadOptions& options, bool reference) {
  std::vector<Warning> warnings;
  check_orientations(scene, options, reference, core::resolve_threads(core::checked_threads(options.threads)), warnings);
  return warnings;
}

}  // namespace shadow
