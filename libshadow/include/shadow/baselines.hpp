// SPDX-License-Identifier: GPL-3.0-or-later
/// @file baselines.hpp
/// @brief The sampled methods people run instead of exact shadows, as baselines to measure
/// libshadow against: shadow mapping (a depth map from the light) and ray sampling (a point
/// grid on every face, one shadow ray per point, on Intel Embree 3).
///
/// Both give estimates in the same shape as the exact engine (one FaceLighting per receiving
/// face and light), so errors are computed the same way. Conventions shared with the exact
/// engine: a face whose front looks away from the light (or is edge-on) is wholly in shadow
/// (`faces_light = false`, lit area 0); degenerate faces cast nothing and receive nothing.
///
/// Each receiving face is sampled on a cell-centred square grid in its own plane (axes along
/// its longest edge and across it, the grid centred on the face's bounding rectangle and then
/// moved by irrational fractions of a cell, so that rows of samples never line up with edges on
/// the scene's own coordinate grid); the samples inside the face are counted and the lit
/// fraction is lit samples / samples. A face with no grid point inside gets one sample, at the
/// centre of its bounding rectangle. `lit_area` is that fraction times the face's area
/// (Newell's formula in double precision).
///
/// Coordinates are shifted by the centre of the scene's bounding box, in double precision,
/// before anything is converted to single precision (the depth map and Embree are float32):
/// that is what a careful user does with georeferenced models (`recentre = false` shows what
/// happens without it).
///
/// Link `libshadow::baselines` (a separate library: the core does not depend on Embree).
#pragma once

#include <shadow/scene.hpp>
#include <shadow/shadows.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace shadow {

/// What a baseline computed, in the exact engine's shape.
struct BaselineResult {
  /// One entry per receiving face and computed light, ordered by face_id then light_id.
  /// `lit_area` and `lit_fraction` are estimates; `shadow_area = area - lit_area`.
  std::vector<FaceLighting> lighting;
  std::uint64_t samples = 0;        ///< sample points evaluated (front-facing receivers only)
  double prepare_seconds = 0.0;     ///< BVH build (rays) or depth-map rasterisation (shadow map)
  double compute_seconds = 0.0;     ///< sampling the faces
  std::size_t map_bytes = 0;        ///< depth-map memory (shadow map only)

  /// The entry for (face, light), or nullptr when that pair was not computed.
  [[nodiscard]] const FaceLighting* find(std::size_t face_id, std::size_t light_id) const;
};

/// Shadow mapping (the z-buffer algorithm run from the light).
///
/// Directional light: one orthographic depth map looking along the light, its square window
/// fitted to the receivers' bounds across the light. Point light: a cube map, six 90-degree
/// perspective depth maps around the light (+x, -x, +y, -y, +z, -z), each `resolution` squared,
/// storing the distance from the light. Every non-degenerate face (both sides; closed or not) is
/// triangulated and rasterised at texel centres, keeping the depth nearest the light in float32.
///
/// Each front-facing receiver is then sampled at a spacing of `sample_spacing` texel footprints
/// (the texel's world size at the sample's distance from a point light), and a sample is lit when
///   depth(sample) <= stored depth + constant_bias + slope_bias * texel * tan(angle),
/// where `angle` is between the face's normal and the direction to the light (the depth slope of
/// the receiver across one texel), the slope term capped at `max_slope_bias` texels. Too little
/// bias gives "shadow acne" (a lit face shadows itself in stripes, because the stored depth is
/// the face's depth at the texel centre, not at the sample); too much gives "peter-panning"
/// (shadows detach from their casters and light leaks under objects resting on others).
/// Samples outside the map are lit.
struct ShadowMapOptions {
  int resolution = 2048;          ///< texels per side of the map (of each cube face)
  double constant_bias = 1e-3;    ///< metres (scene units)
  double slope_bias = 1.0;        ///< texels of depth slope
  double max_slope_bias = 16.0;   ///< cap of the slope term, in texels (grazing faces)
  double sample_spacing = 1.0;    ///< face sample spacing in texel footprints
  /// Cap on samples per face (the spacing is widened on a face that would exceed it).
  std::uint64_t max_samples_per_face = 1ull << 26;
  unsigned threads = 0;           ///< 0: every hardware thread
  std::vector<std::size_t> lights;  ///< scene lights to compute; empty: every light
  bool recentre = true;           ///< subtract the scene's centre before going to float32
};

/// Shadow maps for the scene's lights. The scene must have been validated.
/// @throws InputError on an unusable light or a resolution outside [1, 65536].
BaselineResult shadow_map_lighting(const Scene& scene, const ShadowMapOptions& options = {});

/// Ray sampling on Intel Embree 3: every non-degenerate face is triangulated into one Embree
/// scene (float32, both sides occlude, watertight traversal so that rays cannot slip through
/// the shared edges of a face's triangles). Each front-facing receiver gets a cell-centred grid
/// of spacing `spacing`; from each sample, moved off the face along its normal (not along the
/// light: at grazing light that would stay on the face) by `offset` or 8 float ulps of the
/// largest shifted coordinate, whichever is larger, one occlusion ray goes to the light (to that
/// offset short of a point light). The rays of one face are traced together as a coherent
/// stream. Lit fraction = unoccluded rays / rays.
struct RaySamplingOptions {
  double spacing = 1.0;           ///< grid spacing on each face (scene units)
  double offset = 1e-4;           ///< start of each ray off the face (scene units)
  unsigned threads = 0;           ///< 0: every hardware thread
  std::vector<std::size_t> lights;  ///< scene lights to compute; empty: every light
  bool recentre = true;           ///< subtract the scene's centre before going to float32
};

/// Ray-sampled lit fractions. The scene must have been validated.
/// @throws InputError on an unusable light or spacing, or when Embree fails.
BaselineResult ray_sampling_lighting(const Scene& scene, const RaySamplingOptions& options = {});

}  // namespace shadow
