// SPDX-License-Identifier: GPL-3.0-or-later
// The input checks the library cannot do without (scenes built in code may skip validate_scene),
// shared by validation, the face engine and the plane shadows. The lights' checks are in lights.cpp.
#include "core/input_checks.hpp"

#include <shadow/validation.hpp>

#include <cmath>
#include <cstdio>
#include <string>

namespace shadow {

bool detail::finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

bool detail::in_range(const glm::dvec3& v) {
  return std::fabs(v.x) <= max_coordinate && std::fabs(v.y) <= max_coordinate &&
         std::fabs(v.z) <= max_coordinate;  // false for NaN too
}

std::string detail::format_vec(const glm::dvec3& v) {
  return "(" + format_number(v.x) + ", " + format_number(v.y) + ", " + format_number(v.z) + ")";
}

SourceLocation detail::face_location(const Scene& scene, std::size_t face_id) {
  const SourceLocation& source = scene.faces[face_id].source;
  if (!source.file.empty() || !source.place.empty()) return source;
  return {scene.source.string(), "face " + std::to_string(face_id)};
}

std::string detail::coordinate_problem(const glm::dvec3& v, const char* what) {
  if (!finite(v)) return std::string(what) + " that is not finite " + format_vec(v);
  if (!in_range(v))
    return std::string(what) + " beyond the accepted range |x| <= 2^500 (about 3.27e150) " + format_vec(v) +
           " (docs/numeric-contract.md)";
  return {};
}

void detail::check_plane(const Scene& scene, std::size_t index) {
  const Plane& plane = scene.planes[index];
  const std::string file = scene.source.string();
  const std::string path = "planes[" + std::to_string(index) + "]";
  if (!finite(plane.point)) throw InputError({file, path + ".point"}, "point is not finite");
  if (!finite(plane.normal)) throw InputError({file, path + ".normal"}, "normal is not finite");
  if (plane.normal == glm::dvec3(0.0)) throw InputError({file, path + ".normal"}, "normal has zero length");
  std::string problem = coordinate_problem(plane.point, "coordinate");
  if (!problem.empty()) throw InputError({file, path + ".point"}, "point has a " + problem);
  if (!(plane.window >= 0 && plane.window <= max_coordinate))
    throw InputError({file, path + ".window"}, "window must be in [0, 2^500 (about 3.27e150)], got " +
                                                   format_number(plane.window));
}

void detail::check_face_numbers(const Scene& scene, std::size_t face_id) {
  const Face& face = scene.faces[face_id];
  if (face.mesh >= scene.meshes.size())  // Scene::is_receiver() would read past the meshes
    throw InputError(face_location(scene, face_id), "face belongs to mesh " + std::to_string(face.mesh) +
                                                        ", but the scene has " + std::to_string(scene.meshes.size()) +
                                                        (scene.meshes.size() == 1 ? " mesh" : " meshes"));
  const std::vector<glm::dvec3>& vertices = face.vertices;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (in_range(vertices[i])) continue;  // the common case: one test per vertex
    throw InputError(face_location(scene, face_id),
                     "vertex " + std::to_string(i) + " has a " + coordinate_problem(vertices[i], "coordinate"));
  }
}

void detail::check_scene_numbers(const Scene& scene) {
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    check_face_numbers(scene, f);
    const std::vector<glm::dvec3>& vertices = scene.faces[f].vertices;
    // Face preparation assumes what validate_scene() establishes: no zero-length edge.
    for (std::size_t i = 0; i < vertices.size() && vertices.size() > 1; ++i)
      if (vertices[i] == vertices[(i + 1) % vertices.size()])
        throw InputError(face_location(scene, f), "vertices " + std::to_string(i) + " and " +
                                                      std::to_string((i + 1) % vertices.size()) +
                                                      " coincide: call validate_scene() before computing shadows");
  }
  for (std::size_t p = 0; p < scene.planes.size(); ++p) check_plane(scene, p);
}

}  // namespace shadow
