// SPDX-License-Identifier: GPL-3.0-or-later
// Exact vector views (shadow/view.hpp, docs/vector-views.md): the second pass of Atherton's
// method with the exact engine's own machinery.
//
// Per face F, in exact rationals in F's chart:
//   visible(F) = the region of F that a point light at the eye lights (exact_lit_region),
//                computed on a copy of the scene in which every face seen from its back is
//                turned around (the engine lights only fronts; from the eye, each face shows
//                the side it is seen from, and every face blocks from both sides anyway);
//   in view    = visible(F) cut to the frustum: the chart's box lifted onto F's plane, clipped
//                to the near plane and the four planes through the eye and the image's sides;
//   lit / dark = in view intersected with / minus the region the chosen light reaches on F
//                (exact_lit_region again, on the scene as given); a face seen from its back is
//                wholly dark (only the front can be lit).
// Every piece is then cut into simple cells (exact/regions.hpp), lifted onto F's plane and
// rounded once, as the engine writes fragments.
#include "core/culling.hpp"
#include "core/face_prep.hpp"
#include "core/lights.hpp"
#include "runtime/parallel.hpp"
#include "core/prepared_scene.hpp"
#include "engine/engine_access.hpp"
#include "exact/exact_faces.hpp"
#include "exact/exact_receiver.hpp"
#include "exact/lazy_geometry.hpp"
#include "exact/regions.hpp"

#include <shadow/error.hpp>
#include <shadow/view.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <optional>
#include <string>
#include <utility>

namespace shadow {
namespace {

using namespace exact;

bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

Vector3 to_exact_vector(const glm::dvec3& v) { return Vector3(v.x, v.y, v.z); }

/// a . (p - e) >= c as an Affine3 a . p + b >= 0, exact in the doubles a, e, c.
Affine3 half_space(const glm::dvec3& a, const glm::dvec3& e, double c) {
  const Vector3 ea = to_exact_vector(a);
  return {ea, -(ea.x() * FT(e.x) + ea.y() * FT(e.y) + ea.z() * FT(e.z)) - FT(c)};
}

/// The five half-spaces of the view: in front of the near plane, inside the image's sides.
std::vector<Affine3> frustum(const ViewFrame& fr) {
  const double ty = (fr.height / 2.0) / fr.focal;  // tan(fov / 2)
  const double tx = (fr.width / 2.0) / fr.focal;
  return {half_space(fr.forward, fr.eye, fr.near),
          half_space(tx * fr.forward - fr.right, fr.eye, 0.0), half_space(tx * fr.forward + fr.right, fr.eye, 0.0),
          half_space(ty * fr.forward - fr.up, fr.eye, 0.0), half_space(ty * fr.forward + fr.up, fr.eye, 0.0)};
}

/// The part of face P's chart inside the frustum: a convex polygon, counter-clockwise (empty
/// when the frustum misses P's plane within its chart box, or meets it edge-on).
Polygon2 frustum_in_chart(const ExactFace& P, const core::FacePrep& fp, const std::vector<Affine3>& sides) {
  std::vector<Point3> poly, scratch;
  const double x0 = fp.chart_min[0], y0 = fp.chart_min[1], x1 = fp.chart_max[0], y1 = fp.chart_max[1];
  for (const Point2& c : {Point2(x0, y0), Point2(x1, y0), Point2(x1, y1), Point2(x0, y1)})
    poly.push_back(lift(c, P, fp.axis));
  for (const Affine3& side : sides) clip_convex(poly, side, scratch);
  Polygon2 out;
  for (const Point3& p : poly) out.push_back(to_chart(p, fp.axis));
  if (out.size() < 3) return {};
  const CGAL::Sign s = CGAL::sign(polygon_area(out));
  if (s == CGAL::ZERO) return {};
  if (s == CGAL::NEGATIVE) out.reverse_orientation();
  return out;
}

/// A region of the chart of `from` (dropped axis from_axis) in the chart of `to` (to_axis):
/// the same set when the axes agree; otherwise each vertex lifted onto the plane and dropped
/// the other way (both faces are the same face, so one plane).
PolygonSet2 to_other_chart(const PolygonSet2& region, const ExactFace& from, int from_axis, int to_axis) {
  if (from_axis == to_axis) return region;
  auto convert = [&](const Polygon2& poly) {
    Polygon2 out;
    for (auto v = poly.vertices_begin(); v != poly.vertices_end(); ++v)
      out.push_back(to_chart(lift(*v, from, from_axis), to_axis));
    if (CGAL::is_negative(polygon_area(out))) out.reverse_orientation();
    return out;
  };
  std::vector<PolygonWithHoles2> regions;
  region.polygons_with_holes(std::back_inserter(regions));
  PolygonSet2 out;
  for (const PolygonWithHoles2& r : regions) {
    PolygonSet2 piece(convert(r.outer_boundary()));
    for (auto h = r.holes_begin(); h != r.holes_end(); ++h) piece.difference(convert(*h));
    out.join(piece);
  }
  return out;
}

/// Writes the cells of one face's pieces.
class PieceWriter {
 public:
  PieceWriter(const ExactFace& P, const core::FacePrep& fp, const ViewFrame& frame, std::size_t face_id, bool back)
      : P_(P), fp_(fp), frame_(frame), face_id_(face_id), back_(back) {}

