// SPDX-License-Identifier: GPL-3.0-or-later
// The visible fraction of an extended light from one point, and its irradiance
// (arealight/light_visibility_steps.hpp): the faces that can hide the light culled and cast
// centrally from the point onto the light's plane, their exact union, and its measure on the
// light's polygon or circle (see light_visibility.cpp).
#include "arealight/light_visibility.hpp"
#include "arealight/light_visibility_steps.hpp"

#include "exact/regions.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <limits>
#include <vector>

namespace shadow::arealight {
namespace {

// ---- measuring on a circle -----------------------------------------------------------------

/// Weight of a region inside the circle of radius R around the origin: its area, or the solid
/// angle it subtends from the point at unit distance above the origin (the sun's gnomonic
/// plane). Sum over a region's boundary edges of edge_measure gives the measure of the region's
/// part inside the circle: inside the circle an edge contributes its triangle with the origin
/// (area, or Van Oosterom and Strackee's solid angle of that triangle); outside, the arc it
/// subtends, G(R) times its angle, G(R) = R^2/2 or 1 - 1/sqrt(1 + R^2).
struct CircleMeasure {
  double R = 1;
  bool solid_angle = false;
  double g_of_r = 0;
  double total = 0;
  explicit CircleMeasure(double radius, bool solid) : R(radius), solid_angle(solid) {
    if (solid) {
      const double root = std::sqrt(1.0 + R * R);
      g_of_r = R * R / (root * (1.0 + root));  // 1 - 1/sqrt(1 + R^2) without cancellation
    } else {
      g_of_r = 0.5 * R * R;
    }
    total = 2.0 * kPi * g_of_r;
  }
  static double angle(double ax, double ay, double bx, double by) {
    return std::atan2(ax * by - ay * bx, ax * bx + ay * by);
  }
  double inside(double ax, double ay, double bx, double by) const {
    const double cross = ax * by - ay * bx;
    if (cross == 0.0) return 0.0;
    if (!solid_angle) return 0.5 * cross;
    // A = (0, 0, 1), B = (a, 1), C = (b, 1): tan(omega / 2) = det / denominator.
    const double la = std::sqrt(ax * ax + ay * ay + 1.0), lb = std::sqrt(bx * bx + by * by + 1.0);
    const double denominator = la * lb + (ax * bx + ay * by + 1.0) + lb + la;
    return 2.0 * std::atan2(cross, denominator);
  }
  double outside(double ax, double ay, double bx, double by) const { return g_of_r * angle(ax, ay, bx, by); }
  double edge(double ax, double ay, double bx, double by) const {
    const double dx = bx - ax, dy = by - ay;
    const double dd = dx * dx + dy * dy;
    if (dd == 0.0) return 0.0;
    const double ad = ax * dx + ay * dy;
    const double aa = ax * ax + ay * ay;
    const double disc = ad * ad - dd * (aa - R * R);
    if (!(disc > 0.0)) return outside(ax, ay, bx, by);
    const double root = std::sqrt(disc);
    double t1 = (-ad - root) / dd, t2 = (-ad + root) / dd;
    t1 = std::clamp(t1, 0.0, 1.0);
    t2 = std::clamp(t2, 0.0, 1.0);
    const double px = ax + t1 * dx, py = ay + t1 * dy, qx = ax + t2 * dx, qy = ay + t2 * dy;
    double sum = 0.0;
    if (t1 > 0.0) sum += outside(ax, ay, px, py);
    if (t2 > t1) sum += inside(px, py, qx, qy);
    if (t2 < 1.0) sum += outside(qx, qy, bx, by);
    return sum;
  }
};

glm::dvec3 to_dvec(const Point3& p) { return {CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())}; }

}  // namespace

