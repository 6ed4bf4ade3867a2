// SPDX-License-Identifier: GPL-3.0-or-later
// A diffuse Monte Carlo path tracer on Embree: the baseline that radiosity (shadow/radiosity.hpp)
// is measured against (docs/radiosity.md, "Against a path tracer"). Next-event estimation for
// the scene's lights, cosine-distributed bounces, Russian roulette on the reflectance.
#include "embree_scene.hpp"
#include "light_sampling.hpp"
#include "sampling.hpp"
#include "runtime/parallel.hpp"

#include <shadow/baselines.hpp>
#include <shadow/error.hpp>

#include <embree3/rtcore.h>
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

/// Paths summed in order as one work item: the partition does not depend on the thread count,
/// so neither do the sums.
constexpr std::uint64_t kPathBlock = 64;

std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// A path's own stream (splitmix64), keyed by the seed, the face or point and the path index.
struct Stream {
  std::uint64_t state;
  Stream(std::uint64_t seed, std::uint64_t item, std::uint64_t path)
      : state(mix64(mix64(mix64(seed + 0x9E3779B97F4A7C15ull) + item + 0x632BE59BD9B4E019ull) + path)) {}
  double next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    return static_cast<double>(mix64(z) >> 11) * 0x1.0p-53;
  }
};

/// One light, ready for next-event estimation in the shifted frame.
struct TracerLight {
  bool extended = false;
  ShiftedLight hard;   ///< point or directional
  ExtendedLight ext;   ///< area, disk, sun disk
  double intensity = 0;
};

/// A face to start paths from: its triangles (shifted) and their cumulative area shares.
struct FaceSampler {
  std::vector<std::array<glm::dvec3, 3>> triangles;
  std::vector<double> cumulative;
};

FaceSampler face_sampler(const FaceFrame& fr) {
  FaceSampler s;
  double total = 0;
  for (const auto& t : triangulate(fr.polygon)) {
    std::array<glm::dvec3, 3> tri;
    for (std::size_t c = 0; c < 3; ++c) {
      const glm::dvec2& q = fr.polygon[t[c]];
      tri[c] = fr.origin + q.x * fr.u + q.y * fr.v;
    }
    const double a = 0.5 * glm::length(glm::cross(tri[1] - tri[0], tri[2] - tri[0]));
    if (!(a > 0)) continue;
    s.triangles.push_back(tri);
    total += a;
    s.cumulative.push_back(total);
  }
  for (double& c : s.cumulative) c /= total;
  if (!s.cumulative.empty()) s.cumulative.back() = 1.0;
  return s;
}

glm::dvec3 point_on(const FaceSampler& s, double u1, double u2, double u3) {
  if (s.triangles.empty()) return glm::dvec3(0.0);  // not reached: a face with a frame has area
  const auto t = static_cast<std::size_t>(std::upper_bound(s.cumulative.begin(), s.cumulative.end(), u1) -
                                          s.cumulative.begin());
  const auto& tr = s.triangles[std::min(t, s.triangles.size() - 1)];
  const double r = std::sqrt(u2);
  return tr[0] + r * (tr[1] - tr[0]) + r * u3 * (tr[2] - tr[1]);
}

struct Sums {
  double h = 0, h2 = 0, d = 0, d2 = 0;
};

/// The tracing state shared by every path: the Embree scene, frames, materials, lights.
class Tracer {
 public:
  Tracer(const Scene& scene, const PathTracerOptions& options, const char* place) : options_(options) {
    setup_ = frames_setup(scene, options.recentre);
    for (std::size_t l = 0; l < scene.lights.size(); ++l) {
      TracerLight tl;
      tl.intensity = scene.lights[l].intensity;
      tl.extended = scene.lights[l].is_extended();
      if (tl.extended) tl.ext = extended_light(scene, scene.lights[l], setup_.shift);
      else tl.hard = shifted_light(scene, l, setup_.shift);
      lights_.push_back(std::move(tl));
    }
    rho_.resize(scene.faces.size());
    emit_.resize(scene.faces.size());
    for (std::size_t f = 0; f < scene.faces.size(); ++f) {
      rho_[f] = scene.material_of(f).reflectance;
      emit_[f] = scene.material_of(f).emittance;
    }
    build_embree_scene(scene, setup_, thread_count(options.threads), place, es_);
    offset_ = std::max(options.offset, 8.0 * std::numeric_limits<float>::epsilon() * es_.max_coordinate);
  }

  const Setup& setup() const { return setup_; }
  /// Face f has a frame (not degenerate): paths can start on it.
  bool usable(std::size_t f) const { return setup_.frames[f].ok; }
  double reflectance(std::size_t f) const { return rho_[f]; }
  double emittance(std::size_t f) const { return emit_[f]; }

