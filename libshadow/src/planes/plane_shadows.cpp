// SPDX-License-Identifier: GPL-3.0-or-later
// Exact shadows on planes through Blinn's projection matrix.
//
// For a plane p = (n, c) and a light l, a point of the plane is in shadow when its segment to the
// light meets a face strictly on the light's side of the plane. Every face is clipped to that
// side (s = p.(x, 1) > 0 once p is turned toward the light) and to the prism or pyramid from the
// light over a square window on the plane (a point light at the height of some geometry casts a
// shadow without end), then mapped by the exact rational matrix M = (p.l) I - l p^T with the
// homogeneous divide, and the images are united in one exact Boolean operation.
//
// This path shares no clipping or projection code with the per-face engine on purpose: a face
// lying in a plane must come out of both with the same shadow, and the tests check that.
#include "geometry/box_sides.hpp"
#include "geometry/clip_convex.hpp"
#include "core/culling.hpp"
#include "exact/exact_faces.hpp"
#include "core/parallel.hpp"
#include "planes/plane_shadows.hpp"
#include "exact/regions.hpp"
#include "core/input_checks.hpp"
#include "core/lights.hpp"

#include <shadow/scene_io.hpp>
#include <shadow/shadows.hpp>


#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <gmpxx.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace shadow {
namespace planes {
namespace {

using Q4 = std::array<mpq_class, 4>;  // homogeneous point or plane, exact
using Q3 = std::array<mpq_class, 3>;

mpq_class dot4(const Q4& a, const Q4& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]; }

/// Value of the affine function (a, b) at a point: a.x + b.
mpq_class affine(const Q4& f, const Q3& x) { return f[0] * x[0] + f[1] * x[1] + f[2] * x[2] + f[3]; }

/// Sutherland-Hodgman clip of a convex polygon to f >= 0 (geometry/clip_convex.hpp: crossings
/// only at strict sign changes, so no duplicate vertices). Returns whether anything was cut away.
bool clip(std::vector<Q3>& poly, const Q4& f) {
  const std::size_t n = poly.size();
  if (n == 0) return false;
  std::vector<mpq_class> value(n);
  for (std::size_t a = 0; a < n; ++a) value[a] = affine(f, poly[a]);
  auto side = [&](std::size_t a) { return sgn(value[a]); };
  const geometry::ClipCase what = geometry::clip_case(n, side);
  if (what == geometry::ClipCase::Inside) return false;
  std::vector<Q3> out;
  if (what == geometry::ClipCase::Cut)
    geometry::clip_convex(poly, side, [&](std::size_t a, std::size_t b) {
      const mpq_class t = value[a] / (value[a] - value[b]);
      Q3 x;
      for (int c = 0; c < 3; ++c) x[c] = poly[a][c] + t * (poly[b][c] - poly[a][c]);
      return x;
    }, out);
  poly.swap(out);
  return true;
}

/// One plane and one light.
PlaneShadow plane_shadow(const Scene& scene, const std::vector<core::FacePrep>& prep, std::size_t plane_id,
                         std::size_t light_id, const core::SceneFrame& frame, double window) {
  PlaneShadow out;
  out.plane_id = plane_id;
  out.light_id = light_id;
  out.window_half_size = window;
  const Plane& plane = scene.planes[plane_id];
  const Light& light = scene.lights[light_id];

  const Q3 n{mpq_class(plane.normal.x), mpq_class(plane.normal.y), mpq_class(plane.normal.z)};
  const mpq_class c = -(n[0] * plane.point.x + n[1] * plane.point.y + n[2] * plane.point.z);
  Q4 p{n[0], n[1], n[2], c};
  const bool point = light.type == LightType::Point;
  const glm::dvec3 lv = point ? light.position : light.to_light;
  const Q4 l{mpq_class(lv.x), mpq_class(lv.y), mpq_class(lv.z), mpq_class(point ? 1 : 0)};
  mpq_class pl = dot4(p, l);
  if (sgn(pl) == 0) return out;  // the light lies in the plane (or shines along it): no shadow
  if (sgn(pl) < 0) {             // receive on the light's side
    for (mpq_class& x : p) x = -x;
    pl = -pl;
  }
  // Blinn's matrix, rows: M[r] . x = pl x_r - l_r (p . x).
  std::array<Q4, 4> M;
  for (int r = 0; r < 4; ++r)
    for (int col = 0; col < 4; ++col) M[r][col] = (r == col ? pl : mpq_class(0)) - l[r] * p[col];

  // The plane's chart and the window in it.
  const glm::dvec3 an = glm::abs(plane.normal);
  const int k = an.x >= an.y && an.x >= an.z ? 0 : (an.y >= an.z ? 1 : 2);
  const int i = core::chart_i(k), j = core::chart_j(k);
  const double lo[2] = {frame.centre[i] - window, frame.centre[j] - window};
  const double hi[2] = {frame.centre[i] + window, frame.centre[j] + window};
  // Prism or pyramid from the light over the window: for a bound x_c >= m the plane through the
  // bound's line on the receiving plane and the light is pl (x_c - m) - (l_c - m l_w) s(x) = 0.
  const std::array<Q4, 4> sides = geometry::box_sides(p, l, pl, i, j, lo, hi);

  // The light's level: p.l - p.x >= 0 (point lights).
  Q4 level;
  for (int col = 0; col < 4; ++col) level[col] = -p[col];
  level[3] += pl;
  std::vector<exact::Polygon2> images;
  std::vector<Q3> poly;
  for (std::size_t q = 0; q < scene.faces.size(); ++q) {
    const core::FacePrep& qp = prep[q];
    if (qp.degenerate) continue;
    const Face& face = scene.faces[q];
    std::vector<Q3> vertex(face.vertices.size());
    if (qp.exactly_planar) {
      for (std::size_t v = 0; v < face.vertices.size(); ++v)
        vertex[v] = {mpq_class(face.vertices[v].x), mpq_class(face.vertices[v].y), mpq_class(face.vertices[v].z)};
    } else {  // lifted onto its exact plane, as the per-face engine does
      const exact::ExactFace ef = exact::make_exact_face(face.vertices, qp);
      for (std::size_t v = 0; v < ef.vertices.size(); ++v)
        for (int a = 0; a < 3; ++a) vertex[v][a] = CGAL::exact(ef.vertices[v][a]);
    }
    for (const std::vector<int>& piece : qp.convex_pieces) {
      poly.clear();
      for (int v : piece) poly.push_back(vertex[v]);
      // Strictly on the light's side of the plane: the closure of s > 0 when s > 0 somewhere.
      if (std::none_of(poly.begin(), poly.end(), [&](const Q3& x) { return sgn(affine(p, x)) > 0; })) continue;
      clip(poly, p);
      // Nothing at or beyond a point light's level casts (it lies outside the pyramid anyway):
      // cut it first so that only what really projects outside the window counts as cut by it.
      if (point) clip(poly, level);
      bool cut_by_window = false;
      for (const Q4& side : sides) cut_by_window |= clip(poly, side);
      if (poly.size() < 3) {
        out.reaches_window |= cut_by_window;
        continue;
      }
      exact::Polygon2 image;
      bool touches_light = false;
      for (const Q3& x : poly) {
        const Q4 h{x[0], x[1], x[2], mpq_class(1)};
        const mpq_class w = dot4(M[3], h);
        // w = 0 only at the lamp itself: this face's plane contains the light, it is edge-on.
        if (sgn(w) == 0) {
          touches_light = true;
          break;
        }
        image.push_back(exact::Point2(exact::FT(mpq_class(dot4(M[i], h) / w)), exact::FT(mpq_class(dot4(M[j], h) / w))));
      }
      if (touches_light) continue;
      out.reaches_window |= cut_by_window;
      const CGAL::Sign orientation = CGAL::sign(exact::polygon_area(image));
      if (orientation == CGAL::ZERO) continue;  // edge-on to the light
      if (orientation == CGAL::NEGATIVE) image.reverse_orientation();
      images.push_back(std::move(image));
    }
  }
  if (images.empty()) return out;

  exact::PolygonSet2 shadow;
  shadow.join(images.begin(), images.end());
  std::vector<exact::PolygonWithHoles2> regions;
  shadow.polygons_with_holes(std::back_inserter(regions));

  // Back to 3D on the plane (as given, not turned): x_k = -(c + n_i x_i + n_j x_j) / n_k.
  const exact::FT nk(n[k]), ni(n[i]), nj(n[j]), cc(c);
  const exact::FT scale_squared = exact::FT(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) / (nk * nk);
  const bool flipped = plane.normal[k] < 0;  // the chart sees the plane clockwise
  std::vector<exact::FT> region_areas;  // summed as a balanced tree (kernel.hpp, exact::balanced_sum)
  std::vector<exact::Polygon2> cells;
  for (std::size_t r = 0; r < regions.size(); ++r) {
    cells.clear();
    region_areas.push_back(exact::region_area(regions[r]));
    exact::append_simple_cells(regions[r], cells);
    for (const exact::Polygon2& cell : cells) {
      std::vector<glm::dvec3> polygon;
      for (auto v = cell.vertices_begin(); v != cell.vertices_end(); ++v) {
        glm::dvec3 x;
        x[i] = CGAL::to_double(v->x());
        x[j] = CGAL::to_double(v->y());
        x[k] = CGAL::to_double(-(cc + ni * v->x() + nj * v->y()) / nk);
        polygon.push_back(x);
      }
      if (flipped == CGAL::is_positive(exact::polygon_area(cell))) std::reverse(polygon.begin(), polygon.end());
      out.polygons.push_back(std::move(polygon));
      out.region_id.push_back(r);
      out.polygon_area.push_back(exact::area_3d(CGAL::abs(exact::polygon_area(cell)), scale_squared));
    }
  }
  out.area = exact::area_3d(exact::balanced_sum(region_areas), scale_squared);
  return out;
}

}  // namespace
}  // namespace planes