PointResult Evaluator::evaluate(PointWorker& w, const SurfacePoint& sp, const glm::dvec3& toward) const {
  PointResult none;
  const std::size_t f = sp.face_id;
  if (faces_.prep[f].degenerate) return none;
  if (!w.target) {
    w.target = make_target(plan_);
    w.faces.resize(scene_.faces.size());
  }
  Target& t = *w.target;
  // A fragment vertex is a rounded double: one on a contact line may lie a rounding error on
  // the wrong side of the face through it. Where a face passes within 64 units in the last
  // place of the point's coordinates but not exactly through it, the value is taken at the
  // point moved by `toward` (into the fragment by 1e-6 of the shorter adjacent edge, at least
  // 1,000 times that distance, at most half the edge), exactly.
  if (toward != glm::dvec3(0.0) && finite3(toward)) {
    const double eps = rounding_eps(sp.position);
    if (eps > 0.0 && glm::length(toward) > 10.0 * eps && near_contact(w, sp, eps)) {
      SurfacePoint moved = sp;
      moved.position += toward;
      return evaluate(w, moved, glm::dvec3(0.0));
    }
  }
  const Point3 x = to_exact(sp.position);
  if (t.shape == Shape::Sun) place_sun(t, x);
  const FT h = t.n * (x - CGAL::ORIGIN) + t.offset;  // > 0: in front of the light
  if (CGAL::sign(h) != CGAL::POSITIVE) {
    // A fragment vertex exactly in the light's plane (a wall cell's top edge at the height of
    // a ceiling luminaire) takes the value of the fragment's side, a hair inside it.
    if (CGAL::sign(h) == CGAL::ZERO && toward != glm::dvec3(0.0) && finite3(toward)) {
      SurfacePoint moved = sp;
      moved.position += toward;
      return evaluate(w, moved, glm::dvec3(0.0));
    }
    return none;
  }
  const ExactFace& receiver = w.face(scene_, faces_, f);
  // The side to take the limit from, projected exactly onto the receiver's plane.
  const bool has_toward = toward != glm::dvec3(0.0) && finite3(toward);
  Vector3 d(0, 0, 0);
  if (has_toward) {
    const Vector3 raw(toward.x, toward.y, toward.z);
    d = raw - receiver.normal * ((raw * receiver.normal) / receiver.normal.squared_length());
  }

  // The light's part behind the receiver's plane (n_R . (y - x) < 0) is not seen: g(u, v) >= 0
  // keeps the part behind, as an affine function of (u, v) on the plane.
  const Point3 o = from_uv(t, Point2(0, 0)), pu = from_uv(t, Point2(1, 0)), pv = from_uv(t, Point2(0, 1));
  const FT g0 = -(receiver.normal * (o - x));
  const FT gu = -(receiver.normal * (pu - o)), gv = -(receiver.normal * (pv - o));
  bool all_behind = true, any_behind = false;
  for (const Point3& y : t.hull3) {
    const CGAL::Sign s = CGAL::sign(receiver.normal * (y - x));
    all_behind = all_behind && s != CGAL::POSITIVE;
    any_behind = any_behind || s == CGAL::NEGATIVE;
  }
  if (all_behind) return none;

  std::vector<Polygon2> hidden;
  if (any_behind) {
    Polygon2 behind = clip2(t.hull, gu, gv, g0);
    if (behind.size() >= 3 && CGAL::sign(polygon_area(behind)) == CGAL::POSITIVE) hidden.push_back(std::move(behind));
  }
  cast_hidden(w, sp, t, x, h, has_toward, d, o, pu, pv, hidden);
  if (t.shape == Shape::Polygon) return measure_polygon(t, hidden, sp.position, receiver);
  return measure_circle(t, hidden, sp.position, receiver);
}

