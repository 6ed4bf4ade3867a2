// SPDX-License-Identifier: GPL-3.0-or-later
// The steps of the visible fraction of an extended light (light_visibility.cpp), shared by
// their files: the light's plan and the target plane it is measured on, the scene's faces
// (light_visibility.cpp), and the evaluation at one point (light_visibility_evaluator.cpp).
// Internal to arealight/.
#pragma once

#include "core/face_prep.hpp"
#include "exact/exact_faces.hpp"
#include "exact/kernel.hpp"

#include <shadow/area_lights.hpp>
#include <shadow/scene.hpp>

#include <glm/vec3.hpp>

#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

namespace shadow::arealight {

using namespace exact;

constexpr double kPi = 3.14159265358979323846;
/// Vertices of the regular polygon inscribed in a disk light for its irradiance (the visible
/// fraction uses the circle itself).
constexpr int kDiskIrradianceSides = 1024;

inline bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// A few dozen units in the last place of the largest coordinate of p: how far a point
/// rounded to doubles can be from the exact point it stands for (0 at the origin).
double rounding_eps(const glm::dvec3& p);

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

/// The light checked (InputError naming `light.<field>` otherwise) and in plain numbers.
LightPlan plan_light(const Light& light);

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

Point2 to_uv(const Target& t, const Point3& y);
Point3 from_uv(const Target& t, const Point2& p);
/// The target plane of a light's plan (one per thread).
Target make_target(const LightPlan& plan);
/// Per point for the sun: the plane through x + s.
void place_sun(Target& t, const Point3& x);
/// Keeps the part of a convex polygon where f >= 0 (Sutherland-Hodgman, exact).
std::vector<Point3> clip(const std::vector<Point3>& polygon, const Affine3& f);
/// The part of convex polygon `box` (counter-clockwise) where a u + b v + c >= 0.
Polygon2 clip2(const std::vector<Point2>& box, const FT& a, const FT& b, const FT& c);

/// Per-face data shared by the threads: bounding boxes of the exact (lifted) vertices.
struct SceneFaces {
  std::vector<core::FacePrep> prep;
  std::vector<std::array<double, 6>> box;  // min xyz, max xyz, widened by a margin
};

SceneFaces prepare_scene(const Scene& scene);

/// One thread's exact state.
struct PointWorker {
  std::optional<Target> target;
  std::vector<std::unique_ptr<ExactFace>> faces;
  const ExactFace& face(const Scene& scene, const SceneFaces& sf, std::size_t f) {
    if (!faces[f]) faces[f] = std::make_unique<ExactFace>(make_exact_face(scene.faces[f].vertices, sf.prep[f]));
    return *faces[f];
  }
};

struct PointResult {
  double visibility = 0.0;
  double irradiance = 0.0;
};

/// Evaluates points for one light (one per call; const, shared by the threads).
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
  PointResult evaluate(PointWorker& w, const SurfacePoint& sp, const glm::dvec3& toward) const;

 private:
  /// The light's parts hidden from x, as polygons in (u, v): every face that can stand between
  /// x and the light (culled by boxes, then exactly by the pyramid from x over the light),
  /// clipped to that pyramid and projected centrally from x onto the light's plane; a face
  /// through x adds the wedge it hides on the side `d` (add_contact).
  void cast_hidden(PointWorker& w, const SurfacePoint& sp, const Target& t, const Point3& x, const FT& h, bool has_toward,
                   const Vector3& d, const Point3& o, const Point3& pu, const Point3& pv,
                   std::vector<Polygon2>& hidden) const;

  /// A polygonal light: its visible fraction from the exact area of the hidden union (and the
  /// irradiance from its visible part).
  PointResult measure_polygon(const Target& t, const std::vector<Polygon2>& hidden, const glm::dvec3& x,
                              const ExactFace& receiver) const;

  /// A disk or the sun: the hidden union's part inside the circle, measured edge by edge (and
  /// the irradiance from the inscribed polygon's visible part, or the sun's cosine).
  PointResult measure_circle(const Target& t, const std::vector<Polygon2>& hidden, const glm::dvec3& x,
                             const ExactFace& receiver) const;

  /// Whether a face other than the point's own passes within `eps` of it without passing
  /// exactly through it.
  bool near_contact(PointWorker& w, const SurfacePoint& sp, double eps) const;

  /// Face `face` passes through x. Seen from x + e d (e -> 0+), its part near x hides the light
  /// points y with y - x in the cone spanned by the face's tangent cone at x and -d: for each
  /// convex piece holding x, the half-space on the -d side of the face's plane, cut by one plane
  /// per piece edge through x. Each such convex cone meets the light's plane in a convex region,
  /// clipped here from the light's hull.
  static void add_contact(const Target& t, const ExactFace& face, const core::FacePrep& prep, const Point3& x,
                          const Vector3& d, const Point3& o, const Point3& pu, const Point3& pv,
                          std::vector<Polygon2>& hidden);

  std::array<double, 6> frustum_box(const Target& t, const glm::dvec3& x) const;

  /// L times the integral of cos cos' / r^2 over `visible` (Lambert's contour formula).
  double contour_irradiance(const Target& t, const PolygonSet2& visible, const glm::dvec3& x,
                            const ExactFace& receiver) const;

  const Scene& scene_;
  const Light& light_;
  const LightPlan& plan_;
  const SceneFaces& faces_;
  bool want_irradiance_;
  std::array<double, 6> scene_box_{};  // the non-degenerate faces' box (for the sun's reach)
};

}  // namespace shadow::arealight
