// SPDX-License-Identifier: GPL-3.0-or-later
// One Embree 3 scene of every non-degenerate face (float32 after the shift, both sides occlude,
// watertight traversal), shared by ray sampling (ray_sampling.cpp) and the soft-shadow rays
// (soft_shadows.cpp).
#pragma once

#include "baselines/sampling.hpp"

#include <embree3/rtcore.h>

namespace shadow::baselines_detail {

/// Owns an Embree device and scene.
struct EmbreeScene {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  /// The largest absolute shifted coordinate (rays must start a few float ulps of it off a face).
  double max_coordinate = 0;
  EmbreeScene() = default;
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;
  ~EmbreeScene();
};

/// Builds the scene of `setup`'s faces on `threads` threads into `out`.
/// @throws InputError (place `what`) when Embree fails.
void build_embree_scene(const Scene& scene, const Setup& setup, unsigned threads, const char* what, EmbreeScene& out);

}  // namespace shadow::baselines_detail