void Evaluator::cast_hidden(PointWorker& w, const SurfacePoint& sp, const Target& t, const Point3& x, const FT& h, bool has_toward,
                 const Vector3& d, const Point3& o, const Point3& pu, const Point3& pv,
                 std::vector<Polygon2>& hidden) const {
  const std::size_t f = sp.face_id;
  // The pyramid from x over the hull, and (planar lights) the light's plane: what can hide.
  std::vector<Affine3> planes;
  const std::size_t m = t.hull3.size();
  for (std::size_t a = 0; a < m; ++a) {
    const Point3& p = t.hull3[a];
    const Point3& q = t.hull3[(a + 1) % m];
    const Point3& r = t.hull3[(a + 2) % m];
    Vector3 normal = CGAL::cross_product(p - x, q - x);
    if (CGAL::sign(normal * (r - x)) == CGAL::NEGATIVE) normal = -normal;
    planes.push_back({normal, -(normal * (x - CGAL::ORIGIN))});
  }
  if (t.shape != Shape::Sun) planes.push_back({t.n, t.offset});  // between the light's plane and x

  // Bounding box of the pyramid (truncated by the scene for the sun), in doubles with a margin.
  std::array<double, 6> box = frustum_box(t, sp.position);
  // The pyramid's planes in doubles, for a conservative first cull of each face's box: a box
  // whose corners are all outside one plane by more than rounding could move them is culled.
  const glm::dvec3& xd = sp.position;
  std::vector<std::pair<glm::dvec3, double>> dplanes;  // (normal, tolerance)
  {
    const double size = 1.0 + std::max({std::abs(xd.x), std::abs(xd.y), std::abs(xd.z)});
    for (const Affine3& pl : planes) {
      // Planes through x only (the light's own plane is left to the exact test). The normal is
      // rounded from its exact value: a lazy value's approximation could be coarse.
      if (!CGAL::is_zero(pl(x))) continue;
      const glm::dvec3 m(CGAL::to_double(CGAL::exact(pl.a.x())), CGAL::to_double(CGAL::exact(pl.a.y())),
                         CGAL::to_double(CGAL::exact(pl.a.z())));
      dplanes.emplace_back(m, 1e-9 * glm::length(m) * size);
    }
  }
  auto box_outside = [&](const std::array<double, 6>& b) {
    for (const auto& [m, tol] : dplanes) {
      // The corner farthest along m: if even it is outside, the whole box is.
      const glm::dvec3 corner(m.x > 0 ? b[3] : b[0], m.y > 0 ? b[4] : b[1], m.z > 0 ? b[5] : b[2]);
      if (glm::dot(m, corner - xd) < -tol * (1.0 + glm::length(corner - xd))) return true;
    }
    return false;
  };

  for (std::size_t o_id = 0; o_id < scene_.faces.size(); ++o_id) {
    if (o_id == f || faces_.prep[o_id].degenerate) continue;
    const std::array<double, 6>& b = faces_.box[o_id];
    if (b[0] > box[3] || b[3] < box[0] || b[1] > box[4] || b[4] < box[1] || b[2] > box[5] || b[5] < box[2]) continue;
    if (box_outside(b)) continue;
    const ExactFace& face = w.face(scene_, faces_, o_id);
    // A face through x projects onto a line: it hides nothing of measure from x itself, but
    // from points beside x on the side `toward` it hides a wedge (add_contact). One in the
    // light's own plane does not stand between.
    if (CGAL::is_zero(face.normal * (x - CGAL::ORIGIN) + face.offset)) {
      if (has_toward) add_contact(t, face, faces_.prep[o_id], x, d, o, pu, pv, hidden);
      continue;
    }
    bool outside = false;
    for (const Affine3& pl : planes) {
      bool all_out = true;
      for (const Point3& p : face.vertices)
        if (CGAL::sign(pl(p)) != CGAL::NEGATIVE) {
          all_out = false;
          break;
        }
      if (all_out) {
        outside = true;
        break;
      }
    }
    if (outside) continue;
    if (t.shape != Shape::Sun) {
      bool in_plane = true;
      for (const Point3& p : face.vertices)
        if (!CGAL::is_zero(planes.back()(p))) {
          in_plane = false;
          break;
        }
      if (in_plane) continue;
    }
    for (const std::vector<int>& piece : faces_.prep[o_id].convex_pieces) {
      std::vector<Point3> poly;
      poly.reserve(piece.size());
      for (int v : piece) poly.push_back(face.vertices[static_cast<std::size_t>(v)]);
      for (const Affine3& pl : planes) {
        poly = clip(poly, pl);
        if (poly.size() < 3) break;
      }
      if (poly.size() < 3) continue;
      Polygon2 image;
      for (const Point3& q : poly) {
        const FT sq = t.n * (q - CGAL::ORIGIN) + t.offset;
        const FT tt = h / (h - sq);
        image.push_back(to_uv(t, x + (q - x) * tt));
      }
      const CGAL::Sign orientation = CGAL::sign(polygon_area(image));
      if (orientation == CGAL::ZERO) continue;
      if (orientation == CGAL::NEGATIVE) image.reverse_orientation();
      hidden.push_back(std::move(image));
    }
  }
}

