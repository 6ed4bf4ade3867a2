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
/// Lights are checked as the engine checks them (InputError naming `lights[i].<key>`); an
/// extended light (Light::is_extended) stands for its centre (centre_light: an area light's
/// centroid, a disk's centre, a sun disk's central direction), whose hard shadow is the exact
/// engine's FaceLighting::lit_area for that light (docs/area-lights.md).
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
/// Soft shadows of extended lights (Light::is_extended: an area polygon, a disk, the sun's
/// disk) by the three approximations people use (docs/soft-shadows.md): a shadow map whose edge
/// is blurred by a kernel of fixed size (percentage-closer filtering), penumbra estimation (PCSS),
/// and k rays per point to the light. Each gives the visible fraction (0..1) of the light at
/// given points on faces, the quantity light_visibility (area_lights.hpp) computes exactly;
/// face_sample_points and soft_face_estimates turn them into per-face region estimates.
///
/// Global illumination: a diffuse Monte Carlo path tracer on the same Embree scene
/// (path_trace_faces, path_trace_points), the baseline of the radiosity solver (radiosity.hpp):
/// per-face or per-point irradiance with a standard error, deterministic for a seed.
///
/// Link `libshadow::baselines` (a separate library: the core does not depend on Embree).
#pragma once

#include <shadow/area_lights.hpp>
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

// ---- Soft shadows of extended lights ---------------------------------------------------------

/// Points on the receiving faces, grouped by face: the cell-centred grid of the baselines above
/// (spacing `spacing` in scene units, irrational offsets, one point at the centre of the bounding
/// rectangle of a face too small for the grid), so that methods can be compared point by point
/// and face by face.
struct FacePoints {
  std::vector<SurfacePoint> points;    ///< every point, face after face
  std::vector<std::size_t> face_ids;   ///< the faces sampled (non-degenerate receivers, in order)
  std::vector<std::size_t> offsets;    ///< points of face_ids[i]: [offsets[i], offsets[i + 1])
  std::vector<double> areas;           ///< area of face_ids[i] (Newell's formula, double)
};

/// Samples every non-degenerate receiving face (or only `faces`, when not empty) on its grid of
/// spacing `spacing`, at most `max_per_face` points a face (the spacing is widened on a face
/// that would have more). The scene must have been validated.
/// @throws InputError for a spacing that is not positive and finite, or a face id out of range.
FacePoints face_sample_points(const Scene& scene, double spacing, std::uint64_t max_per_face = 1u << 16,
                              const std::vector<std::size_t>& faces = {});

/// What a soft-shadow baseline computed at the points.
struct SoftResult {
  std::vector<double> visibility;  ///< visible fraction of the light at each point, in [0, 1]
  double prepare_seconds = 0.0;    ///< depth maps (shadow maps) or BVH build (rays)
  double compute_seconds = 0.0;    ///< the points
  std::uint64_t lookups = 0;       ///< depth-map texels read or rays traced
  std::size_t map_bytes = 0;       ///< depth-map memory (shadow maps only)
};