  /// One path from x (shifted) on face f: H and its direct share D; `rays` counts what it traced.
  void path(std::size_t f, glm::dvec3 x, Stream& rng, double& h, double& direct, std::uint64_t& rays) const {
    h = 0;
    direct = 0;
    double weight = 1;
    for (unsigned bounce = 0;; ++bounce) {
      const FaceFrame& fr = setup_.frames[f];
      const glm::dvec3 o = x + offset_ * fr.n;
      const double d = next_event(fr.n, x, o, rng, rays);
      if (bounce == 0) direct = d;
      h += weight * d;
      // A cosine-distributed direction over the front: the estimate of the light from the
      // surfaces is then pi L(y) = B(y) = E(y) + rho(y) H(y).
      const double u1 = rng.next(), u2 = rng.next();
      const double r = std::sqrt(u1), phi = 2.0 * kPi * u2;
      const glm::dvec3 dir = r * std::cos(phi) * fr.u + r * std::sin(phi) * fr.v + std::sqrt(std::max(0.0, 1.0 - u1)) * fr.n;
      std::size_t hit_face = 0;
      double t = 0;
      ++rays;
      if (!intersect(o, dir, hit_face, t)) return;
      const FaceFrame& hf = setup_.frames[hit_face];
      if (!(glm::dot(dir, hf.n) < 0)) return;  // a back: black
      h += weight * emit_[hit_face];
      if (options_.max_bounces != 0 && bounce + 1 > options_.max_bounces) return;
      const double rho = rho_[hit_face];
      if (!(rho > 0)) return;
      if (options_.russian_roulette) {
        if (rng.next() >= rho) return;
      } else {
        weight *= rho;
      }
      f = hit_face;
      x = o + t * dir;
    }
  }

 private:
  bool occluded(const glm::dvec3& o, const glm::dvec3& dir, float tfar) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray = occlusion_ray(o, dir, tfar);
    rtcOccluded1(es_.scene, &context, &ray);
    return ray.tfar < 0.0f;  // -inf: occluded
  }

  bool intersect(const glm::dvec3& o, const glm::dvec3& dir, std::size_t& face, double& t) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh{};
    rh.ray = occlusion_ray(o, dir, std::numeric_limits<float>::infinity());
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(es_.scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    face = es_.triangle_face[rh.hit.primID];
    t = rh.ray.tfar;
    return true;
  }

  /// The lights' irradiance at x (normal n; rays from o), one sample per light.
  double next_event(const glm::dvec3& n, const glm::dvec3& x, const glm::dvec3& o, Stream& rng,
                    std::uint64_t& rays) const {
    double sum = 0;
    for (const TracerLight& l : lights_) {
      if (!l.extended) {
        glm::dvec3 dir;
        float tfar = std::numeric_limits<float>::infinity();
        double scale = 1;
        if (l.hard.point) {
          const glm::dvec3 w = l.hard.position - x;
          const double r2 = glm::dot(w, w);
          dir = l.hard.position - o;
          const double len = glm::length(dir);
          if (!(len > offset_) || !(r2 > 0)) continue;
          tfar = static_cast<float>(1.0 - offset_ / len);
          scale = 1.0 / r2;
          dir = w / std::sqrt(r2);
        } else {
          dir = l.hard.to_light;
        }
        const double c = glm::dot(n, dir);
        if (!(c > 0)) continue;
        ++rays;
        if (!occluded(o, l.hard.point ? l.hard.position - o : dir, tfar)) sum += l.intensity * c * scale;
        continue;
      }
      const ExtendedLight& e = l.ext;
      const double u1 = rng.next(), u2 = rng.next();
      if (e.sun) {
        const double c = glm::dot(n, e.to_light);
        const glm::dvec3 dir = e.sun_direction(u1, u2);
        if (!(c > 0) || !(glm::dot(n, dir) > 0)) continue;
        ++rays;
        if (!occluded(o, dir, std::numeric_limits<float>::infinity())) sum += l.intensity * c;
        continue;
      }
      if (e.behind(x)) continue;
      const glm::dvec3 y = e.surface_point(u1, u2);
      const glm::dvec3 w = y - x;
      const double r2 = glm::dot(w, w);
      if (!(r2 > 0)) continue;
      const double r = std::sqrt(r2);
      const double c = glm::dot(n, w) / r, c_light = -glm::dot(e.normal, w) / r;
      if (!(c > 0) || !(c_light > 0)) continue;
      const glm::dvec3 to = y - o;
      const double len = glm::length(to);
      if (!(len > offset_)) continue;
      ++rays;
      if (!occluded(o, to, static_cast<float>(1.0 - offset_ / len))) sum += l.intensity * e.area * c * c_light / r2;
    }
    return sum;
  }

  PathTracerOptions options_;
  Setup setup_;
  std::vector<TracerLight> lights_;
  std::vector<double> rho_, emit_;
  EmbreeScene es_;
  double offset_ = 0;
};

void check_options(const PathTracerOptions& options, const char* place) {
  if (options.samples < 1) throw InputError({"", place}, "samples must be at least 1");
  if (!(options.offset >= 0) || !std::isfinite(options.offset))
    throw InputError({"", place}, "offset must be non-negative and finite");
  if (!options.russian_roulette && options.max_bounces == 0)
    throw InputError({"", place}, "without Russian roulette max_bounces must be above 0");
}