PointResult Evaluator::measure_polygon(const Target& t, const std::vector<Polygon2>& hidden, const glm::dvec3& x,
                            const ExactFace& receiver) const {
  PointResult result;
  PolygonSet2 set;
  if (!hidden.empty()) {
    set.join(hidden.begin(), hidden.end());
    if (!t.light_convex) set.intersection(t.light);
  }
  std::vector<PolygonWithHoles2> regions;
  set.polygons_with_holes(std::back_inserter(regions));
  std::vector<FT> terms;
  for (const PolygonWithHoles2& r : regions) terms.push_back(region_area(r));
  const FT hidden_area = balanced_sum(terms);
  const FT fraction = (t.light_area - hidden_area) / t.light_area;
  result.visibility = std::clamp(round_to_double(fraction), 0.0, 1.0);
  if (want_irradiance_ && result.visibility > 0.0) {
    PolygonSet2 visible(t.light);
    if (!regions.empty()) visible.difference(set);
    result.irradiance = contour_irradiance(t, visible, x, receiver);
  }
  return result;
}

PointResult Evaluator::measure_circle(const Target& t, const std::vector<Polygon2>& hidden, const glm::dvec3& x,
                           const ExactFace& receiver) const {
  PointResult result;
  // Disk or sun: the hidden union's part inside the circle, measured edge by edge.
  const CircleMeasure measure(t.radius, t.shape == Shape::Sun);
  double hidden_measure = 0.0;
  PolygonSet2 set;
  if (!hidden.empty()) {
    set.join(hidden.begin(), hidden.end());
    std::vector<PolygonWithHoles2> regions;
    set.polygons_with_holes(std::back_inserter(regions));
    auto add = [&](const Polygon2& boundary) {
      std::vector<std::array<double, 2>> p;
      for (auto v = boundary.vertices_begin(); v != boundary.vertices_end(); ++v)
        p.push_back({CGAL::to_double(v->x()) * t.scale_u, CGAL::to_double(v->y()) * t.scale_v});
      for (std::size_t a = 0; a < p.size(); ++a) {
        const auto& u = p[a];
        const auto& v = p[(a + 1) % p.size()];
        hidden_measure += measure.edge(u[0], u[1], v[0], v[1]);
      }
    };
    // The union lies in the square around the circle: all of the square hidden is all of
    // the light hidden, exactly.
    std::vector<FT> terms;
    for (const PolygonWithHoles2& r : regions) terms.push_back(region_area(r));
    if (balanced_sum(terms) == polygon_area(t.hull.begin(), t.hull.end())) return result;
    for (const PolygonWithHoles2& r : regions) {
      add(r.outer_boundary());
      for (auto hole = r.holes_begin(); hole != r.holes_end(); ++hole) add(*hole);
    }
  }
  result.visibility = std::clamp(1.0 - hidden_measure / measure.total, 0.0, 1.0);
  if (want_irradiance_ && result.visibility > 0.0) {
    if (t.shape == Shape::Sun) {
      const double c = glm::dot(glm::normalize(to_dvec(Point3(0, 0, 0) + receiver.normal)), glm::normalize(plan_.normal));
      result.irradiance = light_.intensity * result.visibility * std::max(0.0, c);
    } else {
      // The disk's irradiance: the inscribed regular polygon's visible part.
      Polygon2 disk;
      for (int k = 0; k < kDiskIrradianceSides; ++k) {
        const double a = 2.0 * kPi * k / kDiskIrradianceSides;
        disk.push_back(Point2(t.radius * std::cos(a) / t.scale_u, t.radius * std::sin(a) / t.scale_v));
      }
      PolygonSet2 visible(disk);
      if (!hidden.empty()) visible.difference(set);
      result.irradiance = contour_irradiance(t, visible, x, receiver);
    }
  }
  return result;
}

