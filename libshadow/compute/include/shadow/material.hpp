// SPDX-License-Identifier: GPL-3.0-or-later
/// @file material.hpp
/// @brief Surface materials for the lighting models (see lighting.hpp and docs/lighting.md).
///
/// A plain struct so that scene.hpp can hold materials without depending on the lighting code.
#pragma once

#include <glm/vec3.hpp>

#include <string>

namespace shadow {

/// How a surface reflects light, in the terms of the seed lecture notes (docs/lighting.md):
/// the ambient term is k_a i_a, the diffuse term is scaled by k_d, the specular one by
/// k_s cos^p. Colours are linear RGB in [0, 1]; the diffuse reflectance is k_d * color.
struct Material {
  std::string name;                         ///< unique within a scene; empty for the default
  double k_a = 0.3;                         ///< ambient coefficient, >= 0
  double k_d = 0.7;                         ///< diffuse coefficient, >= 0
  double k_s = 0.2;                         ///< specular coefficient, >= 0
  double shininess = 32.0;                  ///< Phong exponent p (>= 0): larger is glossier
  glm::dvec3 color{1.0, 1.0, 1.0};          ///< ambient and diffuse colour (M_D)
  glm::dvec3 specular_color{1.0, 1.0, 1.0}; ///< highlight colour (M_S): white for most non-metals
  /// Diffuse (Lambertian) reflectance for radiosity (radiosity.hpp): the fraction of the incident
  /// irradiance that the surface reflects, in [0, 1). 0 (the default): the surface absorbs all.
  /// Given as RGB in the scene file, it is the mean of reflectance_rgb.
  double reflectance = 0.0;
  /// The reflectance per colour channel, for pictures; (r, r, r) when given as one number.
  glm::dvec3 reflectance_rgb{0.0, 0.0, 0.0};
  /// Radiant exitance emitted by the surface's front (W/m^2, >= 0): an emitting face is a
  /// source of radiosity (a luminous ceiling panel). 0 by default.
  double emittance = 0.0;
};

}  // namespace shadow
