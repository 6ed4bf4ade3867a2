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
#include "core/face_prep.hpp"
#include "core/parallel.hpp"
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

namespace shadow {
namespace {

using namespace exact;

constexpr double kPi = 3.14159265358979323846;
/// Vertices of the regular polygon inscribed in a disk light for its irradiance (the visible
/// fraction uses the circle itself).
constexpr int kDiskIrradianceSides = 1024;

bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

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

/// A few dozen units in the last place of the largest coordinate of p: how far a point
/// rounded to doubles can be from the exact point it stands for (0 at the origin).
double rounding_eps(const glm::dvec3& p) {
  const double size = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  if (!(size > 0.0)) return 0.0;
  return std::ldexp(64.0, std::ilogb(size) - std::numeric_limits<double>::digits + 1);
}

/// What kind of shape is measured on the target plane.
enum class Shape { Polygon, Disk, Sun };

/// The light, checked, in plain numbers (shared by all threads).
struct LightPlan {
  Shape shape = Shape::Polygon;
  std::vector<glm::dvec3> polygon;  // Polygon: the light's vertices, consecutive repeats removed
  core::FacePrep prep;              // Polygon: its exact plane and chart
  glm::dvec3 centre{0.0};           // Disk
  glm::dvec3 normal{0.0};           // Disk: front normal; Sun: to_light
  double radius = 0.0;              // Disk: radius; Sun: tan(angular radius)
};

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

/// The plane the light is measured on, exact (one per thread: lazy values are not shared),
/// with 2D coordinates (u, v) on it: the chart of a polygonal light, or an orthogonal frame
/// (e1, e2) around a disk's centre or the sun's direction.
struct Target {
  Shape shape = Shape::Polygon;
  Vector3 n;          // toward the front (the side points must be on)
  FT offset;          // plane: n . p + offset = 0 (Sun: per point)
  int axis = 2;       // Polygon: the chart's dropped axis
  Point3 c;           // Disk/Sun: origin of (u, v) (Sun: per point)
  Vector3 e1, e2;     // Disk/Sun: u = e1 . (y - c), v = e2 . (y - c); e1 x e2 along n
  FT e1sq, e2sq;
  Polygon2 light;                 // Polygon: the light in chart coordinates, counter-clockwise
  bool light_convex = true;
  FT light_area;                  // Polygon: its chart area
  std::vector<Point2> hull;       // counter-clockwise hull of what is measured (Disk/Sun: a square)
  std::vector<Point3> hull3;      // the hull on the plane (Sun: per point)
  double scale_u = 1, scale_v = 1;  // Disk/Sun: orthonormal coordinates U = u * scale_u
  double radius = 0;                // Disk/Sun: the circle's radius in (U, V)
};

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

/// Keeps the part of a convex polygon where f >= 0 (Sutherland-Hodgman, exact).
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

/// The part of convex polygon `box` (counter-clockwise) where a u + b v + c >= 0.
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

/// Per-face data shared by the threads: bounding boxes of the exact (lifted) vertices.
struct SceneFaces {
  std::vector<core::FacePrep> prep;
  std::vector<std::array<double, 6>> box;  // min xyz, max xyz, widened by a margin
};

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

/// One thread's exact state.
struct Worker {
  std::optional<Target> target;
  std::vector<std::unique_ptr<ExactFace>> faces;
  const ExactFace& face(const Scene& scene, const SceneFaces& sf, std::size_t f) {
    if (!faces[f]) faces[f] = std::make_unique<ExactFace>(make_exact_face(scene.faces[f].vertices, sf.prep[f]));
    return *faces[f];
  }
};

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

// ---- Lambert's contour integral ----------------------------------------------------------

}  // namespace

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

namespace {

using shadow::detail::lambert_contour;

glm::dvec3 to_dvec(const Point3& p) { return {CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())}; }

// ---- one point ------------------------------------------------------------------------------

struct PointResult {
  double visibility = 0.0;
  double irradiance = 0.0;
};

class Evaluator {
 public:
  Evaluator(const Scene& scene, const Light& light, const LightPlan& plan, const SceneFaces& faces, bool irradiance)
      : scene_(scene), light_(light), plan_(plan), faces_(faces), want_irradiance_(irradiance) {
    for (int k = 0; k < 3; ++k) scene_box_[k] = std::numeric_limits<double>::infinity(), scene_box_[k + 3] = -scene_box_[k];
    for (std::size_t f = 0; f < faces.box.size(); ++f)
      if (!faces.prep[f].degenerate)
        for (int k = 0; k < 3; ++k)
          scene_box_[k] = std::min(scene_box_[k], faces.box[f][k]), scene_box_[k + 3] = std::max(scene_box_[k + 3], faces.box[f][k + 3]);
  }