bool Evaluator::near_contact(PointWorker& w, const SurfacePoint& sp, double eps) const {
  const glm::dvec3& p = sp.position;
  const Point3 x = to_exact(p);
  for (std::size_t o = 0; o < scene_.faces.size(); ++o) {
    if (o == sp.face_id || faces_.prep[o].degenerate) continue;
    const std::array<double, 6>& b = faces_.box[o];
    if (p.x < b[0] - eps || p.x > b[3] + eps || p.y < b[1] - eps || p.y > b[4] + eps || p.z < b[2] - eps ||
        p.z > b[5] + eps)
      continue;
    const ExactFace& face = w.face(scene_, faces_, o);
    const FT s = face.normal * (x - CGAL::ORIGIN) + face.offset;
    if (CGAL::is_zero(s)) continue;
    const double n = std::sqrt(CGAL::to_double(face.normal.squared_length()));
    if (std::abs(CGAL::to_double(s)) < eps * n) return true;
  }
  return false;
}

void Evaluator::add_contact(const Target& t, const ExactFace& face, const core::FacePrep& prep, const Point3& x,
                        const Vector3& d, const Point3& o, const Point3& pu, const Point3& pv,
                        std::vector<Polygon2>& hidden) {
  const Vector3& nf = face.normal;
  const FT nd = nf * d;
  const CGAL::Sign side = CGAL::sign(nd);
  if (side == CGAL::ZERO) return;  // approaching along the face's plane: it stays a line
  const int k = prep.axis;
  const Point2 xc = to_chart(x, k);
  // A functional psi(z) >= 0 on z = y - x, as an affine function of (u, v).
  auto clip_by = [&](Polygon2& poly, const Vector3& psi) {
    const FT c0 = psi * (o - x), cu = psi * (pu - o), cv = psi * (pv - o);
    std::vector<Point2> box(poly.vertices_begin(), poly.vertices_end());
    poly = clip2(box, cu, cv, c0);
  };
  for (const std::vector<int>& piece : prep.convex_pieces) {
    const std::size_t m = piece.size();
    std::vector<Vector3> cuts;
    bool inside = true;
    for (std::size_t e = 0; e < m && inside; ++e) {
      const Point3& a = face.vertices[static_cast<std::size_t>(piece[e])];
      const Point3& b = face.vertices[static_cast<std::size_t>(piece[(e + 1) % m])];
      const CGAL::Orientation turn = CGAL::orientation(to_chart(a, k), to_chart(b, k), xc);
      if (turn == CGAL::RIGHT_TURN) inside = false;
      if (turn != CGAL::COLLINEAR) continue;
      // The edge's line holds x: the tangent cone is on the piece's side of it.
      Vector3 w = CGAL::cross_product(nf, b - a);
      std::vector<FT> sx, sy, sz;  // m times the piece's centroid, relative to a
      for (int v : piece) {
        const Vector3 r = face.vertices[static_cast<std::size_t>(v)] - a;
        sx.push_back(r.x());
        sy.push_back(r.y());
        sz.push_back(r.z());
      }
      if (CGAL::sign(w * Vector3(balanced_sum(sx), balanced_sum(sy), balanced_sum(sz))) == CGAL::NEGATIVE) w = -w;
      // phi(z) = (n.d)(w.z) - (w.d)(n.z), kept with the sign of n.d.
      Vector3 phi = w * nd - nf * (w * d);
      if (side == CGAL::NEGATIVE) phi = -phi;
      cuts.push_back(phi);
    }
    if (!inside) continue;
    Polygon2 poly(t.hull.begin(), t.hull.end());
    clip_by(poly, side == CGAL::POSITIVE ? -nf : nf);  // the -d side of the face's plane
    for (const Vector3& phi : cuts) {
      if (poly.size() < 3) break;
      clip_by(poly, phi);
    }
    if (poly.size() >= 3 && CGAL::sign(polygon_area(poly)) == CGAL::POSITIVE) hidden.push_back(std::move(poly));
  }
}

