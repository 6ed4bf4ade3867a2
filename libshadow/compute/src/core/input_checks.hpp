// SPDX-License-Identifier: GPL-3.0-or-later
// The input checks that the library cannot do without, shared by validation (scene/), the face
// engine (engine/) and the plane shadows (planes/): scenes built in code may skip validate_scene.
// Lights: core/lights.hpp. No CGAL.
#pragma once

#include <shadow/error.hpp>
#include <shadow/scene.hpp>

#include <glm/vec3.hpp>

#include "common/format.hpp"  // format_number

#include <cstddef>
#include <string>
#include <vector>

namespace shadow::detail {

/// `(x, y, z)`, each with format_number.
std::string format_vec(const glm::dvec3& v);
/// All three components finite.
bool finite(const glm::dvec3& v);
/// All three components within max_coordinate (false for NaN too).
bool in_range(const glm::dvec3& v);
/// Where a face came from; faces built in code have no source, so they are named by face_id.
SourceLocation face_location(const Scene& scene, std::size_t face_id);

/// InputError text when `v` is not finite or beyond max_coordinate, else empty.
std::string coordinate_problem(const glm::dvec3& v, const char* what);

/// Throws InputError naming `planes[index]` if the plane's point, normal or window is unusable.
void check_plane(const Scene& scene, std::size_t index);

/// Throws InputError naming the face's source (or `face N`) if the face belongs to no mesh of
/// the scene, or a vertex is not finite or beyond max_coordinate.
void check_face_numbers(const Scene& scene, std::size_t face_id);

/// The cheap part of validation that the library cannot do without (scenes built in code may
/// skip validate_scene): every face vertex, plane point, normal and window finite and within
/// max_coordinate. Linear in the number of vertices.
/// @throws InputError naming the face's source (or `face N`) or the plane.
void check_scene_numbers(const Scene& scene);

}  // namespace shadow::detail
