// SPDX-License-Identifier: GPL-3.0-or-later
/// @file value_picture.hpp
/// @brief Pictures of a value per face (the total irradiation of `shadow irradiance`): each face
/// in the colour of its value on a dark-to-bright scale, with a legend of the scale.
///
/// The colour is the data: no lighting and no shadows are drawn (the shadows are in the values).
/// Brightness (luminance) grows with the value along the whole scale, so a brighter face received
/// more. See docs/render.md.
#pragma once

#include <shadow/render/render_image.hpp>

#include <string>
#include <vector>

namespace shadow::render {

/// The scale of a value picture: from 0 to `top`, labelled every `step`.
struct ValueScale {
  double top = 1.0;   ///< the largest finite value rounded up to a multiple of `step` (at least `step`)
  double step = 1.0;  ///< 1, 2 or 5 times a power of ten: at most 8 labels
  int digits = 0;     ///< decimals the labels need
};

/// The scale for `values` (NaN entries are ignored; negative values count as 0).
ValueScale value_scale(const std::vector<double>& values);

/// The colour of `t` in [0, 1] (clamped) on the value scale, as displayed (sRGB, 0-1): from a
/// dark violet through red and orange to a pale yellow, its luminance increasing throughout.
glm::dvec3 value_colour(double t);

/// An sRGB colour (0-1, as displayed) as linear RGB, what a ColouredMesh holds (render_mesh
/// encodes it back).
glm::dvec3 linear_from_srgb(const glm::dvec3& srgb);

/// Linear RGB (clamped to [0, 1]) as displayed (sRGB, 0-1): what a legend swatch takes.
glm::dvec3 srgb_from_linear(const glm::dvec3& linear);

/// Faces without a value (NaN: they do not receive), as displayed (sRGB): a light grey.
inline constexpr double kNoValueGrey = 0.80;

/// The scene's faces, each flat in the colour of its value (`values`, one per scene face, NaN
/// for none) on `scale`; degenerate faces are left out.
ColouredMesh colour_faces_by_value(const Scene& scene, const std::vector<double>& values, const ValueScale& scale);

/// The legend of `scale` headed `title` (a row per label, the largest first) and, when
/// `options.compass`, the compass (north from the scene's sun block, no suns).
Decorations value_decorations(const Scene& scene, const ValueScale& scale, const RenderOptions& options,
                              const std::string& title);

/// The picture: the coloured faces seen by `options.shade.camera`, a legend in the top left
/// corner headed `title` (a row per label of the scale, the largest first), and a compass when
/// `options.compass` (north from the scene's sun block, no suns). @throws RenderError
Image render_face_values(const Scene& scene, const std::vector<double>& values, const RenderOptions& options,
                         const std::string& title);

}  // namespace shadow::render
