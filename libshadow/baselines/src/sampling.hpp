// SPDX-License-Identifier: GPL-3.0-or-later
// Shared by the sampled baselines: face frames, cell-centred sample grids on faces, ear-clipping
// triangulation, light checks and a dynamically scheduled sampling loop. Double precision.
#pragma once

#include <shadow/baselines.hpp>
#include <shadow/scene.hpp>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <thread>
#include <vector>

namespace shadow::baselines_detail {

/// A face in its own plane: origin (first vertex), orthonormal axes u (along the first usable
/// edge), v and unit normal n = u x v; the polygon in (u, v), counter-clockwise seen from the
/// front. Coordinates are in the shifted frame (scene centre at the origin).
struct FaceFrame {
  glm::dvec3 origin{0.0}, u{0.0}, v{0.0}, n{0.0};
  std::vector<glm::dvec2> polygon;
  double area = 0.0;
  bool ok = false;
};

/// Centre of the bounding box of every non-degenerate face's vertices.
glm::dvec3 scene_centre(const Scene& scene);

FaceFrame face_frame(const std::vector<glm::dvec3>& vertices, const glm::dvec3& shift);

/// Ear clipping of a simple polygon (either orientation); falls back to a fan if it gets stuck
/// (self-touching input). Indices into `polygon`.
std::vector<std::array<std::uint32_t, 3>> triangulate(const std::vector<glm::dvec2>& polygon);

/// Light in the shifted frame, checked: unit direction toward a directional light, or position.
struct ShiftedLight {
  bool point = false;
  glm::dvec3 to_light{0.0};  ///< unit (directional)
  glm::dvec3 position{0.0};  ///< shifted (point)
};
/// @throws InputError for a zero or non-finite direction or a non-finite position.
ShiftedLight shifted_light(const Scene& scene, std::size_t light_id, const glm::dvec3& shift);

/// The lights selected by `wanted` (empty: all); @throws InputError on an index out of range.
std::vector<std::size_t> selected_lights(const Scene& scene, const std::vector<std::size_t>& wanted);

unsigned thread_count(unsigned requested);

/// Does a face with this frame face the light (front strictly toward it)?
bool faces_light(const FaceFrame& frame, const ShiftedLight& light);

/// One receiving face to sample: its frame and grid spacing.
struct SampleJob {
  std::size_t pair = 0;  ///< index of the (face, light) entry the counts go to
  const FaceFrame* frame = nullptr;
  double spacing = 1.0;
};

/// Samples every job's face on its cell-centred grid and counts lit samples, on `threads`
/// threads scheduled dynamically over blocks of rows (one large face is many work items).
/// `make_test(thread_index)` returns the per-thread test: how many of `count` points (all on
/// one job's face, at most kBatch) are lit. Batches let Embree trace coherent rays together.
/// Counts land in samples[pair] and lit[pair]. A face with no grid point inside gets one sample.
constexpr std::size_t kBatch = 256;
using BatchTest = std::function<std::uint64_t(const glm::dvec3* points, std::size_t count, const SampleJob& job)>;
void run_sampling(const std::vector<SampleJob>& jobs, unsigned threads, std::uint64_t max_samples_per_face,
                  const std::function<BatchTest(unsigned)>& make_test, std::vector<std::uint64_t>& samples,
                  std::vector<std::uint64_t>& lit);

/// The points of a face's cell-centred grid of spacing `spacing` (widened to at most `cap`
/// points) that lie inside it, in the frame's coordinates; a face with none gets the centre of
/// its bounding rectangle. The same grid as run_sampling.
std::vector<glm::dvec3> grid_points(const FaceFrame& frame, double spacing, std::uint64_t cap);

/// What both baselines start from: the shift, every face's frame, the selected lights (shifted)
/// and the result's entries (receivers x lights, by face then light, areas filled in).
struct Setup {
  glm::dvec3 shift{0.0};
  std::vector<FaceFrame> frames;
  std::vector<std::size_t> lights;
  std::vector<ShiftedLight> shifted;  ///< one per selected light
  BaselineResult result;
  /// Sampling jobs of the front-facing entries for selected light k (pair = index in lighting),
  /// spacing left at 1.
  std::vector<SampleJob> jobs(std::size_t k) const;
};
/// `recentre`: shift by the scene's centre (else by nothing: coordinates go to float32 as they are).
Setup make_setup(const Scene& scene, const std::vector<std::size_t>& wanted_lights, bool recentre);

/// Fills lit estimates from sample counts (entries without samples: lit 0).
void finish(Setup& setup, const std::vector<std::uint64_t>& samples, const std::vector<std::uint64_t>& lit);


/// Shift and face frames (no lights): the start of the baselines that take points or faces
/// rather than (face, light) pairs (the soft-shadow methods, the path tracer).
Setup frames_setup(const Scene& scene, bool recentre);

/// @throws InputError (place `place`) for a point whose face does not exist or whose position is
/// not finite.
void check_points(const Scene& scene, const std::vector<SurfacePoint>& points, const char* place);

}  // namespace shadow::baselines_detail
