// SPDX-License-Identifier: GPL-3.0-or-later
/// @file lighting.hpp
/// @brief How bright a point is: physical irradiance and the local lighting models of the
///        seed lecture notes (ambient, Lambert, half-Lambert, the two-light modified
///        half-Lambert, Phong, Blinn–Phong), with shadows deciding which lights arrive.
///
/// Shadows (shadows.hpp) say *whether* a light reaches a point; these functions say *how much*
/// it contributes. Everything here is a pure function of plain structs (GLM, no CGAL, no VTK).
/// Formulas, with the seed equation each one implements, are in docs/lighting.md.
#pragma once

#include <shadow/material.hpp>
#include <shadow/scene.hpp>

#include <glm/vec3.hpp>

#include <string>
#include <vector>

namespace shadow {

/// Physical irradiance that `light` delivers at a point with unit normal `normal`
/// (no shadowing: multiply by 0 when the point is in shadow):
/// directional: I max(0, n.l); point: I max(0, n.l) / r^2, r the distance to the light.
/// Returns 0 for a point light at the point itself (r = 0) and for a zero light direction.
/// An area light or a disk counts as a point light at its centre, a sun disk as its central
/// direction (centre_light); the exact irradiance of an extended light is light_irradiance
/// (area_lights.hpp).
[[nodiscard]] double irradiance(const Light& light, const glm::dvec3& point, const glm::dvec3& normal);

/// Unit vector from `point` toward `light` (the light's to_light for a directional light),
/// or zero when it has no direction. Toward the centre of an area light or disk (centre_light).
[[nodiscard]] glm::dvec3 direction_to_light(const Light& light, const glm::dvec3& point);

/// The local lighting models. Each one adds the ambient term k_a i_a (seed 000) to its
/// per-light terms; a light that does not reach the point (shadowed) contributes nothing.
enum class LightingModel {
  Ambient,              ///< k_a i_a only
  Lambert,              ///< + k_d I C_L M_D max(0, N.L)                       (seeds 000, 003)
  HalfLambert,          ///< + k_d I C_L M_D (0.5 N.L + 0.5)                   (seed 003)
  ModifiedHalfLambert,  ///< + k_d M_D [I C_L H + I_B C_B (1 - H)], H = 0.5 N.L + 0.5 (seed 003)
  Phong,                ///< Lambert + k_s I C_L M_S max(0, R.V)^p             (seeds 000, 003)
  BlinnPhong,           ///< Lambert + k_s I C_L M_S max(0, N.H)^p, H = (L+V)/|L+V| (seed 003)
};

/// How a light's terms fall off with distance.
enum class Attenuation {
  None,           ///< factor 1
  InverseSquare,  ///< 1 / r^2, r = distance from the point to a point light (1 for directional)
  ViewerLinear,   ///< 1 / (d + K), d = distance from the viewer to the point (seeds 000 and 001)
  LightLinear,    ///< 1 / (d + K), d = distance from the point to a point light (1 for directional)
};

/// Settings of one shading evaluation that are not properties of a surface.
struct LightingSettings {
  LightingModel model = LightingModel::BlinnPhong;
  Attenuation attenuation = Attenuation::None;
  double attenuation_k = 1.0;                  ///< K of 1/(d + K); must keep d + K > 0
  double ambient_intensity = 1.0;              ///< i_a
  glm::dvec3 ambient_color{1.0, 1.0, 1.0};     ///< colour of the ambient light
  /// ModifiedHalfLambert's back light (I_B, C_LB of seed 003): a fill light opposite to each
  /// scene light that lights what that light leaves dark. It is stylised, casts no shadow and
  /// is attenuated like its light.
  double back_intensity = 0.5;
  glm::dvec3 back_color{0.55, 0.6, 0.75};
};

/// One point to shade: where it is, its unit surface normal and where the viewer stands.
struct ShadingPoint {
  glm::dvec3 position{0.0};
  glm::dvec3 normal{0.0, 0.0, 1.0};
  glm::dvec3 viewer{0.0, 0.0, 1.0};
};

/// Linear RGB reflected toward the viewer at `point` (not clamped: values above 1 are
/// over-exposed). `lit[j]` says whether `lights[j]` reaches the point (true: lit, false: in
/// shadow); lights without an entry count as lit. Several lights add up (seed 000).
/// Only a face's front can be lit: a viewer behind the point (normal . (viewer - position) < 0)
/// sees the back side, which no scene light reaches (ambient only; ModifiedHalfLambert's fill
/// light still lights it, with the back side's normal).
[[nodiscard]] glm::dvec3 shade(const ShadingPoint& point, const Material& material,
                               const std::vector<Light>& lights, const std::vector<bool>& lit,
                               const LightingSettings& settings);

/// The attenuation factor of `light` at `position` seen from `viewer` (see Attenuation).
[[nodiscard]] double attenuation_factor(const Light& light, const glm::dvec3& position,
                                        const glm::dvec3& viewer, const LightingSettings& settings);

/// Names used on the command line and in docs: "ambient", "lambert", "half-lambert",
/// "modified-half-lambert", "phong", "blinn-phong".
[[nodiscard]] std::string to_string(LightingModel model);
/// "none", "inverse-square", "viewer-linear", "light-linear".
[[nodiscard]] std::string to_string(Attenuation attenuation);
/// Parses a name of to_string(LightingModel); false when it is none of them.
bool parse_lighting_model(const std::string& name, LightingModel& model);
/// Parses a name of to_string(Attenuation); false when it is none of them.
bool parse_attenuation(const std::string& name, Attenuation& attenuation);

}  // namespace shadow