  void add(const PolygonSet2& set, bool lit) {
    std::vector<PolygonWithHoles2> regions;
    set.polygons_with_holes(std::back_inserter(regions));
    std::vector<Polygon2> cells, triangles;
    for (const PolygonWithHoles2& region : regions) {
      cells.clear();
      append_simple_cells(region, cells);
      for (Polygon2& cell : cells) {
        const FT cell_area = polygon_area(cell);
        if (write(cell, cell_area, lit)) continue;
        // Rounding broke the cell: its triangles instead, those that collapse left out and
        // counted (as the engine does with fragments).
        if (CGAL::is_negative(cell_area)) cell.reverse_orientation();
        triangles.clear();
        triangulate_region(PolygonWithHoles2(cell), triangles);
        for (const Polygon2& t : triangles) {
          const FT t_area = polygon_area(t);
          if (!write(t, t_area, lit)) dropped_.push_back(CGAL::abs(t_area));
        }
      }
    }
  }

  std::vector<ViewPiece> pieces;
  double dropped_area() {
    return dropped_.empty() ? 0.0 : area_3d(balanced_sum(dropped_), P_.area_scale_squared);
  }

 private:
  bool write(const Polygon2& cell, const FT& cell_area, bool lit) {
    ViewPiece piece;
    piece.face_id = face_id_;
    piece.lit = lit;
    piece.back = back_;
    piece.area = area_3d(CGAL::abs(cell_area), P_.area_scale_squared);
    for (auto v = cell.vertices_begin(); v != cell.vertices_end(); ++v) {
      piece.polygon.push_back(nearest_doubles(lift(*v, P_, fp_.axis)));
    }
    // The chart sees the face clockwise when flipped: restore the face's orientation.
    if (fp_.flipped == CGAL::is_positive(cell_area)) std::reverse(piece.polygon.begin(), piece.polygon.end());
    if (!core::clean_double_polygon(piece.polygon, fp_.axis)) return false;
    for (const glm::dvec3& p : piece.polygon) piece.image.push_back(project_to_image(frame_, p));
    pieces.push_back(std::move(piece));
    return true;
  }

