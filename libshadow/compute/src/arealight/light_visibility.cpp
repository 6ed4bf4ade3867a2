// SPDX-License-Identifier: GPL-3.0-or-later
// The visible fraction of an extended light from points, and the irradiance it delivers
// (docs/area-light-visibility.md). From a point x the light is a receiver and x a point light:
// every face that can stand between x and the light is clipped exactly to the pyramid from x
// over the light (its convex hull; a disk's or the sun's circumscribed square), projected
// centrally from x onto the light's plane, and the projections are united exactly (CGAL, as in
// exact/). A polygonal light's hidden area is then exact; a disk's is the area of that union
// inside the circle, summed edge by edge in closed form (doubles).
#include <shadow/area_lights.hpp>

#include "arealight/light_visibility.hpp"
#include "arealight/light_visibility_steps.hpp"
#include "core/face_prep.hpp"
#include "runtime/parallel.hpp"
#include "exact/exact_faces.hpp"
#include "exact/kernel.hpp"
#include "exact/regions.hpp"

#include <shadow/error.hpp>

#include <CGAL/convex_hull_2.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>

namespace shadow::arealight {
namespace {

std::string light_place(const std::string& what) { return "light." + what; }

/// `v` scaled by a power of two so that its largest component lies in [1, 2), where it is outside
/// [2^-20, 2^21) (left as it is inside, so ordinary inputs keep their exact values). Only the
/// direction of a disk's normal or the sun's to_light matters; scaling keeps it exactly (up to
/// components below 2^-1000 of the largest, which underflow), and the frames built from it
/// (squared lengths ~|v|^4) stay far from overflow and underflow.
glm::dvec3 tame_direction(const glm::dvec3& v) {
  const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  const int e = std::ilogb(m);
  if (e >= -20 && e <= 20) return v;
  return {std::ldexp(v.x, -e), std::ldexp(v.y, -e), std::ldexp(v.z, -e)};
}

}  // namespace

double rounding_eps(const glm::dvec3& p) {
  const double size = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  if (!(size > 0.0)) return 0.0;
  return std::ldexp(64.0, std::ilogb(size) - std::numeric_limits<double>::digits + 1);
}

LightPlan plan_light(const Light& light) {
  if (!light.is_extended())
    throw InputError({"", "light.type"}, "light_visibility needs an extended light (area, disk, or directional "
                                         "with angular_diameter > 0)");
  if (!std::isfinite(light.intensity) || light.intensity < 0)
    throw InputError({"", light_place("intensity")}, "intensity must be finite and >= 0");
  LightPlan plan;
  if (light.type == LightType::Area) {
    plan.shape = Shape::Polygon;
    for (const glm::dvec3& v : light.polygon) {
      if (!finite3(v)) throw InputError({"", light_place("polygon")}, "a vertex is not finite");
      if (plan.polygon.empty() || plan.polygon.back() != v) plan.polygon.push_back(v);
    }
    while (plan.polygon.size() > 1 && plan.polygon.front() == plan.polygon.back()) plan.polygon.pop_back();
    if (plan.polygon.size() < 3)
      throw InputError({"", light_place("polygon")}, "an area light needs at least 3 distinct vertices");
    plan.prep = prepare_face(plan.polygon);
    if (plan.prep.degenerate) throw InputError({"", light_place("polygon")}, "the area light has zero area");
    const ExactFace face = make_exact_face(plan.polygon, plan.prep);
    if (!face.chart.is_simple())
      throw InputError({"", light_place("polygon")}, "the area light's polygon is not simple");
  } else if (light.type == LightType::Disk) {
    plan.shape = Shape::Disk;
    if (!finite3(light.position)) throw InputError({"", light_place("position")}, "position is not finite");
    if (!finite3(light.normal) || light.normal == glm::dvec3(0.0))
      throw InputError({"", light_place("normal")}, "normal must be finite and non-zero");
    if (!(std::isfinite(light.radius) && light.radius > 0.0))
      throw InputError({"", light_place("radius")}, "radius must be finite and > 0");
    plan.centre = light.position;
    plan.normal = tame_direction(light.normal);
    plan.radius = light.radius;
  } else {
    plan.shape = Shape::Sun;
    if (!finite3(light.to_light) || light.to_light == glm::dvec3(0.0))
      throw InputError({"", light_place("to_light")}, "direction must be finite and non-zero");
    if (!(std::isfinite(light.angular_diameter) && light.angular_diameter > 0.0 && light.angular_diameter <= 170.0))
      throw InputError({"", light_place("angular_diameter")}, "angular_diameter must be in (0, 170] degrees");
    plan.normal = tame_direction(light.to_light);
    plan.radius = std::tan(0.5 * light.angular_diameter * kPi / 180.0);
  }
  return plan;
}

Point2 to_uv(const Target& t, const Point3& y) {
  if (t.shape == Shape::Polygon) return to_chart(y, t.axis);
  const Vector3 d = y - t.c;
  return Point2(d * t.e1, d * t.e2);
}

Point3 from_uv(const Target& t, const Point2& p) {
  if (t.shape == Shape::Polygon) {
    const int k = t.axis, i = core::chart_i(k), j = core::chart_j(k);
    const FT xk = -(t.offset + t.n[i] * p.x() + t.n[j] * p.y()) / t.n[k];
    FT xyz[3];
    xyz[i] = p.x();
    xyz[j] = p.y();
    xyz[k] = xk;
    return Point3(xyz[0], xyz[1], xyz[2]);
  }
  return t.c + t.e1 * (p.x() / t.e1sq) + t.e2 * (p.y() / t.e2sq);
}

namespace {

/// e1, e2 orthogonal to n, rational, e1 x e2 = |e1|^2 n.
void make_frame(Target& t) {
  const double ax = std::abs(CGAL::to_double(t.n.x())), ay = std::abs(CGAL::to_double(t.n.y())),
               az = std::abs(CGAL::to_double(t.n.z()));
  Vector3 axis = ax <= ay && ax <= az ? Vector3(1, 0, 0) : (ay <= az ? Vector3(0, 1, 0) : Vector3(0, 0, 1));
  t.e1 = CGAL::cross_product(t.n, axis);
  t.e2 = CGAL::cross_product(t.n, t.e1);
  t.e1sq = t.e1.squared_length();
  t.e2sq = t.e2.squared_length();
}

/// Square [-bu, bu] x [-bv, bv] in (u, v) around the circle of radius `radius` in (U, V), with a
/// margin, so that the pyramid over it holds the whole disk.
void make_square(Target& t) {
  const double bu = t.radius * (1.0 + 1e-6) / t.scale_u, bv = t.radius * (1.0 + 1e-6) / t.scale_v;
  t.hull = {Point2(-bu, -bv), Point2(bu, -bv), Point2(bu, bv), Point2(-bu, bv)};
}

}  // namespace

Target make_target(const LightPlan& plan) {
  Target t;
  t.shape = plan.shape;
  if (plan.shape == Shape::Polygon) {
    const ExactFace face = make_exact_face(plan.polygon, plan.prep);
    t.n = face.normal;
    t.offset = face.offset;
    t.axis = plan.prep.axis;
    t.light = face.chart;
    t.light_convex = t.light.is_convex();
    t.light_area = polygon_area(t.light);
    CGAL::convex_hull_2(t.light.vertices_begin(), t.light.vertices_end(), std::back_inserter(t.hull));
    for (const Point2& p : t.hull) t.hull3.push_back(from_uv(t, p));
  } else if (plan.shape == Shape::Disk) {
    t.n = Vector3(plan.normal.x, plan.normal.y, plan.normal.z);
    t.c = to_exact(plan.centre);
    t.offset = -(t.n * (t.c - CGAL::ORIGIN));
    make_frame(t);
    t.scale_u = 1.0 / std::sqrt(CGAL::to_double(t.e1sq));
    t.scale_v = 1.0 / std::sqrt(CGAL::to_double(t.e2sq));
    t.radius = plan.radius;
    make_square(t);
    for (const Point2& p : t.hull) t.hull3.push_back(from_uv(t, p));
  } else {
    // The sun: the plane at distance |s| from the point toward the sun, facing the point; the
    // central projection onto it is the gnomonic projection (scaled by |s|).
    const Vector3 s(plan.normal.x, plan.normal.y, plan.normal.z);
    t.n = -s;
    make_frame(t);
    const double s_len = glm::length(plan.normal);
    // (u, v) / (|e| |s|) are the coordinates on the tangent plane at unit distance.
    t.scale_u = 1.0 / (std::sqrt(CGAL::to_double(t.e1sq)) * s_len);
    t.scale_v = 1.0 / (std::sqrt(CGAL::to_double(t.e2sq)) * s_len);
    t.radius = plan.radius;
    make_square(t);
  }
  return t;
}

/// Per point for the sun: the plane through x + s.
void place_sun(Target& t, const Point3& x) {
  t.c = x - t.n;  // n = -s
  t.offset = -(t.n * (t.c - CGAL::ORIGIN));
  t.hull3.clear();
  for (const Point2& p : t.hull) t.hull3.push_back(from_uv(t, p));
}

std::vector<Point3> clip(const std::vector<Point3>& polygon, const Affine3& f) {
  std::vector<Point3> out;
  const std::size_t n = polygon.size();
  if (n == 0) return out;
  std::vector<FT> value;
  std::vector<CGAL::Sign> sign;
  value.reserve(n);
  sign.reserve(n);
  bool all_in = true, all_out = true;
  for (const Point3& p : polygon) {
    value.push_back(f(p));
    sign.push_back(CGAL::sign(value.back()));
    all_in = all_in && sign.back() != CGAL::NEGATIVE;
    all_out = all_out && sign.back() == CGAL::NEGATIVE;
  }
  if (all_in) return polygon;
  if (all_out) return out;
  for (std::size_t a = 0; a < n; ++a) {
    const std::size_t b = (a + 1) % n;
    if (sign[a] != CGAL::NEGATIVE) out.push_back(polygon[a]);
    if ((sign[a] == CGAL::POSITIVE && sign[b] == CGAL::NEGATIVE) ||
        (sign[a] == CGAL::NEGATIVE && sign[b] == CGAL::POSITIVE))
      out.push_back(polygon[a] + (polygon[b] - polygon[a]) * (value[a] / (value[a] - value[b])));
  }
  return out;
}

Polygon2 clip2(const std::vector<Point2>& box, const FT& a, const FT& b, const FT& c) {
  Polygon2 out;
  const std::size_t n = box.size();
  auto f = [&](const Point2& p) { return a * p.x() + b * p.y() + c; };
  for (std::size_t i = 0; i < n; ++i) {
    const Point2& p = box[i];
    const Point2& q = box[(i + 1) % n];
    const FT fp = f(p), fq = f(q);
    const CGAL::Sign sp = CGAL::sign(fp), sq = CGAL::sign(fq);
    if (sp != CGAL::NEGATIVE) out.push_back(p);
    if ((sp == CGAL::POSITIVE && sq == CGAL::NEGATIVE) || (sp == CGAL::NEGATIVE && sq == CGAL::POSITIVE))
      out.push_back(p + (q - p) * (fp / (fp - fq)));
  }
  return out;
}

SceneFaces prepare_scene(const Scene& scene) {
  SceneFaces s;
  s.prep.resize(scene.faces.size());
  s.box.resize(scene.faces.size());
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const Face& face = scene.faces[f];
    if (face.degenerate || face.vertices.size() < 3) {
      s.prep[f].degenerate = true;
      continue;
    }
    s.prep[f] = prepare_face(face.vertices);
    if (s.prep[f].degenerate) continue;
    std::array<double, 6> b{};
    for (int k = 0; k < 3; ++k) {
      b[k] = std::numeric_limits<double>::infinity();
      b[k + 3] = -std::numeric_limits<double>::infinity();
    }
    if (s.prep[f].exactly_planar) {
      for (const glm::dvec3& v : face.vertices)
        for (int k = 0; k < 3; ++k) b[k] = std::min(b[k], v[k]), b[k + 3] = std::max(b[k + 3], v[k]);
    } else {
      const ExactFace ef = make_exact_face(face.vertices, s.prep[f]);
      for (const Point3& p : ef.vertices)
        for (int k = 0; k < 3; ++k) {
          const double d = CGAL::to_double(p[k]);
          b[k] = std::min(b[k], d);
          b[k + 3] = std::max(b[k + 3], d);
        }
    }
    for (int k = 0; k < 3; ++k) {
      const double m = 1e-9 * (std::abs(b[k]) + std::abs(b[k + 3]) + (b[k + 3] - b[k])) + 1e-300;
      b[k] -= m;
      b[k + 3] += m;
    }
    s.box[f] = b;
  }
  return s;
}

}  // namespace shadow::arealight