/// The two soft-shadow-map methods share one depth map rendered from the light's centre (the
/// centroid of an area light, a disk's centre: a cube map of six `resolution`-squared
/// perspective maps; the sun's disk: one orthographic map along its centre direction, fitted to
/// the receivers as for shadow_map_lighting), and the same depth test with bias as the hard
/// shadow map (`constant_bias + texel * min(slope_bias * tan(angle), max_slope_bias)` with the
/// angle at the light's centre). A filter tap at an offset from the point compares the stored
/// depth of the texel there with the depth of the point's own plane along that texel's ray from
/// the light (receiver-plane depth), so that a wide kernel on a sloping face does not shadow the
/// face itself. Taps at cube-face seams continue on the neighbouring face. A point whose face
/// looks away from the light's centre, or that lies behind an area or disk light's front, gets 0.
///
/// - **PCF** (percentage-closer filtering, fixed blur): the fraction of the (2r + 1)^2 taps one
///   texel apart, r = `pcf_radius`, that pass the depth test. r = 0 is the hard shadow map.
/// - **PCSS** (percentage-closer soft shadows, penumbra estimation): (1) blocker search: the
///   taps inside the cone from the point to the light, cut at the nearest depth in the map, give
///   the mean depth d_b of the texels nearer the light than the point's plane (none: the point
///   sees all of the light); (2) penumbra width by similar triangles, w = size x (d_r - d_b) / d_b
///   for an area light (size: the square root of its area) or a disk (its diameter), and
///   w = angular_diameter x (d_r - d_b) for the sun (depths along the light); (3) a PCF whose
///   half-width is w / 2 in texels at the point's depth d_r, capped at `max_kernel_radius`.
///   Wide kernels are read with at most (2 `max_taps` + 1)^2 taps spread evenly over them.
struct SoftShadowMapOptions {
  int resolution = 2048;           ///< texels per side of the map (of each cube face)
  double constant_bias = 1e-3;     ///< metres (scene units)
  double slope_bias = 1.0;         ///< texels of depth slope
  double max_slope_bias = 16.0;    ///< cap of the slope term, in texels
  int pcf_radius = 2;              ///< PCF: kernel half-width r in texels ((2r + 1)^2 taps)
  double max_kernel_radius = 64.0; ///< PCSS: cap on the penumbra kernel's half-width (texels)
  double max_search_radius = 64.0; ///< PCSS: cap on the blocker search's half-width (texels)
  int max_taps = 8;                ///< PCSS: taps per half-width of a search or kernel, at most
  unsigned threads = 0;            ///< 0: every hardware thread
  bool recentre = true;            ///< subtract the scene's centre before going to float32
};

/// Percentage-closer filtering (fixed kernel) of `light` at `points`. The scene must have been
/// validated.
/// @throws InputError for a light that is not extended or is unusable, a face id out of range,
/// or options out of range (resolution in [1, 65536], radii and biases non-negative).
SoftResult pcf_visibility(const Scene& scene, const Light& light, const std::vector<SurfacePoint>& points,
                          const SoftShadowMapOptions& options = {});

/// Penumbra estimation (PCSS) of `light` at `points`. Same conditions as pcf_visibility.
SoftResult pcss_visibility(const Scene& scene, const Light& light, const std::vector<SurfacePoint>& points,
                           const SoftShadowMapOptions& options = {});

/// k rays per point to the light, on Embree (the scene as for ray_sampling_lighting). The light
/// is sampled uniformly in the measure light_visibility uses, stratified on an n x n grid of the
/// unit square with n = ceil(sqrt(rays)) (so n^2 rays) and jittered per point from `seed`: an area
/// light by its area (its polygon split into triangles, the first coordinate choosing the
/// triangle in proportion to its area), a disk by area (the concentric square-to-disk map), the
/// sun's disk by solid angle (the spherical cap of half-angle angular_diameter / 2). A ray counts
/// when it reaches its light point unoccluded; light points behind the point's face, or a point
/// behind an area or disk light's front, count as hidden. The estimate converges to
/// light_visibility as rays grow (its standard error is at most 0.5 / sqrt(rays), far less in
/// practice with stratification). The result does not depend on `threads`.
struct SoftRayOptions {
  unsigned rays = 64;              ///< rays per point (rounded up to a square number)
  std::uint64_t seed = 1;          ///< jitter of the strata
  double offset = 1e-4;            ///< start of each ray off the face (scene units), as ray sampling
  unsigned threads = 0;            ///< 0: every hardware thread
  bool recentre = true;            ///< subtract the scene's centre before going to float32
};

/// k rays per point. The scene must have been validated.
/// @throws InputError for a light that is not extended or is unusable, a face id out of range,
/// rays = 0, or when Embree fails.
SoftResult ray_visibility(const Scene& scene, const Light& light, const std::vector<SurfacePoint>& points,
                          const SoftRayOptions& options = {});

/// Per-face estimates from the visible fractions at `samples.points`, in the exact engine's
/// shape (one FaceLighting per face of `samples`, light id `light_id`): fully_lit_area, umbra_area
/// and penumbra_area are the face's area times the share of its points whose visibility is at
/// least 1 - `tolerance`, at most `tolerance`, and between; lit_fraction is the mean visibility
/// (the face's mean share of the light) and lit_area its product with the area; faces_light is
/// true when any point sees some of the light.
std::vector<FaceLighting> soft_face_estimates(const FacePoints& samples, const std::vector<double>& visibility,
                                              std::size_t light_id, double tolerance = 1e-9);

