// SPDX-License-Identifier: GPL-3.0-or-later
/// @file shaded_mesh.hpp
/// @brief From exact per-light fragments to coloured polygons ready to draw (no VTK here).
///
/// Each face has one set of lit/shadowed fragments per light. To shade a point we need its
/// visibility for every light at once, so the per-light sets of a face are overlaid: the
/// fragments are triangulated and intersected (convex clipping in double precision), giving
/// cells that are wholly lit or wholly shadowed for every light. Their edges are the exact
/// shadow edges of the fragments (rounded to double once), not a shadow map's staircase.
#pragma once

#include <shadow/render/camera.hpp>

#include <shadow/lighting.hpp>
#include <shadow/scene.hpp>
#include <shadow/shadows.hpp>

#include <glm/vec3.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace shadow::render {

/// Shading methods of seed 000.
enum class Shading {
  Flat,     ///< one colour per cell, evaluated at its centroid
  Gouraud,  ///< colours evaluated at cell vertices, interpolated across the cell
  Phong,    ///< colours evaluated per pixel (cells subdivided to about a pixel; see docs/lighting.md)
};

std::string to_string(Shading shading);
bool parse_shading(const std::string& name, Shading& shading);

/// One convex cell of a face on which every light is either lit or shadowed throughout.
struct OverlayCell {
  std::size_t face_id = 0;
  std::vector<glm::dvec3> polygon;  ///< convex, on the face's plane
  std::vector<bool> lit;            ///< one entry per scene light
};

/// The overlay of every light's fragments on every face that has fragments for every light.
/// `result` must hold fragments for every light of `scene` (compute_shadows with polygons on).
std::vector<OverlayCell> overlay_fragments(const Scene& scene, const ShadowResult& result);

/// Triangles (as point index triples) with a colour per point (for Gouraud and Phong) or per
/// triangle (for Flat). Colours are linear RGB clamped to [0, 1].
struct ColouredMesh {
  std::vector<glm::dvec3> points;
  std::vector<std::size_t> triangles;   ///< 3 point indices per triangle
  std::vector<glm::dvec3> point_colours;     ///< Gouraud, Phong: one per point
  std::vector<glm::dvec3> triangle_colours;  ///< Flat: one per triangle
  double exposure = 1.0;  ///< the scale the colours were multiplied by (Exposure)
};

/// How the models' linear colours become displayable ones in [0, 1] (docs/render.md). The
/// defaults keep the models' values, clipped at 1.
struct Exposure {
  /// Scale the colours down (never up) so that `percentile` of the brightest channel of the
  /// shaded points lands at `target`: lit surfaces are not clipped whatever the lights add to.
  bool automatic = false;
  double percentile = 0.99;
  double target = 0.85;
  double scale = 1.0;  ///< multiplies the colours (after the automatic scale)
  /// Above `knee`, values run smoothly toward 1 (knee + (1 - knee)(1 - exp(-(x - knee)/(1 - knee))))
  /// instead of being clipped: highlights keep some shape and pure white needs x > 1.7.
  bool soft_shoulder = false;
  double knee = 0.8;
};