namespace shadow {

using namespace arealight;

namespace detail {

struct LightQuery::Impl {
  const Scene& scene;
  SceneFaces faces;
  std::vector<PointWorker> workers;
  Light light;
  LightPlan plan;
  std::optional<Evaluator> evaluator;
  Impl(const Scene& s, unsigned n) : scene(s), faces(prepare_scene(s)), workers(std::max(1u, n)) {}
};

LightQuery::LightQuery(const Scene& scene, unsigned workers) : impl_(std::make_unique<Impl>(scene, workers)) {}
LightQuery::~LightQuery() = default;

void LightQuery::set_light(const Light& light, bool irradiance) {
  Impl& q = *impl_;
  q.evaluator.reset();
  q.plan = plan_light(light);
  q.light = light;
  for (PointWorker& w : q.workers) w.target.reset();  // the exact faces stay: they do not depend on the light
  q.evaluator.emplace(q.scene, q.light, q.plan, q.faces, irradiance);
}

std::pair<double, double> LightQuery::evaluate(unsigned worker, const SurfacePoint& point,
                                               const glm::dvec3& toward) const {
  const PointResult r = impl_->evaluator->evaluate(impl_->workers[worker], point, toward);
  return {r.visibility, r.irradiance};
}

unsigned LightQuery::workers() const { return static_cast<unsigned>(impl_->workers.size()); }

std::vector<std::pair<double, double>> light_visibility_irradiance(const Scene& scene, const Light& light,
                                                                   const std::vector<SurfacePoint>& points,
                                                                   unsigned threads, bool irradiance,
                                                                   const std::vector<glm::dvec3>& toward) {
  plan_light(light);  // an unusable light is an error before the points are
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (points[i].face_id >= scene.faces.size())
      throw InputError({"", "points[" + std::to_string(i) + "].face_id"},
                       "no face " + std::to_string(points[i].face_id) + ": the scene has " +
                           std::to_string(scene.faces.size()) + " faces");
    if (!finite3(points[i].position))
      throw InputError({"", "points[" + std::to_string(i) + "].position"}, "position is not finite");
  }
  std::vector<std::pair<double, double>> out(points.size(), {0.0, 0.0});
  if (points.empty()) return out;
  const unsigned n = runtime::resolve_threads(runtime::checked_threads(threads));
  LightQuery query(scene, std::max(1u, std::min<unsigned>(n, static_cast<unsigned>(points.size()))));
  query.set_light(light, irradiance);
  runtime::parallel_for(points.size(), query.workers(), [&](unsigned wi, std::size_t i) {
    out[i] = query.evaluate(wi, points[i], i < toward.size() ? toward[i] : glm::dvec3(0.0));
  });
  return out;
}

namespace {

/// A fragment's vertices, each with the direction into the fragment at it: the bisector of its
/// corner (turned round at a reflex corner), so that a vertex on a contact edge takes the value
/// of the fragment's side.
void add_fragment_points(const Scene& scene, const Fragment& f, std::vector<SurfacePoint>& points,
                         std::vector<glm::dvec3>& toward) {
  const std::size_t n = f.polygon.size();
  glm::dvec3 normal(0.0);
  const std::vector<glm::dvec3>& ring = f.face_id < scene.faces.size() ? scene.faces[f.face_id].vertices : f.polygon;
  for (std::size_t a = 0; a < ring.size(); ++a) normal += glm::cross(ring[a], ring[(a + 1) % ring.size()]);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3& v = f.polygon[i];
    const glm::dvec3 to_prev = f.polygon[(i + n - 1) % n] - v, to_next = f.polygon[(i + 1) % n] - v;
    glm::dvec3 dir(0.0);
    const double lp = glm::length(to_prev), ln = glm::length(to_next);
    if (lp > 0 && ln > 0) {
      const glm::dvec3 bisector = to_prev / lp + to_next / ln;
      const double turn = glm::dot(glm::cross(-to_prev, to_next), normal);  // > 0: convex corner
      if (glm::length(bisector) > 1e-9 && turn != 0.0) dir = turn > 0 ? bisector : -bisector;
      else dir = glm::cross(normal, to_next);  // a straight corner: left of the way round
      const double len = glm::length(dir);
      // 1e-6 of the shorter edge, at least 1,000 times the rounding distance of the vertex's
      // coordinates (rounding_eps), at most half the edge: tied to the fragment, not to where
      // the scene lies (a georeferenced scene at 5e6 m takes the same step as at the origin).
      const double edge = std::min(lp, ln);
      const double step = std::min(0.5 * edge, std::max(1e-6 * edge, 1e3 * rounding_eps(v)));
      dir = len > 0 ? dir * (step / len) : glm::dvec3(0.0);
    }
    points.push_back({f.face_id, v});
    toward.push_back(dir);
  }
}

}  // namespace