// ---- Global illumination: a diffuse Monte Carlo path tracer ----------------------------------

/// Options of the path tracer (path_trace_faces, path_trace_points; docs/radiosity.md, "Against a
/// path tracer").
struct PathTracerOptions {
  std::uint64_t samples = 1024;  ///< paths per face (path_trace_faces) or per point
  std::uint64_t seed = 1;        ///< the random streams: one per (face or point, path index)
  /// The most reflections a path follows: light that reached the point after more reflections
  /// than this is left out, so the estimate is low by it. 0: no limit, paths end by Russian
  /// roulette alone (unbiased).
  unsigned max_bounces = 0;
  /// After a reflection off a surface of reflectance rho the path goes on with probability rho
  /// and keeps its weight (unbiased). Off: it always goes on, its weight times rho, and
  /// max_bounces must be above 0.
  bool russian_roulette = true;
  double offset = 1e-4;   ///< start of each ray off its face (scene units), as ray sampling
  unsigned threads = 0;   ///< 0: every hardware thread; the result does not depend on it
  bool recentre = true;   ///< subtract the scene's centre before going to float32
};

/// One estimate: a face's area-weighted mean, or the value at one point.
struct IrradianceEstimate {
  std::size_t face_id = 0;
  double area = 0.0;               ///< the face's area (Newell's formula); 0 for a point
  double irradiance = 0.0;         ///< H (W/m^2) on the front: the lights' and the other faces'
  double standard_error = 0.0;     ///< of `irradiance`: the paths' standard deviation / sqrt(paths)
  double direct_irradiance = 0.0;  ///< the lights' share of H (next-event estimation at the start)
  double direct_standard_error = 0.0;
  double radiosity = 0.0;          ///< B = E + rho H, the face's emittance and reflectance
  std::uint64_t paths = 0;         ///< 0 for a degenerate face (no estimate)
};

/// What the path tracer computed.
struct PathTracerResult {
  std::vector<IrradianceEstimate> estimates;  ///< one per face asked for, or per point, in order
  std::uint64_t paths = 0;        ///< paths traced
  std::uint64_t rays = 0;         ///< rays traced: path segments and shadow rays
  unsigned max_bounces = 0;       ///< as run (0: no limit)
  bool russian_roulette = true;   ///< as run
  double prepare_seconds = 0.0;   ///< BVH build
  double compute_seconds = 0.0;   ///< the paths
};

/// Diffuse global illumination by path tracing, on the Embree scene of ray_sampling_lighting,
/// with the meaning of solve_radiosity (shadow/radiosity.hpp): every face is Lambertian with its
/// material's `reflectance` rho and `emittance` E, light leaves and arrives on a face's front
/// only (a back is black and opaque), lights do not occlude. The irradiance at a point x is
///   H(x) = D(x) + E(y) + rho(y) H(y)   (y: the front hit along a cosine-distributed direction; 0 on a miss or a back)
/// where D is the direct irradiance of the scene's lights by next-event estimation, one shadow
/// ray per light and vertex: a point light I cos / r^2, a directional light I cos, an area or disk
/// light of radiance L = intensity by one point uniform on its area (L A cos cos' / r^2, front
/// only), the sun's disk by one direction uniform in its solid angle (intensity times cos to its
/// centre when the ray is free), as light_irradiance defines them. Emitting faces are found by the
/// paths (no next-event estimation for them). Each path has its own random stream from (seed,
/// face or point index, path index), and sums are made in fixed blocks of paths, so the result
/// is the same bit for bit for any thread count.
///
/// path_trace_faces: `samples` paths per face, each from its own point uniform on the face (by
/// area), so `irradiance` is the face's area-weighted mean H. All non-degenerate faces, or
/// those of `faces` in the order given. The scene must have been validated.
/// @throws InputError for bad options, a face out of range, an unusable light, or when Embree fails.
PathTracerResult path_trace_faces(const Scene& scene, const PathTracerOptions& options = {},
                                  const std::vector<std::size_t>& faces = {});

/// `samples` paths from each of `points` (on its face's front), estimates in the order of points.
/// @throws InputError as path_trace_faces, or for a point that is not finite.
PathTracerResult path_trace_points(const Scene& scene, const std::vector<SurfacePoint>& points,
                                   const PathTracerOptions& options = {});

}  // namespace shadow
