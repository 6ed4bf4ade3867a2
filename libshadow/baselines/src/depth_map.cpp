// SPDX-License-Identifier: GPL-3.0-or-later
// Depth maps from a light: the z-buffer algorithm (Catmull) run from the light.
#include "depth_map.hpp"

#include "runtime/parallel.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace shadow::baselines_detail {

namespace {

constexpr float kFar = std::numeric_limits<float>::infinity();

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

glm::dvec3 cube_world(const glm::dvec3& l, int k) {
  const CubeFace c = kCube[k];
  const int i = (c.axis + 1) % 3, j = (c.axis + 2) % 3;
  glm::dvec3 q(0.0);
  q[i] = l.x;
  q[j] = l.y;
  q[c.axis] = c.sign * l.z;
  return q;
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
  runtime::parallel_for(threads, threads, [&](unsigned, std::size_t t) {
    for (DepthMap& map : maps) {
      const int R = map.resolution;
      const int begin = static_cast<int>(static_cast<long long>(R) * static_cast<long long>(t) / threads);
      const int end = static_cast<int>(static_cast<long long>(R) * static_cast<long long>(t + 1) / threads);
      rasterise(map, perspective, begin, end);
    }
  });
}

}  // namespace

MapPoint LightMaps::locate(const glm::dvec3& p) const {
  MapPoint m;
  const int R = resolution;
  if (light.point) {
    const glm::dvec3 q = p - light.position;
    const glm::dvec3 a = glm::abs(q);
    const int axis = (a.x >= a.y && a.x >= a.z) ? 0 : (a.y >= a.z ? 1 : 2);
    m.face = 2 * axis + (q[axis] >= 0 ? 0 : 1);
    const glm::dvec3 loc = cube_local(q, m.face);
    m.depth = glm::length(q);
    m.foot = m.depth * 2.0 / R;
    if (!(loc.z > 0)) return m;
    const double half = 0.5 * R;
    m.x = half + half * loc.x / loc.z;
    m.y = half + half * loc.y / loc.z;
    m.inside = true;
  } else {
    m.x = (glm::dot(p, u) - a0) / texel;
    m.y = (glm::dot(p, v) - b0) / texel;
    m.depth = -glm::dot(p, light.to_light);
    m.foot = texel;
    m.inside = m.x >= 0 && m.x < R && m.y >= 0 && m.y < R;
  }
  return m;
}

float LightMaps::stored(const MapPoint& m) const {
  const int R = resolution;
  if (!m.inside) return kFar;
  if (light.point) {
    const long long xc = std::clamp<long long>(static_cast<long long>(std::floor(m.x)), 0, R - 1);
    const long long yc = std::clamp<long long>(static_cast<long long>(std::floor(m.y)), 0, R - 1);
    return maps[static_cast<std::size_t>(m.face)].depth[static_cast<std::size_t>(yc * R + xc)];
  }
  return maps[0].depth[static_cast<std::size_t>(m.y) * static_cast<std::size_t>(R) + static_cast<std::size_t>(m.x)];
}

bool LightMaps::on_plane(int face, double x, double y, const glm::dvec3& p0, const glm::dvec3& n,
                         glm::dvec3& out) const {
  if (light.point) {
    const double half = 0.5 * resolution;
    const glm::dvec3 w = cube_world({(x - half) / half, (y - half) / half, 1.0}, face);
    const double denom = glm::dot(n, w);
    if (!(std::abs(denom) > 0)) return false;
    const double s = glm::dot(n, p0 - light.position) / denom;
    if (!(s > 0) || !std::isfinite(s)) return false;
    out = light.position + s * w;
    return true;
  }
  const glm::dvec3& l = light.to_light;
  const double denom = glm::dot(n, l);
  if (!(std::abs(denom) > 0)) return false;
  const glm::dvec3 a = (x * texel + a0) * u + (y * texel + b0) * v;  // depth 0 on this ray
  const double t = (glm::dot(n, a) - glm::dot(n, p0)) / denom;  // depth where it meets the plane
  if (!std::isfinite(t)) return false;
  out = a - t * l;
  return true;
}

std::size_t LightMaps::bytes() const {
  return maps.size() * static_cast<std::size_t>(resolution) * static_cast<std::size_t>(resolution) * sizeof(float);
}

std::vector<glm::dvec3> scene_triangles(const Scene& scene, const Setup& setup, double& diagonal) {
  std::vector<glm::dvec3> tri;  // 3 per triangle
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const FaceFrame& fr = setup.frames[f];
    if (!fr.ok) continue;
    for (const auto& t : triangulate(fr.polygon))
      for (std::uint32_t i : t) tri.push_back(scene.faces[f].vertices[i] - setup.shift);
  }
  diagonal = 0;
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
  for (const glm::dvec3& p : tri) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  if (!tri.empty()) diagonal = glm::length(hi - lo);
  return tri;
}

LightMaps build_light_maps(const std::vector<glm::dvec3>& tri, double diag, const ShiftedLight& light,
                           const std::vector<glm::dvec3>& window_points, int R, unsigned threads) {
  LightMaps lm;
  lm.light = light;
  lm.resolution = R;
  std::vector<DepthMap>& maps = lm.maps;
  maps.resize(light.point ? 6 : 1);
  for (DepthMap& m : maps) m.resolution = R;
  if (!light.point) {
    // Orthographic frame for a sun: u, v across the light, depth along the light's travel.
    const glm::dvec3 l = light.to_light;
    const glm::dvec3 helper = std::abs(l.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
    lm.u = glm::normalize(glm::cross(helper, l));
    lm.v = glm::cross(l, lm.u);
    // Window: the receivers' bounds across the light, square so texels are square.
    double lo_a = std::numeric_limits<double>::max(), hi_a = -lo_a, lo_b = lo_a, hi_b = -lo_a;
    for (const glm::dvec3& p : window_points) {
      lo_a = std::min(lo_a, glm::dot(p, lm.u));
      hi_a = std::max(hi_a, glm::dot(p, lm.u));
      lo_b = std::min(lo_b, glm::dot(p, lm.v));
      hi_b = std::max(hi_b, glm::dot(p, lm.v));
    }
    if (lo_a > hi_a) lo_a = hi_a = lo_b = hi_b = 0;
    const double side = std::max({hi_a - lo_a, hi_b - lo_b, 1e-9 * std::max(1.0, diag)}) * (1 + 1e-6);
    lm.texel = side / R;
    lm.a0 = 0.5 * (lo_a + hi_a) - 0.5 * side;
    lm.b0 = 0.5 * (lo_b + hi_b) - 0.5 * side;
    DepthMap& m = maps[0];
    m.triangles.reserve(tri.size() / 3);
    for (std::size_t i = 0; i < tri.size(); i += 3) {
      MapTriangle t;
      for (int c = 0; c < 3; ++c) {
        const glm::dvec3& p = tri[i + c];
        t.p[c] = {(glm::dot(p, lm.u) - lm.a0) / lm.texel, (glm::dot(p, lm.v) - lm.b0) / lm.texel};
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
  lm.min_depth = std::numeric_limits<double>::infinity();
  for (DepthMap& m : maps) {
    m.triangles = {};
    for (float d : m.depth) lm.min_depth = std::min(lm.min_depth, static_cast<double>(d));
  }
  return lm;
}

}  // namespace shadow::baselines_detail