void fill_light_fragment_visibility(const Scene& scene, const Light& light, std::size_t light_id,
                                    std::vector<Fragment>& fragments, unsigned threads) {
  std::vector<SurfacePoint> points;
  std::vector<glm::dvec3> toward;
  for (const Fragment& f : fragments)
    if (f.light_id == light_id) add_fragment_points(scene, f, points, toward);
  if (points.empty()) return;
  const auto values = light_visibility_irradiance(scene, light, points, threads, true, toward);
  std::size_t next = 0;
  for (Fragment& f : fragments) {
    if (f.light_id != light_id) continue;
    f.visibility.resize(f.polygon.size());
    f.irradiance.resize(f.polygon.size());
    for (std::size_t i = 0; i < f.polygon.size(); ++i, ++next) {
      f.visibility[i] = values[next].first;
      f.irradiance[i] = values[next].second;
      // The exact vertex of a fully lit cell sees all of the light, an umbra cell's none of it;
      // the written vertex is that point rounded to nearest, which may lie a rounding error
      // outside the closed region (a visible fraction of 1e-16). The cell's own value stands.
      if (f.region == LightRegion::FullyLit) f.visibility[i] = 1.0;
      if (f.region == LightRegion::Umbra) f.visibility[i] = 0.0, f.irradiance[i] = 0.0;
    }
  }
}

}  // namespace detail

