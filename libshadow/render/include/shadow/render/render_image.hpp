// SPDX-License-Identifier: GPL-3.0-or-later
/// @file render_image.hpp
/// @brief Pictures of a scene with its exact shadows, drawn with VTK off screen.
///
/// Colours come from libshadow's lighting models evaluated on the CPU (shaded_mesh.hpp); VTK
/// only rasterises them, its own lighting switched off. Debian's VTK 9.1 draws through X11
/// (GLX) even off screen, so an X display is needed: on a headless machine run under
/// `xvfb-run -a` (the `shadow render` command does that by itself). See docs/lighting.md.
#pragma once

#include <shadow/render/shaded_mesh.hpp>

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace shadow::render {

/// Rendering failed (no display, no OpenGL context, an unwritable file).
class RenderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// An RGB image, rows from the top, 3 bytes per pixel.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;
  double exposure = 1.0;  ///< the factor the colours were scaled by (render_scene; Exposure)
  /// Red, green, blue of pixel (x, y), y counted from the top.
  [[nodiscard]] const std::uint8_t* pixel(int x, int y) const {
    return rgb.data() + 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x));
  }
};

struct RenderOptions {
  int width = 800;
  int height = 600;
  ShadeOptions shade;                     ///< model, shading method, camera (image_height is set from height)
  glm::dvec3 background{0.93, 0.95, 0.98};  ///< as displayed (sRGB), a pale sky
  /// render_scene: a legend in the top left corner (each mesh group's colour lit and in
  /// shadow, and the lights).
  bool legend = false;
  /// render_scene: a compass in the bottom right corner: north (the scene's sun block's
  /// north_axis, or +y) and the directions of the directional lights (suns) on the ground.
  bool compass = false;
  /// render_mesh: draw the triangles from their front only (counter-clockwise on screen), as a
  /// radiosity result, whose elements leave light from the front, is seen: the walls of a room
  /// seen from outside vanish and show the room inside.
  bool cull_back_faces = false;
};

/// One row of the legend: a label and its colours lit and in shadow (displayed, sRGB 0-1).
struct LegendEntry {
  std::string label;
  glm::dvec3 lit{1.0};
  glm::dvec3 shadow{0.5};
};

/// What is drawn over the picture (render_scene makes it from the scene and the options).
struct Decorations {
  std::vector<LegendEntry> legend;  ///< empty: no legend
  std::string header = "lit, in shadow";  ///< the legend's first line, over its rows
  std::vector<std::string> notes;   ///< lines under the legend's rows (the lights)
  bool compass = false;
  glm::dvec3 anchor{0.0};           ///< a point on the ground the compass directions start from
  glm::dvec3 north{0.0, 1.0, 0.0};  ///< horizontal
  std::vector<glm::dvec3> suns;     ///< horizontal directions toward the suns
};

/// The decorations `options` ask for on `scene` (colours through the exposure `exposure`).
Decorations make_decorations(const Scene& scene, const RenderOptions& options, double exposure);

/// True when an X display is available for VTK's OpenGL (DISPLAY set).
bool display_available();

/// Draws the coloured mesh, and `decorations` over it. @throws RenderError
Image render_mesh(const ColouredMesh& mesh, const RenderOptions& options, const Decorations& decorations = {});

/// Everything: overlay the fragments of `result`, shade, draw. `result` must hold fragment
/// polygons for every light of `scene` on every face to be drawn. @throws RenderError
Image render_scene(const Scene& scene, const ShadowResult& result, const RenderOptions& options);

/// The bytes of a PNG file of `image`, encoded in memory. @throws RenderError
std::string encode_png(const Image& image);

/// Writes a PNG file under the rule of every output (shadow::write_file_staged: a temporary
/// name, a checked close, a rename; nothing at `path` after a failure).
/// @throws RenderError (encoding), shadow::OutputError naming the file (writing)
void write_png(const Image& image, const std::filesystem::path& path);

}  // namespace shadow::render
