// SPDX-License-Identifier: GPL-3.0-or-later
// One Embree 3 scene of every non-degenerate face (float32 after the shift, both sides occlude,
// watertight traversal), shared by ray sampling (ray_sampling.cpp) and the soft-shadow rays
// (soft_shadows.cpp).
#pragma once

#include "sampling.hpp"

#include <embree3/rtcore.h>

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace shadow::baselines_detail {

/// Owns an Embree device and scene.
struct EmbreeScene {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  /// The largest absolute shifted coordinate (rays must start a few float ulps of it off a face).
  double max_coordinate = 0;
  /// The face of each Embree triangle (primID), for the rays that need to know what they hit.
  std::vector<std::uint32_t> triangle_face;
  EmbreeScene() = default;
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;
  ~EmbreeScene();
};

/// Builds the scene of `setup`'s faces on `threads` threads into `out`.
/// @throws InputError (place `what`) when Embree fails.
void build_embree_scene(const Scene& scene, const Setup& setup, unsigned threads, const char* what, EmbreeScene& out);

/// An occlusion ray from `origin` along `direction` (any length), hitting in (0, tfar] of it:
/// Embree's fields in float32, no motion blur, every geometry mask.
inline RTCRay occlusion_ray(const glm::dvec3& origin, const glm::dvec3& direction, float tfar) {
  RTCRay ray{};
  ray.org_x = static_cast<float>(origin.x);
  ray.org_y = static_cast<float>(origin.y);
  ray.org_z = static_cast<float>(origin.z);
  ray.dir_x = static_cast<float>(direction.x);
  ray.dir_y = static_cast<float>(direction.y);
  ray.dir_z = static_cast<float>(direction.z);
  ray.tnear = 0.0f;
  ray.tfar = tfar;
  ray.mask = 0xFFFFFFFFu;
  ray.time = 0.0f;
  ray.id = 0;
  ray.flags = 0;
  return ray;
}

}  // namespace shadow::baselines_detail
