// SPDX-License-Identifier: GPL-3.0-or-later
/// @file radiosity_picture.hpp
/// @brief Pictures of a radiosity result (`shadow render --radiosity`, docs/radiosity.md): the
/// elements coloured by their radiosity or irradiance (W/m^2) on the value scale with its
/// legend, or in colour: each element's reflected light, its wall colour (the material's RGB
/// reflectance) times its irradiance, plus its emittance, through an exposure.
///
/// Elements are drawn from their fronts only: a face leaves light from its front, and a room
/// seen from outside shows its inside. `smooth` averages the element values at the vertices
/// they share on a face and interpolates across each element (the seed's Gouraud shading of
/// radiosity); flat draws each element in its own value.
#pragma once

#include <shadow/radiosity_output.hpp>
#include <shadow/render/render_image.hpp>
#include <shadow/render/value_picture.hpp>

#include <string>
#include <vector>

namespace shadow::render {

/// What a radiosity picture shows.
enum class RadiosityMode {
  Radiosity,   ///< B, W/m^2 leaving each element, on the value scale with a legend
  Irradiance,  ///< H, W/m^2 arriving, on the value scale with a legend
  Colour,      ///< linear RGB E + rho_rgb H (W/m^2 per channel) times the exposure
};

/// Parses "radiosity", "irradiance" or "colour" (also "color"). @throws InputError
RadiosityMode parse_radiosity_mode(const std::string& text);

struct RadiosityPictureOptions {
  RadiosityMode mode = RadiosityMode::Radiosity;
  /// Average the element values at each vertex over the elements of the same face that share
  /// it (weighted by their areas) and interpolate across each element; false: flat elements.
  bool smooth = false;
};

/// Each element's value (Radiosity, Irradiance: one channel in r, g and b alike) or linear
/// colour in W/m^2 (Colour: emittance + reflectance_rgb x irradiance on each channel).
std::vector<glm::dvec3> radiosity_element_values(const RadiosityFiles& files, RadiosityMode mode);

/// The elements as a mesh of `values` (one per element, in W/m^2), not yet coloured: flat, a
/// triangle fan per element, each triangle carrying its element's value in triangle_colours;
/// smooth, the points shared per face (vertices equal in every bit), each carrying the
/// area-weighted mean of the values of the face's elements that have it, in point_colours.
ColouredMesh radiosity_value_mesh(const RadiosityFiles& files, const std::vector<glm::dvec3>& values, bool smooth);

/// The automatic exposure of a colour picture: the factor that puts the 99th percentile of the
/// brightest channel of `colours` at 0.85 (up or down: W/m^2 have no natural display scale);
/// 1 when every colour is black.
double radiosity_auto_exposure(const std::vector<glm::dvec3>& colours);

/// The picture, seen by `options.shade.camera`, fronts only. Radiosity and Irradiance: the value
/// scale from 0 (value_scale) with its legend always drawn, headed with the quantity and W/m^2.
/// Colour: the colours times options.shade.exposure.scale, times radiosity_auto_exposure when
/// options.shade.exposure.automatic, through its soft shoulder; with options.legend, the wall
/// colours of the materials and the exposure. `image.exposure` is the factor used (Colour).
/// @throws RenderError
Image render_radiosity(const Scene& scene, const RadiosityFiles& files, const RenderOptions& options,
                       const RadiosityPictureOptions& picture);

}  // namespace shadow::render