/// Runs `samples` paths for each of `items`; start(i, rng) gives item i's start (face, point).
/// Block sums in a fixed partition, then summed in order: independent of the thread count.
template <class Start>
PathTracerResult run_paths(const Tracer& tracer, const PathTracerOptions& options, std::size_t items,
                           const std::vector<std::size_t>& item_faces, const Start& start) {
  PathTracerResult result;
  result.max_bounces = options.max_bounces;
  result.russian_roulette = options.russian_roulette;
  const std::uint64_t blocks_per_item = (options.samples + kPathBlock - 1) / kPathBlock;
  std::vector<Sums> blocks(items * blocks_per_item);
  const unsigned threads = thread_count(options.threads);
  std::vector<std::uint64_t> rays(threads, 0);
  runtime::parallel_for(blocks.size(), threads, [&](unsigned worker, std::size_t block) {
    const std::size_t item = block / blocks_per_item;
    const std::size_t f = item_faces[item];
    if (!tracer.usable(f)) return;
    const std::uint64_t first = (block % blocks_per_item) * kPathBlock;
    const std::uint64_t last = std::min(options.samples, first + kPathBlock);
    Sums s;
    for (std::uint64_t p = first; p < last; ++p) {
      Stream rng(options.seed, item, p);
      double h = 0, d = 0;
      tracer.path(f, start(item, rng), rng, h, d, rays[worker]);
      s.h += h;
      s.h2 += h * h;
      s.d += d;
      s.d2 += d * d;
    }
    blocks[block] = s;
  });
  const double n = static_cast<double>(options.samples);
  for (std::size_t i = 0; i < items; ++i) {
    IrradianceEstimate e;
    e.face_id = item_faces[i];
    if (!!tracer.usable(e.face_id)) {
      Sums s;
      for (std::uint64_t b = 0; b < blocks_per_item; ++b) {
        const Sums& x = blocks[i * blocks_per_item + b];
        s.h += x.h;
        s.h2 += x.h2;
        s.d += x.d;
        s.d2 += x.d2;
      }
      e.paths = options.samples;
      e.irradiance = s.h / n;
      e.direct_irradiance = s.d / n;
      // The sample variance (n - 1) over n: the standard error of the mean.
      const double denominator = n > 1 ? n * (n - 1) : 1.0;
      e.standard_error = std::sqrt(std::max(0.0, (s.h2 - s.h * s.h / n) / denominator));
      e.direct_standard_error = std::sqrt(std::max(0.0, (s.d2 - s.d * s.d / n) / denominator));
      e.radiosity = tracer.emittance(e.face_id) + tracer.reflectance(e.face_id) * e.irradiance;
      result.paths += e.paths;
    }
    result.estimates.push_back(e);
  }
  for (std::uint64_t r : rays) result.rays += r;
  return result;
}

}  // namespace

PathTracerResult path_trace_faces(const Scene& scene, const PathTracerOptions& options,
                                  const std::vector<std::size_t>& faces) {
  using Clock = std::chrono::steady_clock;
  const char* place = "path tracer";
  check_options(options, place);
  std::vector<std::size_t> ids = faces;
  if (ids.empty())
    for (std::size_t f = 0; f < scene.faces.size(); ++f)
      if (!scene.faces[f].degenerate) ids.push_back(f);
  for (std::size_t f : ids)
    if (f >= scene.faces.size()) throw InputError({"", place}, "face " + std::to_string(f) + " does not exist");
  const auto t0 = Clock::now();
  const Tracer tracer(scene, options, place);
  std::vector<FaceSampler> samplers(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i)
    if (tracer.setup().frames[ids[i]].ok) samplers[i] = face_sampler(tracer.setup().frames[ids[i]]);
  const auto t1 = Clock::now();
  PathTracerResult result = run_paths(tracer, options, ids.size(), ids, [&](std::size_t item, Stream& rng) {
    const double u1 = rng.next(), u2 = rng.next(), u3 = rng.next();
    return point_on(samplers[item], u1, u2, u3);
  });
  for (IrradianceEstimate& e : result.estimates)
    if (e.paths > 0) e.area = tracer.setup().frames[e.face_id].area;
  result.prepare_seconds = std::chrono::duration<double>(t1 - t0).count();
  result.compute_seconds = std::chrono::duration<double>(Clock::now() - t1).count();
  return result;
}

PathTracerResult path_trace_points(const Scene& scene, const std::vector<SurfacePoint>& points,
                                   const PathTracerOptions& options) {
  using Clock = std::chrono::steady_clock;
  const char* place = "path tracer";
  check_options(options, place);
  check_points(scene, points, place);
  const auto t0 = Clock::now();
  const Tracer tracer(scene, options, place);
  std::vector<std::size_t> ids(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) ids[i] = points[i].face_id;
  const auto t1 = Clock::now();
  const glm::dvec3 shift = tracer.setup().shift;
  PathTracerResult result = run_paths(tracer, options, points.size(), ids,
                                      [&](std::size_t item, Stream&) { return points[item].position - shift; });
  result.prepare_seconds = std::chrono::duration<double>(t1 - t0).count();
  result.compute_seconds = std::chrono::duration<double>(Clock::now() - t1).count();
  return result;
}

}  // namespace shadow
