// SPDX-License-Identifier: GPL-3.0-or-later
// Soft shadows of extended lights by the three usual approximations (docs/soft-shadows.md):
// percentage-closer filtering of a shadow map (fixed blur), penumbra estimation (PCSS) and
// k stratified rays per point to the light on Embree.
#include "depth_map.hpp"
#include "embree_scene.hpp"
#include "light_sampling.hpp"
#include "sampling.hpp"
#include "core/lights.hpp"
#include "runtime/parallel.hpp"
#include "geometry/newell_normal.hpp"
#include "geometry/unit_vector.hpp"

#include <shadow/baselines.hpp>
#include <shadow/error.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

namespace shadow {

using namespace baselines_detail;

namespace {

constexpr std::size_t kBlock = 64;  // points per work item

SoftResult map_visibility(const Scene& scene, const Light& light, const std::vector<SurfacePoint>& points,
                          const SoftShadowMapOptions& options, bool pcss) {
  using Clock = std::chrono::steady_clock;
  const char* place = pcss ? "pcss" : "pcf";
  if (options.resolution < 1 || options.resolution > 65536)
    throw InputError({"", place}, "resolution must be in [1, 65536]");
  if (!(options.constant_bias >= 0) || !(options.slope_bias >= 0) || !(options.max_slope_bias >= 0) ||
      options.pcf_radius < 0 || options.pcf_radius > 4096 || !(options.max_kernel_radius >= 0) ||
      !(options.max_search_radius >= 0) || options.max_taps < 1 || options.max_taps > 4096 ||
      !std::isfinite(options.max_kernel_radius) || !std::isfinite(options.max_search_radius))
    throw InputError({"", place}, "biases and radii must be non-negative and finite, pcf_radius and max_taps at most 4096, "
                                  "max_taps at least 1");
  check_points(scene, points, place);
  const auto t0 = Clock::now();
  Setup setup = frames_setup(scene, options.recentre);
  const ExtendedLight ext = extended_light(scene, light, setup.shift);
  const ShiftedLight centre = ext.centre_light();
  const unsigned threads = thread_count(options.threads);
  double diag = 0;
  const std::vector<glm::dvec3> tri = scene_triangles(scene, setup, diag);
  std::vector<glm::dvec3> window;
  if (ext.sun)
    for (std::size_t f = 0; f < scene.faces.size(); ++f)
      if (setup.frames[f].ok && scene.is_receiver(f))
        for (const glm::dvec3& p : scene.faces[f].vertices) window.push_back(p - setup.shift);
  const LightMaps maps = build_light_maps(tri, diag, centre, window, options.resolution, threads);
  const auto t1 = Clock::now();

  SoftResult result;
  result.visibility.assign(points.size(), 0.0);
  result.map_bytes = maps.bytes();
  std::atomic<std::uint64_t> lookups{0};
  const double cb = options.constant_bias, sb = options.slope_bias, sb_max = options.max_slope_bias;
  const std::size_t items = (points.size() + kBlock - 1) / kBlock;
  runtime::parallel_for(items, std::max(1u, std::min<unsigned>(threads, static_cast<unsigned>(std::max<std::size_t>(1, items)))),
                     [&](unsigned, std::size_t item) {
    std::uint64_t reads = 0;
    for (std::size_t i = item * kBlock; i < std::min(points.size(), (item + 1) * kBlock); ++i) {
      const FaceFrame& fr = setup.frames[points[i].face_id];
      const glm::dvec3 p = points[i].position - setup.shift;
      if (!fr.ok || ext.behind(p)) continue;
      if (!(ext.sun ? glm::dot(fr.n, ext.to_light) > 0 : glm::dot(fr.n, ext.centre - p) > 0)) continue;
      const MapPoint m = maps.locate(p);
      if (!m.inside) {  // outside the map: lit
        result.visibility[i] = 1.0;
        continue;
      }
      double cosine = ext.sun ? glm::dot(fr.n, ext.to_light) : glm::dot(fr.n, ext.centre - p) / m.depth;
      cosine = std::clamp(cosine, 1e-12, 1.0);
      const double tangent = std::sqrt(std::max(0.0, 1.0 - cosine * cosine)) / cosine;
      const double bias = cb + m.foot * std::min(sb * tangent, sb_max);
      // One tap at offset (dx, dy) texels: the receiver's depth there (its plane along the
      // texel's ray) and the stored depth; false when nothing of it is in the map.
      auto tap = [&](double dx, double dy, double& depth, double& stored) {
        MapPoint q = m;
        if (dx != 0 || dy != 0) {
          glm::dvec3 x;
          if (!maps.on_plane(m.face, m.x + dx, m.y + dy, p, fr.n, x)) return false;
          q = maps.locate(x);
          if (!q.inside) return false;
        }
        ++reads;
        depth = q.depth;
        stored = static_cast<double>(maps.stored(q));
        return true;
      };
      // Lit share of a square kernel of half-width `radius` texels read with (2n + 1)^2 taps.
      auto filter = [&](double radius, int n) {
        const double step = n > 0 ? radius / n : 0.0;
        std::size_t lit = 0, count = 0;
        for (int a = -n; a <= n; ++a)
          for (int b = -n; b <= n; ++b) {
            double depth = 0, stored = 0;
            ++count;
            if (!tap(a * step, b * step, depth, stored) || depth <= stored + bias) ++lit;
          }
        return static_cast<double>(lit) / static_cast<double>(count);
      };
      if (!pcss) {
        result.visibility[i] = filter(options.pcf_radius, options.pcf_radius);
        continue;
      }
      // Blocker search over the cone from the point to the light, cut at the nearest depth.
      const double d_r = m.depth;
      auto half_width = [&](double d_b) {  // penumbra half-width in texels for blockers at d_b
        if (ext.sun) return 0.5 * ext.size * (d_r - d_b) / m.foot;
        return 0.5 * ext.size * (d_r - d_b) / std::max(d_b, 1e-12) / m.foot;
      };
      const double search =
          maps.min_depth < d_r ? std::clamp(half_width(maps.min_depth), 0.0, options.max_search_radius) : 0.0;
      const int ns = std::min(static_cast<int>(std::ceil(search)), options.max_taps);
      const double step = ns > 0 ? search / ns : 0.0;
      double sum = 0;
      std::size_t blockers = 0;
      for (int a = -ns; a <= ns; ++a)
        for (int b = -ns; b <= ns; ++b) {
          double depth = 0, stored = 0;
          if (tap(a * step, b * step, depth, stored) && !(depth <= stored + bias)) {
            sum += stored;
            ++blockers;
          }
        }
      if (blockers == 0) {
        result.visibility[i] = 1.0;
        continue;
      }
      // Blockers found beside the point, under a sloping receiver, can lie beyond d_r: no blur.
      const double kernel =
          std::clamp(half_width(sum / static_cast<double>(blockers)), 0.0, options.max_kernel_radius);
      const int nk = std::min(static_cast<int>(std::ceil(kernel)), options.max_taps);
      result.visibility[i] = filter(kernel, nk);
    }
    lookups += reads;
  });
  result.lookups = lookups;
  result.prepare_seconds = std::chrono::duration<double>(t1 - t0).count();
  result.compute_seconds = std::chrono::duration<double>(Clock::now() - t1).count();
  return result;
}

std::uint64_t splitmix(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
double uniform(std::uint64_t& state) { return static_cast<double>(splitmix(state) >> 11) * 0x1.0p-53; }

}  // namespace

FacePoints face_sample_points(const Scene& scene, double spacing, std::uint64_t max_per_face,
                              const std::vector<std::size_t>& faces) {
  if (!(spacing > 0) || !std::isfinite(spacing)) throw InputError({"", "face points"}, "spacing must be positive and finite");
  std::vector<std::size_t> ids = faces;
  if (ids.empty())
    for (std::size_t f = 0; f < scene.faces.size(); ++f)
      if (scene.is_receiver(f)) ids.push_back(f);
  FacePoints out;
  out.offsets.push_back(0);
  for (std::size_t f : ids) {
    if (f >= scene.faces.size())
      throw InputError({"", "face points"}, "face " + std::to_string(f) + " does not exist");
    if (scene.faces[f].degenerate) continue;
    const FaceFrame fr = face_frame(scene.faces[f].vertices, glm::dvec3(0.0));
    if (!fr.ok) continue;
    for (const glm::dvec3& p : grid_points(fr, spacing, max_per_face)) out.points.push_back({f, p});
    out.face_ids.push_back(f);
    out.areas.push_back(fr.area);
    out.offsets.push_back(out.points.size());
  }
  return out;
}

SoftResult pcf_visibility(const Scene& scene, const Light& light, const std::vector<SurfacePoint>& points,
                          const SoftShadowMapOptions& options) {
  return map_visibility(scene, light, points, options, false);
}

SoftResult pcss_visibility(const Scene& scene, const Light& light, const std::vector<SurfacePoint>& points,
                           const SoftShadowMapOptions& options) {
  return map_visibility(scene, light, points, options, true);
}

SoftResult ray_visibility(const Scene& scene, const Light& light, const std::vector<SurfacePoint>& points,
                          const SoftRayOptions& options) {
  using Clock = std::chrono::steady_clock;
  if (options.rays < 1 || options.rays > (1u << 24)) throw InputError({"", "soft rays"}, "rays must be in [1, 2^24]");
  if (!(options.offset >= 0) || !std::isfinite(options.offset))
    throw InputError({"", "soft rays"}, "offset must be non-negative and finite");
  check_points(scene, points, "soft rays");
  const auto t0 = Clock::now();
  Setup setup = frames_setup(scene, options.recentre);
  const ExtendedLight ext = extended_light(scene, light, setup.shift);
  const unsigned threads = thread_count(options.threads);
  EmbreeScene es;
  build_embree_scene(scene, setup, threads, "soft rays", es);
  const double offset = std::max(options.offset, 8.0 * std::numeric_limits<float>::epsilon() * es.max_coordinate);
  const auto t1 = Clock::now();

  const auto n = static_cast<unsigned>(std::ceil(std::sqrt(static_cast<double>(options.rays)) - 1e-9));
  const std::size_t total = static_cast<std::size_t>(n) * n;
  SoftResult result;
  result.visibility.assign(points.size(), 0.0);
  std::atomic<std::uint64_t> traced{0};
  const std::size_t items = (points.size() + kBlock - 1) / kBlock;
  const unsigned workers = std::max(1u, std::min<unsigned>(threads, static_cast<unsigned>(std::max<std::size_t>(1, items))));
  std::vector<std::vector<RTCRay>> buffers(workers, std::vector<RTCRay>(kBatch));
  runtime::parallel_for(items, workers, [&](unsigned worker, std::size_t item) {
    std::vector<RTCRay>& rays = buffers[worker];
    std::uint64_t count = 0;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (std::size_t i = item * kBlock; i < std::min(points.size(), (item + 1) * kBlock); ++i) {
      const FaceFrame& fr = setup.frames[points[i].face_id];
      const glm::dvec3 p = points[i].position - setup.shift;
      if (!fr.ok || ext.behind(p)) continue;
      const glm::dvec3 o = p + offset * fr.n;
      std::uint64_t state = options.seed ^ (0xD1B54A32D192ED03ull * (static_cast<std::uint64_t>(i) + 1));
      std::size_t visible = 0, filled = 0;
      auto flush = [&] {
        if (filled == 0) return;
        rtcOccluded1M(es.scene, &context, rays.data(), static_cast<unsigned>(filled), sizeof(RTCRay));
        for (std::size_t r = 0; r < filled; ++r) visible += rays[r].tfar >= 0.0f ? 1 : 0;  // -inf: occluded
        count += filled;
        filled = 0;
      };
      for (unsigned a = 0; a < n; ++a)
        for (unsigned b = 0; b < n; ++b) {
          const double u1 = std::min((a + uniform(state)) / n, 1.0 - 1e-16);
          const double u2 = std::min((b + uniform(state)) / n, 1.0 - 1e-16);
          glm::dvec3 d;
          float tfar = std::numeric_limits<float>::infinity();
          if (ext.sun) {
            d = ext.sun_direction(u1, u2);
          } else {
            const glm::dvec3 target = ext.surface_point(u1, u2);
            d = target - o;
            const double len = glm::length(d);
            if (!(len > offset)) continue;
            tfar = static_cast<float>(1.0 - offset / len);
          }
          if (!(glm::dot(fr.n, d) > 0)) continue;  // behind the point's own face
          rays[filled++] = occlusion_ray(o, d, tfar);
          if (filled == rays.size()) flush();
        }
      flush();
      result.visibility[i] = static_cast<double>(visible) / static_cast<double>(total);
    }
    traced += count;
  });
  result.lookups = traced;
  result.prepare_seconds = std::chrono::duration<double>(t1 - t0).count();
  result.compute_seconds = std::chrono::duration<double>(Clock::now() - t1).count();
  return result;
}

std::vector<FaceLighting> soft_face_estimates(const FacePoints& samples, const std::vector<double>& visibility,
                                              std::size_t light_id, double tolerance) {
  if (visibility.size() != samples.points.size())
    throw InputError({"", "soft face estimates"}, "one visibility per point is needed");
  std::vector<FaceLighting> out;
  for (std::size_t k = 0; k < samples.face_ids.size(); ++k) {
    FaceLighting fl;
    fl.face_id = samples.face_ids[k];
    fl.light_id = light_id;
    fl.area = samples.areas[k];
    const std::size_t a = samples.offsets[k], b = samples.offsets[k + 1];
    double sum = 0;
    std::size_t full = 0, none = 0;
    for (std::size_t i = a; i < b; ++i) {
      sum += visibility[i];
      if (visibility[i] >= 1 - tolerance) ++full;
      else if (visibility[i] <= tolerance) ++none;
      if (visibility[i] > 0) fl.faces_light = true;
    }
    const double count = b > a ? static_cast<double>(b - a) : 1.0;
    fl.lit_fraction = sum / count;
    fl.lit_area = fl.lit_fraction * fl.area;
    fl.shadow_area = fl.area - fl.lit_area;
    fl.fully_lit_area = fl.area * static_cast<double>(full) / count;
    fl.umbra_area = fl.area * static_cast<double>(none) / count;
    fl.penumbra_area = std::max(0.0, fl.area - fl.fully_lit_area - fl.umbra_area);
    out.push_back(fl);
  }
  return out;
}

}  // namespace shadow