  const ExactFace& P_;
  const core::FacePrep& fp_;
  const ViewFrame& frame_;
  std::size_t face_id_;
  bool back_;
  std::vector<FT> dropped_;
};

}  // namespace

ViewFrame make_view_frame(const ViewCamera& camera, const std::string& what) {
  const SourceLocation where{"", what};
  if (!finite3(camera.eye) || !finite3(camera.target) || !finite3(camera.up))
    throw InputError(where, "the camera's eye, target and up must be finite");
  if (!(camera.fov_degrees > 0.0 && camera.fov_degrees < 180.0))
    throw InputError(where, "the camera's view angle must be in (0, 180) degrees, got " +
                                std::to_string(camera.fov_degrees));
  if (camera.width < 1 || camera.height < 1)
    throw InputError(where, "the image size must be at least 1 x 1 pixels, got " + std::to_string(camera.width) +
                                " x " + std::to_string(camera.height));
  if (!std::isfinite(camera.near_distance) || camera.near_distance < 0.0)
    throw InputError(where, "the near distance must be finite and >= 0, got " + std::to_string(camera.near_distance));
  const glm::dvec3 view = camera.target - camera.eye;
  const double length = glm::length(view);
  if (!(length > 0.0) || !std::isfinite(length)) throw InputError(where, "the camera's eye and target are the same point");
  const double up_length = glm::length(camera.up);
  ViewFrame fr;
  fr.eye = camera.eye;
  fr.forward = view / length;
  if (!(up_length > 0.0) || !std::isfinite(up_length) ||
      glm::length(glm::cross(fr.forward, camera.up / up_length)) <= 1e-12)
    throw InputError(where, "the camera's up direction is zero or parallel to the view direction");
  fr.right = glm::normalize(glm::cross(fr.forward, camera.up));
  fr.up = glm::cross(fr.right, fr.forward);
  fr.width = camera.width;
  fr.height = camera.height;
  fr.focal = (camera.height / 2.0) / std::tan(camera.fov_degrees * (M_PI / 360.0));
  fr.near = camera.near_distance > 0.0 ? camera.near_distance : 1e-3 * length;
  return fr;
}

glm::dvec2 project_to_image(const ViewFrame& frame, const glm::dvec3& point, double* depth) {
  const glm::dvec3 d = point - frame.eye;
  const double z = glm::dot(d, frame.forward);
  if (depth != nullptr) *depth = z;
  return {frame.width / 2.0 + frame.focal * glm::dot(d, frame.right) / z,
          frame.height / 2.0 - frame.focal * glm::dot(d, frame.up) / z};
}

VectorView compute_vector_view(const ShadowEngine& engine, const ViewCamera& camera, const VectorViewOptions& options) {
  const core::PreparedScene ctx = shadow::engine::prepared_scene(engine);
  const Scene& scene = *ctx.scene;
  VectorView view;
  view.frame = make_view_frame(camera);
  const ViewFrame& frame = view.frame;
  const unsigned threads = runtime::resolve_threads(runtime::checked_threads(options.threads));

  const Light* light = nullptr;
  Light centre;  // an extended light's centre, a point or directional light
  if (options.light) {
    const std::size_t id = *options.light;
    if (id >= scene.lights.size())
      throw InputError({"", "light"}, "light " + std::to_string(id) + " is out of range (the scene has " +
                                          std::to_string(scene.lights.size()) + " lights)");
    light = &scene.lights[id];
    shadow::detail::check_light(*light, "", "lights[" + std::to_string(id) + "]");
    // The view splits pieces by hard shadows: an extended light lights it from its centre (an
    // area light's centroid, a disk's centre, a sun disk's central direction), as
    // FaceLighting::lit_area does (docs/vector-views.md).
    if (light->is_extended()) {
      centre = shadow::detail::centre_light(*light);
      light = &centre;
    }
    view.light_id = id;
  }

  // Which side of each face the eye is on, exactly (0: on the plane, edge-on, nothing seen).
  Light eye_light;
  eye_light.type = LightType::Point;
  eye_light.position = frame.eye;
  const ExactLight eye = to_exact_light(eye_light);
  const std::size_t n = scene.faces.size();
  std::vector<int> eye_side(n, 0);
  {
    ExactWorker w;
    w.reset(n, ctx.solids->size());
    for (std::size_t f = 0; f < n; ++f)
      if (!(*ctx.prep)[f].degenerate) eye_side[f] = CGAL::sign(plane_at_light(w.face(ctx, f), eye));
  }
  // A face of a closed convex solid (fronts outward) seen from its back, by an eye outside the
  // solid (in front of one of its faces), is hidden by the solid itself: from any of its points
  // the way to the eye runs through the solid and leaves it through another face. Such faces are
  // skipped, not computed (a city of boxes shows half of its faces from the back).
  std::vector<char> eye_outside(ctx.solids->size(), 0);
  for (std::size_t f = 0; f < n; ++f)
    if ((*ctx.solid_of)[f] >= 0 && eye_side[f] > 0) eye_outside[static_cast<std::size_t>((*ctx.solid_of)[f])] = 1;
  auto hidden_by_own_solid = [&](std::size_t f) {
    const int s = (*ctx.solid_of)[f];
    return s >= 0 && eye_side[f] < 0 && eye_outside[static_cast<std::size_t>(s)];
  };

  // The scene as the eye sees it: every face turned to show the eye its front.
  Scene seen;
  seen.meshes = scene.meshes;
  seen.faces = scene.faces;
  for (std::size_t f = 0; f < n; ++f)
    if (eye_side[f] < 0) std::reverse(seen.faces[f].vertices.begin(), seen.faces[f].vertices.end());
  const ShadowEngine seen_engine(seen, threads);
  core::PreparedScene seen_ctx = shadow::engine::prepared_scene(seen_engine);
  // No convex solid of the turned scene keeps its faces from hiding each other: a face's own
  // solid is skipped as a caster (right for a front lit from outside), but a solid's back faces
  // are hidden by its own front faces.
  const std::vector<int> no_solids(n, -1);
  seen_ctx.solid_of = &no_solids;

  std::optional<ExactLight> exact_light;
  std::optional<core::LightSpaceGrid> grid;
  if (light != nullptr) {
    exact_light = to_exact_light(*light);
    if (light->type == LightType::Directional) grid.emplace(*ctx.cull, *ctx.prep, light->to_light);
  }
  const std::vector<Affine3> sides = frustum(frame);

  struct Worker {
    ExactWorker seen, given;
    ShadowStats stats;
  };
  std::vector<Worker> workers(threads);
  for (Worker& w : workers) {
    w.seen.reset(n, seen_ctx.solids->size());
    w.given.reset(n, ctx.solids->size());
  }
  std::vector<std::vector<ViewPiece>> per_face(n);
  std::vector<double> dropped(n, 0.0);
  runtime::parallel_for(
      n, threads,
      [&](unsigned wi, std::size_t f) {
        if (eye_side[f] == 0 || (*ctx.prep)[f].degenerate || hidden_by_own_solid(f)) return;
        Worker& w = workers[wi];
        const core::FacePrep& fp = (*ctx.prep)[f];
        const ExactFace& P = w.given.face(ctx, f);
        const Polygon2 in_frustum = frustum_in_chart(P, fp, sides);
        if (in_frustum.is_empty()) return;
        // What the eye sees of the face: what a point light at the eye lights of the turned face.
        const core::FacePrep& sp = (*seen_ctx.prep)[f];
        const ExactFace& S = w.seen.face(seen_ctx, f);
        const int facing = CGAL::sign(plane_at_light(S, eye));
        const LitRegion seen_region =
            exact_lit_region(seen_ctx, w.seen, f, 0, eye, facing, eye_light, nullptr, w.stats);
        if (seen_region.kind == LitRegion::Kind::Dark) return;
        PolygonSet2 visible = seen_region.kind == LitRegion::Kind::Whole ? PolygonSet2(S.chart) : seen_region.lit;
        visible = to_other_chart(visible, S, sp.axis, fp.axis);
        visible.intersection(in_frustum);
        if (visible.is_empty()) return;

        const bool back = eye_side[f] < 0;
        PieceWriter writer(P, fp, frame, f, back);
        if (light == nullptr || back) {
          writer.add(visible, false);
        } else {
          const int light_facing = CGAL::sign(plane_at_light(P, *exact_light));
          const LitRegion lit = exact_lit_region(ctx, w.given, f, *view.light_id, *exact_light, light_facing, *light,
                                                 grid ? &*grid : nullptr, w.stats);
          if (lit.kind == LitRegion::Kind::Dark) {
            writer.add(visible, false);
          } else if (lit.kind == LitRegion::Kind::Whole) {
            writer.add(visible, true);
          } else {
            PolygonSet2 lit_part = visible;
            lit_part.intersection(lit.lit);
            PolygonSet2 dark_part = visible;
            dark_part.difference(lit.lit);
            writer.add(lit_part, true);
            writer.add(dark_part, false);
          }
        }
        per_face[f] = std::move(writer.pieces);
        dropped[f] = writer.dropped_area();
      },
      {});

  for (std::size_t f = 0; f < n; ++f) {
    for (ViewPiece& p : per_face[f]) view.pieces.push_back(std::move(p));
    view.dropped_area += dropped[f];
  }
  return view;
}

}  // namespace shadow