  /// `toward`: zero, or a direction along the point's face: the value is then the limit from
  /// that side (faces through the point hide what they hide from points just beside it).
  PointResult evaluate(Worker& w, const SurfacePoint& sp, const glm::dvec3& toward) const {
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

    std::vector<Polygon2> hidden;
    if (any_behind) {
      Polygon2 behind = clip2(t.hull, gu, gv, g0);
      if (behind.size() >= 3 && CGAL::sign(polygon_area(behind)) == CGAL::POSITIVE) hidden.push_back(std::move(behind));
    }
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

    PointResult result;
    if (t.shape == Shape::Polygon) {
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
        result.irradiance = contour_irradiance(t, visible, sp.position, receiver);
      }
      return result;
    }
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
        result.irradiance = contour_irradiance(t, visible, sp.position, receiver);
      }
    }
    return result;
  }

 private:
  /// Whether a face other than the point's own passes within `eps` of it without passing
  /// exactly through it.
  bool near_contact(Worker& w, const SurfacePoint& sp, double eps) const {
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

  /// Face `face` passes through x. Seen from x + e d (e -> 0+), its part near x hides the light
  /// points y with y - x in the cone spanned by the face's tangent cone at x and -d: for each
  /// convex piece holding x, the half-space on the -d side of the face's plane, cut by one plane
  /// per piece edge through x. Each such convex cone meets the light's plane in a convex region,
  /// clipped here from the light's hull.
  static void add_contact(const Target& t, const ExactFace& face, const core::FacePrep& prep, const Point3& x,
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

  std::array<double, 6> frustum_box(const Target& t, const glm::dvec3& x) const {
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

  /// L times the integral of cos cos' / r^2 over `visible` (Lambert's contour formula).
  double contour_irradiance(const Target& t, const PolygonSet2& visible, const glm::dvec3& x,
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
      sum += lambert_contour(r, n);
    };
    for (const PolygonWithHoles2& region : regions) {
      add(region.outer_boundary());
      for (auto hole = region.holes_begin(); hole != region.holes_end(); ++hole) add(*hole);
    }
    // Counter-clockwise seen from the front (from x) gives r_a x r_b pointing away from the
    // receiver's side: the sum is negative for a light in front.
    return std::max(0.0, -0.5 * orientation * sum * light_.intensity);
  }

  const Scene& scene_;
  const Light& light_;
  const LightPlan& plan_;
  const SceneFaces& faces_;
  bool want_irradiance_;
  std::array<double, 6> scene_box_{};  // the non-degenerate faces' box (for the sun's reach)
};

}  // namespace

namespace detail {

struct LightQuery::Impl {
  const Scene& scene;
  SceneFaces faces;
  std::vector<Worker> workers;
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
  for (Worker& w : q.workers) w.target.reset();  // the exact faces stay: they do not depend on the light
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
  const unsigned n = core::resolve_threads(core::checked_threads(threads));
  LightQuery query(scene, std::max(1u, std::min<unsigned>(n, static_cast<unsigned>(points.size()))));
  query.set_light(light, irradiance);
  core::parallel_for(points.size(), query.workers(), [&](unsigned wi, std::size_t i) {
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
