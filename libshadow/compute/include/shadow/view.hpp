// SPDX-License-Identifier: GPL-3.0-or-later
/// @file view.hpp
/// @brief Exact vector views: what a camera sees of the scene, face by face, split into the
/// parts a light reaches and the parts in its shadow (the second pass of Atherton's method).
///
/// The part of a face that the camera's eye E sees is exactly the part a point light at E
/// would light, so the exact engine computes it with its own machinery: casters projected
/// from E onto the face, united, subtracted from the face, in exact rationals in the face's
/// 2D chart. That region is cut to the view's frustum (near plane and the four sides of the
/// image) and overlaid, still exactly, with the region of the face that the chosen light
/// reaches. Every resulting piece is rounded to doubles once. See docs/vector-views.md.
///
/// Pieces of one view are interior-disjoint in the image (a ray from the eye meets at most one
/// visible face first), so they can be drawn in any order: no painter's sort is needed. The
/// one exception is coincident faces (two faces overlapping in one plane), which neither hides.
#pragma once

#include <shadow/shadows.hpp>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace shadow {

/// A pinhole camera and the image it makes. Image coordinates are pixels: x to the right from
/// the left edge, y downward from the top edge, the image spanning [0, width] x [0, height].
struct ViewCamera {
  glm::dvec3 eye{0.0, -10.0, 10.0};  ///< where the camera stands
  glm::dvec3 target{0.0};            ///< the point it looks at (the image's centre)
  glm::dvec3 up{0.0, 0.0, 1.0};      ///< up direction (any length, not parallel to target - eye)
  double fov_degrees = 30.0;         ///< vertical view angle, in (0, 180)
  int width = 800;                   ///< image width in pixels, >= 1
  int height = 600;                  ///< image height in pixels, >= 1
  /// Distance from the eye to the near clipping plane along the view direction; 0 picks
  /// 1e-3 x |target - eye|. Anything nearer than it is left out of the view.
  double near_distance = 0.0;
};

/// The camera's frame in doubles, exactly as the view uses it (also for rasterising the same
/// view elsewhere, e.g. to check it).
struct ViewFrame {
  glm::dvec3 eye;
  glm::dvec3 forward;  ///< unit vector from eye toward target
  glm::dvec3 right;    ///< unit vector, image x
  glm::dvec3 up;       ///< unit vector, image -y (cross(right, forward))
  double focal = 1.0;  ///< pixels per unit of (lateral / depth): (height / 2) / tan(fov / 2)
  double near = 0.0;   ///< the near plane's distance (resolved from ViewCamera::near_distance)
  int width = 0, height = 0;
};

/// Builds the frame of `camera`.
/// @throws InputError naming `what` when the eye equals the target, the up direction is zero
/// or parallel to the view, the angle is outside (0, 180), the size is < 1, a coordinate is not
/// finite, or near_distance is negative or not finite
ViewFrame make_view_frame(const ViewCamera& camera, const std::string& what = "camera");

/// Image position of a point in front of the eye (depth > 0); depth is returned in `depth`
/// when not null.
glm::dvec2 project_to_image(const ViewFrame& frame, const glm::dvec3& point, double* depth = nullptr);

/// One visible piece of one face: a simple polygon, wholly lit or wholly in shadow.
struct ViewPiece {
  std::size_t face_id = 0;
  /// Lit by the view's light. False where the light is hidden, where the face looks away from
  /// it, on every face seen from its back (only the front can be lit: the back is in its
  /// attached shadow), and everywhere when the view has no light.
  bool lit = false;
  bool back = false;  ///< the camera sees the face's back
  /// The piece on the face, exact vertices rounded once, in the face's own orientation.
  std::vector<glm::dvec3> polygon;
  std::vector<glm::dvec2> image;  ///< the same vertices projected to the image (project_to_image)
  double area = 0.0;              ///< exact 3D area, rounded once
};

/// What compute_vector_view computes.
struct VectorView {
  ViewFrame frame;
  std::optional<std::size_t> light_id;  ///< the light that splits pieces into lit and shadowed
  std::vector<ViewPiece> pieces;        ///< by face_id, then lit pieces before shadowed ones
  /// Exact area (3D) of visible cells whose vertices, rounded to doubles, no longer make a simple
  /// polygon, and whose triangles collapse too: left out (as the engine's dropped_area).
  double dropped_area = 0.0;
};

struct VectorViewOptions {
  /// The scene light that splits the pieces (index into Scene::lights); none: unsplit pieces,
  /// all with lit = false. Hard shadows: an extended light (Light::is_extended) splits them by
  /// its centre (centre_light), as FaceLighting::lit_area does.
  std::optional<std::size_t> light;
  unsigned threads = 0;  ///< 0: every hardware thread (at most 1024)
};

/// The exact vector view of `engine`'s scene from `camera`. Faces whose plane contains the eye
/// are edge-on and give nothing; faces behind the eye or nearer than the near plane are cut off.
/// @throws InputError for a bad camera (make_view_frame), a light index out of range, an
/// extended light, or threads > 1024
VectorView compute_vector_view(const ShadowEngine& engine, const ViewCamera& camera,
                               const VectorViewOptions& options = {});

}  // namespace shadow
