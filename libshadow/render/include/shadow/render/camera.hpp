// SPDX-License-Identifier: GPL-3.0-or-later
/// @file camera.hpp
/// @brief The camera of `shadow render`, raster and vector views alike: one place that turns a
///        scene and the user's camera options into the view (no VTK here).
///
/// The default view frames what casts and receives shadows: every mesh but the ground, and the
/// shadows those meshes cast on the ground, not the whole ground plane (a house on a 200 m site
/// would otherwise fill an eighth of the picture). The scene file's `camera`, then the command
/// line options, replace any part of it. See docs/render.md.
#pragma once

#include <shadow/scene.hpp>

#include <glm/vec3.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace shadow::render {

/// A pinhole camera: eye, the point looked at, the up direction and the vertical view angle.
struct Camera {
  glm::dvec3 eye{0.0, -10.0, 10.0};
  glm::dvec3 target{0.0};
  glm::dvec3 up{0.0, 0.0, 1.0};
  double fov_degrees = 30.0;
};

/// What the default camera frames.
enum class Framing {
  Shadows,  ///< the meshes other than the ground, and their shadows on the ground (default)
  Scene,    ///< every vertex of the scene, the ground's included
};

/// What a mesh is, for the default palette and framing (z is up).
enum class MeshRole {
  Ground,    ///< the ground (see ground_mesh)
  Building,  ///< a mesh named like a building (building, house, wall, roof, facade, ...)
  Other,     ///< anything else
};

/// The index in `scene.meshes` of the ground, or none: a mesh named like a ground (ground,
/// floor, terrain, site, plane, base; case-insensitive, as a word of the name) if one is;
/// otherwise the largest mesh whose faces all face up (normal z > 0.9) and that lies at or
/// below every other mesh's lowest point, when it is larger in plan than the rest together.
std::optional<std::size_t> ground_mesh(const Scene& scene);

/// The role of each mesh (one entry per scene mesh).
std::vector<MeshRole> mesh_roles(const Scene& scene);

/// The meshes the default framing leaves out (one entry per scene mesh, 1: left out): with ten
/// or more meshes besides `ground`, those whose centre lies in plan more than four times farther
/// from the median of the centres than 80% of them do (or than four median mesh sizes, when
/// larger), when they are at most a tenth of the meshes. A real city sample can hold one
/// building hundreds of metres from the others.
std::vector<char> stray_meshes(const Scene& scene, std::optional<std::size_t> ground);

/// The points the default camera frames: with Framing::Shadows and a ground, the vertices of
/// every other mesh and their projections along each light onto the ground's plane (its mean
/// height), clipped to the ground's extent in plan; otherwise every vertex. With
/// Framing::Shadows, the stray_meshes are left out.
std::vector<glm::dvec3> framed_points(const Scene& scene, Framing framing);

/// A camera that frames `points` from 40 degrees above the horizon, on the side the first
/// light's shadows fall to, looking back toward the light (turned 17 degrees), every point in
/// view with `margin` (a fraction of the picture) to spare, and the picture centred. `aspect`
/// is width / height. Without points: Camera{}.
Camera frame_points(const Scene& scene, const std::vector<glm::dvec3>& points, double aspect,
                    double margin = 0.04, double fov_degrees = 30.0);

/// The whole scene framed (Framing::Scene; kept for the callers that had it).
Camera default_camera(const Scene& scene, double aspect);

/// The camera the user asked for: each field that is set replaces the default view's.
struct CameraRequest {
  std::optional<glm::dvec3> eye;
  std::optional<glm::dvec3> target;
  std::optional<glm::dvec3> up;
  std::optional<double> fov_degrees;
  Framing framing = Framing::Shadows;
  /// Room left around the framed points, a fraction of the picture's half-size.
  double margin = 0.04;
  /// The scene file as the user named it, for errors about the scene's `camera`.
  std::string scene_file;
};

/// The camera of `shadow render`: the default framing (framed_points, frame_points), then the
/// scene file's `camera`, then `request`, each set key replacing the one before.
/// @throws shadow::InputError when the eye is the target, or up is zero or along the view
///         (naming `--eye/--target`, `--up`, or the scene file's `camera`).
Camera resolve_camera(const Scene& scene, const CameraRequest& request, double aspect);

}  // namespace shadow::render
