// SPDX-License-Identifier: GPL-3.0-or-later
// Shadow mapping: the z-buffer algorithm (Catmull) run from the light, then a depth comparison
// with bias for every sample point of every receiving face.
#include "depth_map.hpp"
#include "sampling.hpp"
#include "runtime/parallel.hpp"

#include <shadow/baselines.hpp>
#include <shadow/error.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

namespace shadow {

using namespace baselines_detail;

BaselineResult shadow_map_lighting(const Scene& scene, const ShadowMapOptions& options) {
  using Clock = std::chrono::steady_clock;
  if (options.resolution < 1 || options.resolution > 65536)
    throw InputError({"", "shadow map"}, "resolution must be in [1, 65536]");
  if (!(options.sample_spacing > 0) || !std::isfinite(options.sample_spacing) || !(options.constant_bias >= 0) ||
      !(options.slope_bias >= 0) || !(options.max_slope_bias >= 0))
    throw InputError({"", "shadow map"}, "biases must be non-negative and the sample spacing positive");
  const auto start = Clock::now();
  Setup setup = make_setup(scene, options.lights, options.recentre);
  const unsigned threads = thread_count(options.threads);
  const int R = options.resolution;

  // Triangles of every non-degenerate face, shifted, in double.
  double diag = 0;
  const std::vector<glm::dvec3> tri = scene_triangles(scene, setup, diag);

  double prepare = std::chrono::duration<double>(Clock::now() - start).count(), compute = 0;
  std::vector<std::uint64_t> samples(setup.result.lighting.size(), 0), lit(samples.size(), 0);
  for (std::size_t k = 0; k < setup.lights.size(); ++k) {
    const auto t0 = Clock::now();
    const ShiftedLight light = setup.shifted[k];
    // Window of an orthographic map: the receivers' vertices.
    std::vector<glm::dvec3> window;
    if (!light.point)
      for (const FaceLighting& fl : setup.result.lighting) {
        if (fl.light_id != setup.lights[k] || !setup.frames[fl.face_id].ok) continue;
        for (const glm::dvec3& p0 : scene.faces[fl.face_id].vertices) window.push_back(p0 - setup.shift);
      }
    const LightMaps maps = build_light_maps(tri, diag, light, window, R, threads);
    setup.result.map_bytes = std::max(setup.result.map_bytes, maps.bytes());
    const auto t1 = Clock::now();

    // Sampling: spacing in texel footprints on the face (at the face's plane distance for a lamp).
    std::vector<SampleJob> jobs = setup.jobs(k);
    for (SampleJob& j : jobs) {
      if (light.point) {
        // Nearest distance from the lamp to the face, bounded below by its distance to the
        // face's plane and to the face's bounding box.
        glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
        for (const glm::dvec3& p0 : scene.faces[setup.result.lighting[j.pair].face_id].vertices) {
          lo = glm::min(lo, p0 - setup.shift);
          hi = glm::max(hi, p0 - setup.shift);
        }
        const glm::dvec3 outside = glm::max(glm::dvec3(0.0), glm::max(lo - light.position, light.position - hi));
        const double dist = std::max(glm::length(outside), std::abs(glm::dot(j.frame->n, light.position - j.frame->origin)));
        j.spacing = options.sample_spacing * 2.0 / R * std::max(dist, 1e-4 * std::max(1.0, diag));
      } else {
        j.spacing = options.sample_spacing * maps.texel;
      }
    }
    const double cb = options.constant_bias, sb = options.slope_bias, sb_max = options.max_slope_bias;
    std::vector<std::uint64_t> s(samples.size(), 0), l(samples.size(), 0);
    run_sampling(jobs, threads, options.max_samples_per_face,
                 [&](unsigned) {
                   auto lit_point = [&](const glm::dvec3& p, const SampleJob& job) {
                     const MapPoint m = maps.locate(p);
                     if (!m.inside) return true;  // outside the map (or behind a cube face): lit
                     const float stored = maps.stored(m);
                     double cosine = light.point ? -glm::dot(job.frame->n, p - light.position) / m.depth
                                                 : glm::dot(job.frame->n, light.to_light);
                     cosine = std::clamp(cosine, 1e-12, 1.0);
                     const double tangent = std::sqrt(std::max(0.0, 1.0 - cosine * cosine)) / cosine;
                     const double bias = cb + m.foot * std::min(sb * tangent, sb_max);
                     return m.depth <= static_cast<double>(stored) + bias;
                   };
                   return [lit_point](const glm::dvec3* points, std::size_t count, const SampleJob& job) {
                     std::uint64_t n = 0;
                     for (std::size_t i = 0; i < count; ++i) n += lit_point(points[i], job) ? 1 : 0;
                     return n;
                   };
                 },
                 s, l);
    for (std::size_t e = 0; e < samples.size(); ++e) {
      samples[e] += s[e];
      lit[e] += l[e];
    }
    const auto t2 = Clock::now();
    prepare += std::chrono::duration<double>(t1 - t0).count();
    compute += std::chrono::duration<double>(t2 - t1).count();
  }
  finish(setup, samples, lit);
  setup.result.prepare_seconds = prepare;
  setup.result.compute_seconds = compute;
  return std::move(setup.result);
}

}  // namespace shadow
