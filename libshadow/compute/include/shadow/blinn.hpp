// SPDX-License-Identifier: GPL-3.0-or-later
/// @file blinn.hpp
/// @brief Blinn's shadow projection matrices: the whole scene flattened onto a plane, from a light,
/// by one 4x4 matrix.
///
/// Conventions (column vectors, homogeneous points x = (X, 1)):
/// - a plane is p = (n, c) with n.X + c = 0; its front (the side it receives light on) is n.X + c > 0;
/// - a light is l = (L, 1) for a point light at L, or (d, 0) for a directional light, d pointing
///   from the scene toward the light (`to_light`);
/// - M = (p.l) I - l p^T. Then M x = (p.l) x - (p.x) l: a homogeneous point on the plane
///   (p . M x = 0) on the line through X and the light. Divide by its w (homogeneous divide) to
///   get the shadow point: S = ((p.l) X - (p.x) L) / ((p.l) - (p.x)) for a point light and
///   S = X - ((p.x) / (p.l)) d for a directional one.
/// - The sign of M is irrelevant (homogeneous). For a point light w = (p.l) - (p.x) is positive
///   for every point below the light's level (p.x < p.l, with p turned so that p.l > 0), behind
///   the plane too, and zero on the plane through the light parallel to the receiving plane.
///   The matrix does not decide what casts: only points strictly between the plane's front and
///   the light do (0 < p.x < p.l), and callers must clip to that slab first (compute_plane_shadows
///   does); a point behind the plane maps to a point on the far side of its foot.
///
/// For the plane z = 0 and a directional light (x_l, y_l, z_l), M is z_l times Blinn's
/// matrix [1 0 -x_l/z_l 0; 0 1 -y_l/z_l 0; 0 0 0 0; 0 0 0 1]; for a point light at
/// (x_l, y_l, z_l) it is minus [-z_l 0 x_l 0; 0 -z_l y_l 0; 0 0 0 0; 0 0 1 -z_l], which gives
/// x_s = (x_l z_p - x_p z_l) / (z_p - z_l) and y_s likewise.
#pragma once

#include <shadow/scene.hpp>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace shadow {

/// The plane (n, c) with n.X + c = 0 of a scene plane (n as given, c = -n.point).
glm::dvec4 plane_equation(const Plane& plane);

/// The light in homogeneous form: (position, 1) or (to_light, 0).
glm::dvec4 homogeneous_light(const Light& light);

/// Blinn's shadow matrix M = (p.l) I - l p^T (GLM, column-major: M[column][row]).
glm::dmat4 shadow_matrix(const glm::dvec4& plane, const glm::dvec4& light);

/// Blinn's shadow matrix for a scene plane and light.
glm::dmat4 shadow_matrix(const Plane& plane, const Light& light);

/// Applies a shadow matrix to a point and divides by w. The result is meaningful (the shadow
/// point) only when w != 0; `w` receives it when non-null.
glm::dvec3 project_with(const glm::dmat4& matrix, const glm::dvec3& point, double* w = nullptr);

}  // namespace shadow
