// SPDX-License-Identifier: GPL-3.0-or-later
/// @file vector_drawing.hpp
/// @brief The exact vector view (shadow/view.hpp) drawn as SVG (by the project) or PDF (through
/// cairo), as `shadow render SCENE -o view.svg|view.pdf` writes it. See docs/vector-views.md.
#pragma once

#include <shadow/scene.hpp>
#include <shadow/view.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace shadow::render {

/// How a vector view is drawn.
struct VectorStyle {
  bool edges = false;  ///< a thin dark outline around every piece
  std::string title;   ///< the SVG's <title> and the PDF's title
  /// Linear RGB per scene mesh (the PNG's display_materials); empty: each face's material.
  std::vector<glm::dvec3> mesh_colours;
  /// Linear RGB per scene face (the PNG's display_groups: by type); when set, it wins over
  /// mesh_colours.
  std::vector<glm::dvec3> face_colours;
};

/// Whether `path` names a vector output (".svg" or ".pdf", any case).
bool is_vector_output(const std::string& path);

/// Fill colour of a piece as sRGB in [0, 1]: its mesh's colour (style.mesh_colours, else the
/// face's material), lit or in shadow.
glm::dvec3 piece_colour(const Scene& scene, const VectorView& view, const ViewPiece& piece,
                        const VectorStyle& style);

/// Writes the view as SVG: a <g> per face (data-face-id, data-mesh, data-back), a <path> per
/// piece (data-lit), coordinates with 17 significant digits, staged like every output
/// (shadow::write_file_staged). @throws shadow::OutputError naming the file
void write_svg(const Scene& scene, const VectorView& view, const std::filesystem::path& path,
               const VectorStyle& style);

/// Writes the view as a one-page PDF through cairo (drawn in memory, then staged like every
/// output: shadow::write_file_staged), 1 pixel = 1 point. @throws shadow::OutputError naming the
/// file (writing), RenderError naming the file, with cairo's own words, or when libshadow was
/// built without cairo
void write_pdf(const Scene& scene, const VectorView& view, const std::filesystem::path& path,
               const VectorStyle& style);

/// Faces a vector view may have before `shadow render` refuses it (`--max-faces`): the exact
/// view's cost grows faster than the face count (docs/vector-views.md).
constexpr std::size_t kDefaultMaxVectorFaces = 20000;

}  // namespace shadow::render