std::array<double, 6> Evaluator::frustum_box(const Target& t, const glm::dvec3& x) const {
  std::array<double, 6> b{x.x, x.y, x.z, x.x, x.y, x.z};
  auto add = [&](const glm::dvec3& p) {
    for (int k = 0; k < 3; ++k) b[k] = std::min(b[k], p[k]), b[k + 3] = std::max(b[k + 3], p[k]);
  };
  if (t.shape == Shape::Sun) {
    // Far enough along the pyramid's edges to leave the scene's box.
    const auto& s = scene_box_;
    double reach = 0.0;
    for (int k = 0; k < 3; ++k) reach += std::max(std::abs(s[k] - x[k]), std::abs(s[k + 3] - x[k]));
    const double s_len = glm::length(plan_.normal);
    const double scale = std::isfinite(reach) ? 2.0 * reach / s_len + 1.0 : 1.0;
    for (const Point3& p : t.hull3) add(x + (to_dvec(p) - x) * scale);
  } else {
    for (const Point3& p : t.hull3) add(to_dvec(p));
  }
  for (int k = 0; k < 3; ++k) {
    const double m = 1e-9 * (std::abs(b[k]) + std::abs(b[k + 3]) + (b[k + 3] - b[k])) + 1e-300;
    b[k] -= m;
    b[k + 3] += m;
  }
  return b;
}

double Evaluator::contour_irradiance(const Target& t, const PolygonSet2& visible, const glm::dvec3& x,
                          const ExactFace& receiver) const {
  const glm::dvec3 n = glm::normalize(to_dvec(Point3(0, 0, 0) + receiver.normal));
  // Counter-clockwise in (u, v) is counter-clockwise seen from the front for the frames; for a
  // chart, when the plane's normal has a positive dropped component.
  double orientation = 1.0;
  if (t.shape == Shape::Polygon && CGAL::sign(t.n[t.axis]) == CGAL::NEGATIVE) orientation = -1.0;
  std::vector<PolygonWithHoles2> regions;
  visible.polygons_with_holes(std::back_inserter(regions));
  double sum = 0.0;
  auto add = [&](const Polygon2& boundary) {
    std::vector<glm::dvec3> r;
    for (auto v = boundary.vertices_begin(); v != boundary.vertices_end(); ++v) r.push_back(to_dvec(from_uv(t, *v)) - x);
    sum += shadow::detail::lambert_contour(r, n);
  };
  for (const PolygonWithHoles2& region : regions) {
    add(region.outer_boundary());
    for (auto hole = region.holes_begin(); hole != region.holes_end(); ++hole) add(*hole);
  }
  // Counter-clockwise seen from the front (from x) gives r_a x r_b pointing away from the
  // receiver's side: the sum is negative for a light in front.
  return std::max(0.0, -0.5 * orientation * sum * light_.intensity);
}

}  // namespace shadow::arealight

// ---- Lambert's contour integral ----------------------------------------------------------

double shadow::detail::lambert_contour(const std::vector<glm::dvec3>& r, const glm::dvec3& n) {
  double sum = 0.0;
  for (std::size_t a = 0; a < r.size(); ++a) {
    const glm::dvec3& p = r[a];
    const glm::dvec3& q = r[(a + 1) % r.size()];
    const glm::dvec3 cross = glm::cross(p, q);
    const double len = glm::length(cross);
    if (!(len > 0.0)) continue;
    const double gamma = std::atan2(len, glm::dot(p, q));
    sum += gamma * glm::dot(cross, n) / len;
  }
  return sum;
}