std::vector<double> light_visibility(const Scene& scene, const Light& light, const std::vector<SurfacePoint>& points,
                                     unsigned threads) {
  const auto both = shadow::detail::light_visibility_irradiance(scene, light, points, threads, false);
  std::vector<double> out(both.size());
  for (std::size_t i = 0; i < both.size(); ++i) out[i] = both[i].first;
  return out;
}

std::vector<double> light_irradiance(const Scene& scene, const Light& light, const std::vector<SurfacePoint>& points,
                                     unsigned threads) {
  const auto both = shadow::detail::light_visibility_irradiance(scene, light, points, threads, true);
  std::vector<double> out(both.size());
  for (std::size_t i = 0; i < both.size(); ++i) out[i] = both[i].second;
  return out;
}

void fill_fragment_visibility(const Scene& scene, const Light& light, std::vector<Fragment>& fragments,
                              unsigned threads) {
  std::vector<SurfacePoint> points;
  std::vector<glm::dvec3> toward;
  for (const Fragment& f : fragments) shadow::detail::add_fragment_points(scene, f, points, toward);
  const auto values = shadow::detail::light_visibility_irradiance(scene, light, points, threads, true, toward);
  std::size_t next = 0;
  for (Fragment& f : fragments) {
    f.visibility.resize(f.polygon.size());
    f.irradiance.resize(f.polygon.size());
    for (std::size_t i = 0; i < f.polygon.size(); ++i, ++next) {
      f.visibility[i] = values[next].first;
      f.irradiance[i] = values[next].second;
    }
  }
}

}  // namespace shadow