namespace planes {

std::vector<PlaneShadow> plane_shadows(const Scene& scene, const std::vector<core::FacePrep>& prep,
                                       const ShadowOptions& options) {
  const std::vector<std::size_t> light_ids = shadow::detail::resolve_lights(scene, options.lights);
  const unsigned threads = core::checked_threads(options.threads);
  if (!(options.plane_window >= 0 && options.plane_window <= max_coordinate))
    throw InputError({"", "ShadowOptions::plane_window"},
                     "must be in [0, 2^500 (about 3.27e150)], got " + shadow::detail::format_number(options.plane_window));
  if (scene.planes.empty() || light_ids.empty()) return {};

  const core::SceneFrame frame = core::scene_frame(scene);
  const double window = options.plane_window > 0 ? options.plane_window : 10.0 * frame.diagonal;
  for (std::size_t plane_id = 0; plane_id < scene.planes.size(); ++plane_id) {
    const double own = scene.planes[plane_id].window > 0 ? scene.planes[plane_id].window : window;
    // The window's corners must be finite numbers to become exact rationals.
    const glm::dvec3 lo = frame.centre - own, hi = frame.centre + own;
    if (!std::isfinite(own) || !std::isfinite(lo.x + lo.y + lo.z) || !std::isfinite(hi.x + hi.y + hi.z))
      throw InputError({"", "planes[" + std::to_string(plane_id) + "].window"},
                       "the plane-shadow window is too large to represent (" + std::to_string(own) + ")");
  }
  std::vector<PlaneShadow> shadows(scene.planes.size() * light_ids.size());
  core::parallel_for(shadows.size(), core::resolve_threads(threads), [&](unsigned, std::size_t item) {
    const std::size_t plane_id = item / light_ids.size();
    const double own = scene.planes[plane_id].window;
    shadows[item] = planes::plane_shadow(scene, prep, plane_id, light_ids[item % light_ids.size()], frame,
                                        own > 0 ? own : window);
  });
  return shadows;
}

}  // namespace planes

std::vector<PlaneShadow> compute_plane_shadows(const Scene& scene, const ShadowOptions& options) {
  shadow::detail::check_scene_numbers(scene);  // the scene may never have been validated
  std::vector<core::FacePrep> prep(scene.faces.size());
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    if (scene.faces[f].degenerate || scene.faces[f].vertices.size() < 3) {
      prep[f].degenerate = true;
      continue;
    }
    prep[f] = exact::prepare_face(scene.faces[f].vertices);
  }
  return planes::plane_shadows(scene, prep, options);
}

}  // namespace shadow
