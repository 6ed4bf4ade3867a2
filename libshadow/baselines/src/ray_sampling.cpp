// SPDX-License-Identifier: GPL-3.0-or-later
// Ray sampling on Intel Embree 3: a point grid on every receiving face, one occlusion ray per
// point toward the light.
#include "embree_scene.hpp"
#include "sampling.hpp"

#include <shadow/baselines.hpp>
#include <shadow/error.hpp>

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

namespace shadow {

using namespace baselines_detail;

BaselineResult ray_sampling_lighting(const Scene& scene, const RaySamplingOptions& options) {
  using Clock = std::chrono::steady_clock;
  if (!(options.spacing > 0) || !std::isfinite(options.spacing))
    throw InputError({"", "ray sampling"}, "spacing must be positive and finite");
  if (!(options.offset >= 0) || !std::isfinite(options.offset))
    throw InputError({"", "ray sampling"}, "offset must be non-negative and finite");
  const auto t0 = Clock::now();
  Setup setup = make_setup(scene, options.lights, options.recentre);
  const unsigned threads = thread_count(options.threads);

  EmbreeScene es;
  build_embree_scene(scene, setup, threads, "ray sampling", es);
  // Rays start off the face by at least a few float ulps of the coordinates: closer, a ray can
  // hit its own face in Embree's single precision.
  const double offset = std::max(options.offset, 8.0 * std::numeric_limits<float>::epsilon() * es.max_coordinate);
  const auto t1 = Clock::now();

  std::vector<std::uint64_t> samples(setup.result.lighting.size(), 0), lit(samples.size(), 0);
  for (std::size_t k = 0; k < setup.lights.size(); ++k) {
    std::vector<SampleJob> jobs = setup.jobs(k);
    for (SampleJob& j : jobs) j.spacing = options.spacing;
    const ShiftedLight light = setup.shifted[k];
    std::vector<std::uint64_t> s(samples.size(), 0), l(samples.size(), 0);
    run_sampling(jobs, threads, std::numeric_limits<std::uint64_t>::max(),
                 [&](unsigned) -> BatchTest {
                   // Per thread: a ray buffer; rays of one batch share a face and a light, so
                   // they are coherent and Embree's stream traversal is told so.
                   auto rays = std::make_shared<std::vector<RTCRay>>(kBatch);
                   return [&, rays](const glm::dvec3* points, std::size_t count, const SampleJob& job) {
                     RTCIntersectContext context;
                     rtcInitIntersectContext(&context);
                     context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
                     std::size_t n = 0;
                     for (std::size_t i = 0; i < count; ++i) {
                       const glm::dvec3 o = points[i] + offset * job.frame->n;
                       glm::dvec3 d;
                       float tfar;
                       if (light.point) {
                         d = light.position - o;
                         const double len = glm::length(d);
                         if (!(len > offset)) continue;  // a sample at the lamp itself: not lit
                         tfar = static_cast<float>(1.0 - offset / len);
                       } else {
                         d = light.to_light;
                         tfar = std::numeric_limits<float>::infinity();
                       }
                       (*rays)[n++] = occlusion_ray(o, d, tfar);
                     }
                     if (n > 0) rtcOccluded1M(es.scene, &context, rays->data(), static_cast<unsigned>(n), sizeof(RTCRay));
                     std::uint64_t lit_count = 0;
                     for (std::size_t i = 0; i < n; ++i) lit_count += (*rays)[i].tfar >= 0.0f ? 1 : 0;  // -inf: occluded
                     return lit_count;
                   };
                 },
                 s, l);
    for (std::size_t e = 0; e < samples.size(); ++e) {
      samples[e] += s[e];
      lit[e] += l[e];
    }
  }
  finish(setup, samples, lit);
  const auto t2 = Clock::now();
  setup.result.prepare_seconds = std::chrono::duration<double>(t1 - t0).count();
  setup.result.compute_seconds = std::chrono::duration<double>(t2 - t1).count();
  return std::move(setup.result);
}

}  // namespace shadow
