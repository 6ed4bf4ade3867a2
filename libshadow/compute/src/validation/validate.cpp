// SPDX-License-Identifier: GPL-3.0-or-later
// Validation of a scene's geometry, for scenes read from files and scenes built in code alike.
//
// Cheap floating-point checks (finite values, planarity within the tolerance) come first, then
// the exact shape check (zero area, self-intersection) from the exact kernel.
#include <shadow/validation.hpp>

#include <glm/common.hpp>

#include "core/input_checks.hpp"
#include "core/lights.hpp"
#include "runtime/parallel.hpp"
#include "exact/face_shape.hpp"
#include "geometry/newell_normal.hpp"
#include "geometry/point_hash.hpp"
#include "validation/planarity.hpp"
#include "validation/validate_reference.hpp"
#include "validation/mesh_orientation.hpp"

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
  // A face in a plane x_k = c (a floor, a flat roof, the ground; every face of an axis-aligned
  // box) is planar, and the sums below say so exactly: relative to the first vertex every
  // coordinate k is 0, so the Newell normal's other two components are sums of products by 0,
  // and every vertex's distance is 0 (or the normal is lost, which gives 0 as well). The same
  // result without them: about a tenth of reading a million faces went there.
  for (int k = 0; k < 3; ++k)
    if (extent[k] == 0) return out;

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
  runtime::parallel_for_blocks(n, kChunk, threads, [&](unsigned, std::size_t c, std::size_t begin, std::size_t end) {
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
  if (options.threads > runtime::kMaxThreads)
    throw InputError({"", "LoadOptions::threads"}, "must be 0 (every hardware thread) to " +
                                                       std::to_string(runtime::kMaxThreads) + ", got " +
                                                       std::to_string(options.threads));
  Rejected rejected;
  if (reference) {
    for (std::size_t f = 0; f < scene.faces.size(); ++f) {
      std::string problem = validate_face(scene, f, options, warnings, detail::classify_face_shape_exact);
      if (!problem.empty()) rejected.emplace_back(f, std::move(problem));
    }
  } else {
    validate_faces(scene, options, runtime::resolve_threads(options.threads), warnings, rejected);
  }
  // Skipped faces leave before anything looks at meshes as wholes (orientation), and before any
  // face_id is handed out: ids count the faces kept.
  remove_rejected(scene, rejected);
  if (!rejected.empty() && scene.faces.empty())  // nothing left to compute: not a result to write
    throw InputError(scene.skipped_faces.front().source,
                     "every face of the scene is invalid (" + std::to_string(scene.skipped_faces.size()) +
                         " skipped with --skip-invalid); this one: " + scene.skipped_faces.front().reason);
  warn_skipped(scene, warnings);
  validation::check_orientations(scene, options, reference, runtime::resolve_threads(options.threads), warnings);
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
  validation::check_orientations(scene, options, reference,
                                    runtime::resolve_threads(runtime::checked_threads(options.threads)), warnings);
  return warnings;
}

}  // namespace shadow
