// SPDX-License-Identifier: GPL-3.0-or-later
// Shadow mapping: the z-buffer algorithm (Catmull) run from the light, then a depth comparison
// with bias for every sample point of every receiving face.
#include "baselines/sampling.hpp"
#include "core/parallel.hpp"

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

namespace {

constexpr float kFar = std::numeric_limits<float>::infinity();

/// A triangle in a map's image coordinates (texel units, texel centres at +0.5) with what is
/// needed to get its depth at a texel centre.
struct MapTriangle {
  glm::dvec2 p[3];
  double depth[3];         // orthographic: depth at each vertex (interpolated linearly)
  glm::dvec3 normal{0.0};  // perspective: plane n . x = offset in the cube face's local frame
  double plane = 0.0;
};

/// One depth map: R x R floats, nearest depth to the light per texel (+inf: empty).
struct DepthMap {
  int resolution = 0;
  std::vector<float> depth;
  std::vector<MapTriangle> triangles;
};

/// Cube face k: major axis k / 2, sign + for even k. Local frame (x, y, z) with z along the axis.
struct CubeFace {
  int axis;
  double sign;
};
constexpr CubeFace kCube[6] = {{0, 1}, {0, -1}, {1, 1}, {1, -1}, {2, 1}, {2, -1}};

glm::dvec3 cube_local(const glm::dvec3& q, int k) {
  const CubeFace c = kCube[k];
  const int i = (c.axis + 1) % 3, j = (c.axis + 2) % 3;
  return {q[i], q[j], c.sign * q[c.axis]};
}

/// Rasterises map.triangles into rows [row_begin, row_end), keeping the smallest depth.
void rasterise(DepthMap& map, bool perspective, int row_begin, int row_end) {
  const int R = map.resolution;
  const double half = 0.5 * R;
  for (const MapTriangle& t : map.triangles) {
    double area = (t.p[1].x - t.p[0].x) * (t.p[2].y - t.p[0].y) - (t.p[1].y - t.p[0].y) * (t.p[2].x - t.p[0].x);
    if (!(std::abs(area) > 0) || !std::isfinite(area)) continue;  // edge-on to the light
    const double lo_y = std::min({t.p[0].y, t.p[1].y, t.p[2].y}), hi_y = std::max({t.p[0].y, t.p[1].y, t.p[2].y});
    // Clamp to [-1, R] in double before converting: a vertex far outside the map (a caster
    // beyond the receivers' window, or near a lamp's near plane) must not overflow int.
    auto texel = [R](double v) { return std::clamp(v, -1.0, static_cast<double>(R)); };
    if (!std::isfinite(lo_y) || !std::isfinite(hi_y)) continue;
    const int y0 = std::max(row_begin, static_cast<int>(std::ceil(texel(lo_y - 0.5))));
    const int y1 = std::min(row_end - 1, static_cast<int>(std::floor(texel(hi_y - 0.5))));
    if (y0 > y1) continue;
    const double lo_x = std::min({t.p[0].x, t.p[1].x, t.p[2].x}), hi_x = std::max({t.p[0].x, t.p[1].x, t.p[2].x});
    if (!std::isfinite(lo_x) || !std::isfinite(hi_x)) continue;
    const int x0 = std::max(0, static_cast<int>(std::ceil(texel(lo_x - 0.5))));
    const int x1 = std::min(R - 1, static_cast<int>(std::floor(texel(hi_x - 0.5))));
    if (x0 > x1) continue;
    const double s = area > 0 ? 1.0 : -1.0;
    for (int y = y0; y <= y1; ++y) {
      const double cy = y + 0.5;
      for (int x = x0; x <= x1; ++x) {
        const double cx = x + 0.5;
        // Barycentric weights (edge functions); centres on an edge count for both triangles.
        const double w0 = s * ((t.p[2].x - t.p[1].x) * (cy - t.p[1].y) - (t.p[2].y - t.p[1].y) * (cx - t.p[1].x));
        const double w1 = s * ((t.p[0].x - t.p[2].x) * (cy - t.p[2].y) - (t.p[0].y - t.p[2].y) * (cx - t.p[2].x));
        const double w2 = s * ((t.p[1].x - t.p[0].x) * (cy - t.p[0].y) - (t.p[1].y - t.p[0].y) * (cx - t.p[0].x));
        if (w0 < 0 || w1 < 0 || w2 < 0) continue;
        double d;
        if (perspective) {
          // Ray from the light through the texel centre: direction (a, b, 1) in the local frame.
          const glm::dvec3 dir((cx - half) / half, (cy - half) / half, 1.0);
          const double denom = glm::dot(t.normal, dir);
          if (!(std::abs(denom) > 0)) continue;
          const double tt = t.plane / denom;
          if (!(tt > 0)) continue;
          d = tt * glm::length(dir);  // distance from the light
        } else {
          const double sum = w0 + w1 + w2;
          d = (w0 * t.depth[0] + w1 * t.depth[1] + w2 * t.depth[2]) / sum;
        }
        float& cell = map.depth[static_cast<std::size_t>(y) * static_cast<std::size_t>(R) + static_cast<std::size_t>(x)];
        cell = std::min(cell, static_cast<float>(d));
      }
    }
  }
}

void rasterise_all(std::vector<DepthMap>& maps, bool perspective, unsigned threads) {
  // Bands of rows per thread: no two threads write the same texel, no locks.
  core::parallel_for(threads, threads, [&](unsigned, std::size_t t) {
    for (DepthMap& map : maps) {
      const int R = map.resolution;
      const int begin = static_cast<int>(static_cast<long long>(R) * static_cast<long long>(t) / threads);
      const int end = static_cast<int>(static_cast<long long>(R) * static_cast<long long>(t + 1) / threads);
      rasterise(map, perspective, begin, end);
    }
  });
}

}  // namespace

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
  std::vector<glm::dvec3> tri;  // 3 per triangle
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const FaceFrame& fr = setup.frames[f];
    if (!fr.ok) continue;
    for (const auto& t : triangulate(fr.polygon))
      for (std::uint32_t i : t) tri.push_back(scene.faces[f].vertices[i] - setup.shift);
  }
  double diag = 0;
  {
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
    for (const glm::dvec3& p : tri) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    if (!tri.empty()) diag = glm::length(hi - lo);
  }

  double prepare = std::chrono::duration<double>(Clock::now() - start).count(), compute = 0;
  std::vector<std::uint64_t> samples(setup.result.lighting.size(), 0), lit(samples.size(), 0);
  for (std::size_t k = 0; k < setup.lights.size(); ++k) {
    const auto t0 = Clock::now();
    const ShiftedLight light = setup.shifted[k];
    std::vector<DepthMap> maps(light.point ? 6 : 1);
    for (DepthMap& m : maps) m.resolution = R;
    // Orthographic frame for a sun: u, v across the light, depth along the light's travel.
    glm::dvec3 u(0.0), v(0.0);
    double a0 = 0, b0 = 0, texel = 1;
    if (!light.point) {
      const glm::dvec3 l = light.to_light;
      const glm::dvec3 helper = std::abs(l.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
      u = glm::normalize(glm::cross(helper, l));
      v = glm::cross(l, u);
      // Window: the receivers' bounds across the light, square so texels are square.
      double lo_a = std::numeric_limits<double>::max(), hi_a = -lo_a, lo_b = lo_a, hi_b = -lo_a;
      for (const FaceLighting& fl : setup.result.lighting) {
        if (fl.light_id != setup.lights[k] || !setup.frames[fl.face_id].ok) continue;
        for (const glm::dvec3& p0 : scene.faces[fl.face_id].vertices) {
          const glm::dvec3 p = p0 - setup.shift;
          lo_a = std::min(lo_a, glm::dot(p, u));
          hi_a = std::max(hi_a, glm::dot(p, u));
          lo_b = std::min(lo_b, glm::dot(p, v));
          hi_b = std::max(hi_b, glm::dot(p, v));
        }
      }
      if (lo_a > hi_a) lo_a = hi_a = lo_b = hi_b = 0;
      const double side = std::max({hi_a - lo_a, hi_b - lo_b, 1e-9 * std::max(1.0, diag)}) * (1 + 1e-6);
      texel = side / R;
      a0 = 0.5 * (lo_a + hi_a) - 0.5 * side;
      b0 = 0.5 * (lo_b + hi_b) - 0.5 * side;
      DepthMap& m = maps[0];
      m.triangles.reserve(tri.size() / 3);
      for (std::size_t i = 0; i < tri.size(); i += 3) {
        MapTriangle t;
        for (int c = 0; c < 3; ++c) {
          const glm::dvec3& p = tri[i + c];
          t.p[c] = {(glm::dot(p, u) - a0) / texel, (glm::dot(p, v) - b0) / texel};
          t.depth[c] = -glm::dot(p, l);  // grows away from the light
        }
        m.triangles.push_back(t);
      }
    } else {
      // Cube map: clip each triangle to z > near in each face's frame, project (x/z, y/z).
      const double near = 1e-6 * std::max(1.0, diag);
      const double half = 0.5 * R;
      for (std::size_t i = 0; i < tri.size(); i += 3) {
        for (int face = 0; face < 6; ++face) {
          glm::dvec3 q[3];
          for (int c = 0; c < 3; ++c) q[c] = cube_local(tri[i + c] - light.position, face);
          if (q[0].z <= near && q[1].z <= near && q[2].z <= near) continue;
          // Quick reject: wholly outside one side of the 90-degree frustum.
          if ((q[0].x > q[0].z && q[1].x > q[1].z && q[2].x > q[2].z) ||
              (-q[0].x > q[0].z && -q[1].x > q[1].z && -q[2].x > q[2].z) ||
              (q[0].y > q[0].z && q[1].y > q[1].z && q[2].y > q[2].z) ||
              (-q[0].y > q[0].z && -q[1].y > q[1].z && -q[2].y > q[2].z))
            continue;
          const glm::dvec3 n = glm::cross(q[1] - q[0], q[2] - q[0]);
          if (!(glm::length(n) > 0)) continue;
          // Sutherland-Hodgman against z > near: a convex polygon of 3 or 4 vertices.
          glm::dvec3 poly[4];
          int count = 0;
          for (int c = 0; c < 3; ++c) {
            const glm::dvec3& a = q[c];
            const glm::dvec3& b = q[(c + 1) % 3];
            const bool ina = a.z > near, inb = b.z > near;
            if (ina) poly[count++] = a;
            if (ina != inb && count < 4) poly[count++] = a + (b - a) * ((near - a.z) / (b.z - a.z));
          }
          for (int c = 1; c + 1 < count; ++c) {
            MapTriangle t;
            const glm::dvec3 corners[3] = {poly[0], poly[c], poly[c + 1]};
            for (int e = 0; e < 3; ++e)
              t.p[e] = {half + half * corners[e].x / corners[e].z, half + half * corners[e].y / corners[e].z};
            t.normal = n;
            t.plane = glm::dot(n, q[0]);
            maps[static_cast<std::size_t>(face)].triangles.push_back(t);
          }
        }
      }
    }
    for (DepthMap& m : maps) m.depth.assign(static_cast<std::size_t>(R) * static_cast<std::size_t>(R), kFar);
    rasterise_all(maps, light.point, threads);
    for (DepthMap& m : maps) m.triangles = {};
    setup.result.map_bytes = std::max(setup.result.map_bytes, maps.size() * static_cast<std::size_t>(R) * R * sizeof(float));
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
        j.spacing = options.sample_spacing * texel;
      }
    }
    const double cb = options.constant_bias, sb = options.slope_bias, sb_max = options.max_slope_bias;
    std::vector<std::uint64_t> s(samples.size(), 0), l(samples.size(), 0);
    run_sampling(jobs, threads, options.max_samples_per_face,
                 [&](unsigned) {
                   auto lit_point = [&](const glm::dvec3& p, const SampleJob& job) {
                     double depth, foot, cosine;
                     float stored;
                     if (light.point) {
                       const glm::dvec3 q = p - light.position;
                       const glm::dvec3 a = glm::abs(q);
                       const int axis = (a.x >= a.y && a.x >= a.z) ? 0 : (a.y >= a.z ? 1 : 2);
                       const int face = 2 * axis + (q[axis] >= 0 ? 0 : 1);
                       const glm::dvec3 loc = cube_local(q, face);
                       if (!(loc.z > 0)) return true;
                       const double half = 0.5 * R;
                       const auto x = static_cast<long long>(std::floor(half + half * loc.x / loc.z));
                       const auto y = static_cast<long long>(std::floor(half + half * loc.y / loc.z));
                       const long long xc = std::clamp<long long>(x, 0, R - 1), yc = std::clamp<long long>(y, 0, R - 1);
                       stored = maps[static_cast<std::size_t>(face)].depth[static_cast<std::size_t>(yc * R + xc)];
                       depth = glm::length(q);
                       foot = depth * 2.0 / R;
                       cosine = -glm::dot(job.frame->n, q) / depth;
                     } else {
                       const double a = (glm::dot(p, u) - a0) / texel, b = (glm::dot(p, v) - b0) / texel;
                       if (!(a >= 0 && a < R && b >= 0 && b < R)) return true;  // outside the map: lit
                       stored = maps[0].depth[static_cast<std::size_t>(b) * static_cast<std::size_t>(R) +
                                              static_cast<std::size_t>(a)];
                       depth = -glm::dot(p, light.to_light);
                       foot = texel;
                       cosine = glm::dot(job.frame->n, light.to_light);
                     }
                     cosine = std::clamp(cosine, 1e-12, 1.0);
                     const double tangent = std::sqrt(std::max(0.0, 1.0 - cosine * cosine)) / cosine;
                     const double bias = cb + foot * std::min(sb * tangent, sb_max);
                     return depth <= static_cast<double>(stored) + bias;
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