/// The display palette for meshes without a material (linear RGB). Faces whose model says what
/// they are get the colour of their type (display_groups): an EnergyPlus surface type or a
/// CityJSON semantic surface (Face::kind), else the CityJSON object type (Mesh::object_type).
/// Other meshes get one by their role: the ground one calm colour, buildings another, further
/// meshes each their own (see mesh_roles in camera.hpp).
struct Palette {
  glm::dvec3 ground{0.40, 0.46, 0.30};    ///< the ground; CityJSON terrain (TINRelief, LandUse)
  glm::dvec3 building{0.76, 0.60, 0.44};  ///< buildings; EnergyPlus walls
  glm::dvec3 roof{0.55, 0.27, 0.20};      ///< roofs (EnergyPlus Roof, CityJSON RoofSurface)
  glm::dvec3 floor{0.52, 0.50, 0.47};     ///< EnergyPlus floors and ceilings
  glm::dvec3 glass{0.30, 0.55, 0.75};     ///< windows and glass doors (drawn with a highlight)
  glm::dvec3 door{0.36, 0.22, 0.12};      ///< opaque doors
  glm::dvec3 shading{0.42, 0.44, 0.52};   ///< shading surfaces (EnergyPlus Shading:*)
  glm::dvec3 vegetation{0.17, 0.38, 0.12};
  glm::dvec3 water{0.10, 0.28, 0.55};
  glm::dvec3 road{0.30, 0.30, 0.32};
  glm::dvec3 bridge{0.62, 0.58, 0.52};
  glm::dvec3 other{0.45, 0.45, 0.48};     ///< other city objects (furniture, tunnels, ...)
  std::vector<glm::dvec3> others{{0.26, 0.40, 0.62}, {0.60, 0.24, 0.15}, {0.36, 0.24, 0.44},
                                 {0.16, 0.42, 0.38}, {0.60, 0.48, 0.13}, {0.45, 0.45, 0.48}};
  /// Less ambient than Material{} (0.3): shadows read as shadows (lit/shadowed ground about
  /// 1 + 3 cos(sun's zenith angle) : 1).
  double k_a = 0.25, k_d = 0.75, k_s = 0.1, shininess = 16.0;
  /// Glass reflects more, and more sharply.
  double glass_k_s = 0.6, glass_shininess = 64.0;
};

/// `linear` (a model's colour) as displayed under `exposure`: scaled, through the soft shoulder
/// if it is on, clipped to [0, 1] (still linear).
glm::dvec3 expose(const glm::dvec3& linear, const Exposure& exposure, double scale);

/// One material per scene mesh: the mesh's named material where the scene has it; otherwise,
/// with `palette`, a palette material by the mesh's role (ground, building, other in turn);
/// otherwise Material{} (white), as the lighting models' default.
std::vector<Material> display_materials(const Scene& scene, const std::optional<Palette>& palette);

/// A colour the picture uses and what it stands for: one legend row.
struct DisplayGroup {
  std::string label;  ///< a type ("windows (glass)", "roofs", "terrain") or the meshes' names
  Material material;
};

/// The colour of every face (display_groups).
struct DisplayGroups {
  std::vector<DisplayGroup> groups;     ///< in order of first use
  std::vector<std::size_t> face_group;  ///< one per scene face: its index in `groups`
};

/// The type a face is drawn as, by what the model says it is: the face's kind (an EnergyPlus
/// surface type such as Window, GlassDoor, Door, Wall, Roof, Floor, Ceiling, Shading, or a
/// CityJSON semantic surface such as RoofSurface, Window, Door), else its mesh's CityJSON object
/// type. One of "windows (glass)", "doors", "walls", "roofs", "floors, ceilings", "shading",
/// "buildings", "terrain", "vegetation", "water", "roads", "bridges", "other city objects"; empty
/// when the model says nothing (an OBJ file, inline polygons without a kind).
std::string display_type(const Scene& scene, std::size_t face_id);

/// The colour of each face: the mesh's named material where the scene has it (one group per
/// material, labelled by its meshes); otherwise, with `palette`, the palette's colour of the
/// face's display_type (one group per type, labelled by it), or for faces of no type the
/// colour of their mesh's role (ground, building, other in turn; labelled by the meshes);
/// without a palette, Material{} (white).
DisplayGroups display_groups(const Scene& scene, const std::optional<Palette>& palette);

/// What to shade and how.
struct ShadeOptions {
  LightingSettings lighting;
  Shading shading = Shading::Gouraud;
  Camera camera;
  int image_height = 600;  ///< with the camera's view angle, sets the pixel size for Phong
  /// Phong: the largest number of triangles; past it the subdivision is coarser than a pixel.
  std::size_t max_triangles = 2'000'000;
  Exposure exposure;
  /// Meshes without a material get the palette's colours (none: white Material{}).
  std::optional<Palette> palette;
};

/// Colours the overlay cells with the lighting model (materials from `scene`).
ColouredMesh shade_cells(const Scene& scene, const std::vector<OverlayCell>& cells,
                         const ShadeOptions& options);

}  // namespace shadow::render
