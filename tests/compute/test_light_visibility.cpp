// SPDX-License-Identifier: GPL-3.0-or-later
// The visible fraction of extended lights and their irradiance (docs/area-light-visibility.md):
// analytic fractions, open space and a closed box, monotonicity when occluders are added, the
// form factor of a square in closed form, and agreement with many random rays per point.
#include <shadow/area_lights.hpp>
#include <shadow/error.hpp>
#include <shadow/output.hpp>
#include <shadow/scene.hpp>
#include <shadow/shadows.hpp>

#include "support/ray_caster.hpp"

#include <gtest/gtest.h>

#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPolyDataReader.h>

#include <filesystem>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <vector>

namespace {

using shadow::Light;
using shadow::LightType;
using shadow::Scene;
using shadow::SurfacePoint;
using glm::dvec3;

constexpr double kPi = 3.14159265358979323846;

/// Adds one face (its own mesh) and returns its id.
std::size_t add_face(Scene& scene, std::vector<dvec3> vertices) {
  shadow::Mesh mesh;
  mesh.name = "m" + std::to_string(scene.meshes.size());
  mesh.first_face = scene.faces.size();
  mesh.face_count = 1;
  scene.meshes.push_back(mesh);
  shadow::Face face;
  face.vertices = std::move(vertices);
  face.mesh = scene.meshes.size() - 1;
  scene.faces.push_back(face);
  return scene.faces.size() - 1;
}

/// Axis-aligned rectangle [x0, x1] x [y0, y1] at height z, facing up (+z) or down.
std::vector<dvec3> rect_z(double x0, double x1, double y0, double y1, double z, bool up = true) {
  std::vector<dvec3> v{{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
  if (!up) std::reverse(v.begin(), v.end());
  return v;
}

Scene ground_scene() {
  Scene scene;
  add_face(scene, rect_z(-5, 5, -5, 5, 0));  // face 0: the receiving ground, facing up
  return scene;
}

Light square_light(double half, double z) {
  Light light;
  light.type = LightType::Area;
  light.polygon = rect_z(-half, half, -half, half, z, /*up=*/false);  // light leaves downward
  light.intensity = 1.0;
  return light;
}

Light disk_light(double radius, double z) {
  Light light;
  light.type = LightType::Disk;
  light.position = {0, 0, z};
  light.normal = {0, 0, -1};
  light.radius = radius;
  return light;
}

Light sun(dvec3 to_light, double diameter = 0.53) {
  Light light;
  light.type = LightType::Directional;
  light.to_light = to_light;
  light.angular_diameter = diameter;
  return light;
}

double visibility_at(const Scene& scene, const Light& light, dvec3 p, std::size_t face = 0) {
  return shadow::light_visibility(scene, light, {SurfacePoint{face, p}}, 1).at(0);
}

/// Closed-form integral of cos cos' / r^2 over a w x h rectangle parallel to the receiver at
/// distance c, seen from below one corner (the classic corner form factor times pi).
double corner_integral(double w, double h, double c) {
  const double a = w / c, b = h / c;
  const double ra = std::sqrt(1 + a * a), rb = std::sqrt(1 + b * b);
  return 0.5 * (a / ra * std::atan(b / ra) + b / rb * std::atan(a / rb));
}

TEST(LightVisibility, OpenSpaceSeesAllOfTheLight) {
  const Scene scene = ground_scene();
  EXPECT_EQ(visibility_at(scene, square_light(1, 2), {0.3, -0.2, 0}), 1.0);
  EXPECT_EQ(visibility_at(scene, disk_light(1, 2), {0.3, -0.2, 0}), 1.0);
  EXPECT_EQ(visibility_at(scene, sun({0.2, 0.1, 1}), {0.3, -0.2, 0}), 1.0);
}

TEST(LightVisibility, HalfCoveringEdgeHidesHalfOfASquare) {
  Scene scene = ground_scene();
  add_face(scene, rect_z(0, 3, -3, 3, 1));  // its edge x = 0 projects onto the light's middle
  EXPECT_EQ(visibility_at(scene, square_light(1, 2), {0, 0, 0}), 0.5);
  // Seen from (0.1, 0, 0) the edge projects to u = 2 * 0 - 0.1: 0.45 of the width stays visible.
  EXPECT_EQ(visibility_at(scene, square_light(1, 2), {0.1, 0, 0}), 0.45);
}

TEST(LightVisibility, SquareSeenThroughASquareHole) {
  Scene scene = ground_scene();
  // A plate at z = 1 with a hole [-0.25, 0.25]^2, as four rectangles; the light is [-1, 1]^2
  // at z = 2: from the ground the hole projects onto a square of side 1, a quarter of the light.
  add_face(scene, rect_z(-3, -0.25, -3, 3, 1));
  add_face(scene, rect_z(0.25, 3, -3, 3, 1));
  add_face(scene, rect_z(-0.25, 0.25, -3, -0.25, 1));
  add_face(scene, rect_z(-0.25, 0.25, 0.25, 3, 1));
  EXPECT_EQ(visibility_at(scene, square_light(1, 2), {0, 0, 0}), 0.25);
  EXPECT_EQ(visibility_at(scene, square_light(1, 2), {0.1, -0.2, 0}), 0.25);
  // Far off to the side the hole's image leaves the light: nothing is seen.
  EXPECT_EQ(visibility_at(scene, square_light(1, 2), {4, 0, 0}), 0.0);
}

TEST(LightVisibility, DiskAgainstTheCircularSegment) {
  for (double d : {0.0, 0.1, 0.3, -0.2, 0.45}) {
    Scene scene = ground_scene();
    add_face(scene, rect_z(d, 3, -3, 3, 1));  // projects onto u >= 2d on the disk of radius 1
    const double c = 2 * d, R = 1.0;
    const double segment = R * R * std::acos(c / R) - c * std::sqrt(R * R - c * c);  // area with u >= c
    const double expected = 1.0 - segment / (kPi * R * R);
    EXPECT_NEAR(visibility_at(scene, disk_light(R, 2), {0, 0, 0}), expected, 1e-13) << "d = " << d;
  }
}

TEST(LightVisibility, SunDiskHalfHiddenByAHorizonEdge) {
  Scene scene = ground_scene();
  // A wall at x = 10, 10 high: its top edge lies on the ray from the origin to the sun's centre.
  add_face(scene, {{10, -100, 0}, {10, 100, 0}, {10, 100, 10}, {10, -100, 10}});
  EXPECT_NEAR(visibility_at(scene, sun({1, 0, 1}), {0, 0, 0}), 0.5, 1e-12);
  // The sun is 0.53 degrees wide: 0.3 degrees lower it is hidden, 0.3 degrees higher it is clear.
  const double a = (45.0 - 0.3) * kPi / 180, b = (45.0 + 0.3) * kPi / 180;
  EXPECT_EQ(visibility_at(scene, sun({std::cos(a), 0, std::sin(a)}), {0, 0, 0}), 0.0);
  EXPECT_EQ(visibility_at(scene, sun({std::cos(b), 0, std::sin(b)}), {0, 0, 0}), 1.0);
  // Straight overhead, an occluder whose edge passes over the point hides half.
  Scene over = ground_scene();
  add_face(over, rect_z(0, 100, -100, 100, 10));
  EXPECT_NEAR(visibility_at(over, sun({0, 0, 1}), {0, 0, 0}), 0.5, 1e-12);
}

TEST(LightVisibility, SunDiskAgainstTheCapSegmentInSolidAngle) {
  // An edge at angular distance beta from the sun's centre hides a segment of the cap. Its solid
  // angle, by numerical quadrature over the polar angle (independent of the library's
  // closed-form edge sums): omega(beta) = int_0^alpha sin t * 2 acos(tan(beta)/tan(t)) dt.
  const double alpha = 2.0 * kPi / 180;  // a 4-degree sun, to make the solid-angle weight matter
  for (double beta_deg : {0.5, 1.0, 1.7}) {
    const double beta = beta_deg * kPi / 180;
    const int steps = 200000;
    double hidden = 0;
    for (int i = 0; i < steps; ++i) {
      const double t = (i + 0.5) * alpha / steps;
      if (t <= beta) continue;
      hidden += std::sin(t) * 2.0 * std::acos(std::tan(beta) / std::tan(t)) * (alpha / steps);
    }
    const double total = 2 * kPi * (1 - std::cos(alpha));
    Scene scene = ground_scene();
    add_face(scene, rect_z(10 * std::tan(beta), 100, -100, 100, 10));  // hides directions with x/z >= tan(beta)
    EXPECT_NEAR(visibility_at(scene, sun({0, 0, 1}, 4.0), {0, 0, 0}), 1 - hidden / total, 2e-6) << beta_deg;
  }
}

TEST(LightVisibility, ClosedBoxSeesNothing) {
  Scene scene;
  add_face(scene, rect_z(-1, 1, -1, 1, 0, /*up=*/true));  // the box's floor, seen from inside
  add_face(scene, rect_z(-1, 1, -1, 1, 2, /*up=*/true));  // roof
  add_face(scene, {{-1, -1, 0}, {1, -1, 0}, {1, -1, 2}, {-1, -1, 2}});
  add_face(scene, {{1, -1, 0}, {1, 1, 0}, {1, 1, 2}, {1, -1, 2}});
  add_face(scene, {{1, 1, 0}, {-1, 1, 0}, {-1, 1, 2}, {1, 1, 2}});
  add_face(scene, {{-1, 1, 0}, {-1, -1, 0}, {-1, -1, 2}, {-1, 1, 2}});
  EXPECT_EQ(visibility_at(scene, square_light(3, 5), {0.3, 0.2, 0}), 0.0);
  EXPECT_EQ(visibility_at(scene, disk_light(3, 5), {0.3, 0.2, 0}), 0.0);
  EXPECT_EQ(visibility_at(scene, sun({0.3, 0.2, 1}), {0.3, 0.2, 0}), 0.0);
  // Next to the floor's edge the roof and the wall still shut it in; on the edge itself the wall
  // passes through the point and hides nothing of measure (docs/area-light-visibility.md: contact).
  EXPECT_EQ(visibility_at(scene, square_light(3, 5), {0.999, 0, 0}), 0.0);
  EXPECT_EQ(visibility_at(scene, square_light(3, 5), {1, 0, 0}), 1.0 / 3.0);
}

TEST(LightVisibility, BehindTheLightOrLookingAwaySeesNothing) {
  Scene scene = ground_scene();
  add_face(scene, rect_z(-5, 5, -5, 5, 3));  // face 1, facing up at z = 3: above the light's plane
  EXPECT_EQ(visibility_at(scene, square_light(1, 2), {0, 0, 3}, 1), 0.0);
  Scene down;
  add_face(down, rect_z(-5, 5, -5, 5, 0, /*up=*/false));  // facing away from the light
  EXPECT_EQ(visibility_at(down, square_light(1, 2), {0, 0, 0}), 0.0);
  EXPECT_EQ(visibility_at(down, disk_light(1, 2), {0, 0, 0}), 0.0);
  EXPECT_EQ(visibility_at(down, sun({0, 0, 1}), {0, 0, 0}), 0.0);
}

TEST(LightVisibility, LightHalfBelowTheReceiversHorizon) {
  const Scene scene = ground_scene();
  Light wall_lamp;  // a vertical square at x = 2, z in [-1, 1], shining toward -x
  wall_lamp.type = LightType::Area;
  wall_lamp.polygon = {{2, -1, -1}, {2, -1, 1}, {2, 1, 1}, {2, 1, -1}};
  EXPECT_EQ(visibility_at(scene, wall_lamp, {0, 0, 0}), 0.5);
}

TEST(LightVisibility, InputErrors) {
  const Scene scene = ground_scene();
  Light point;
  point.type = LightType::Point;
  EXPECT_THROW(shadow::light_visibility(scene, point, {SurfacePoint{0, {0, 0, 0}}}), shadow::InputError);
  EXPECT_THROW(shadow::light_visibility(scene, square_light(1, 2), {SurfacePoint{7, {0, 0, 0}}}), shadow::InputError);
  Light flat = square_light(1, 2);
  flat.polygon = {{0, 0, 2}, {1, 0, 2}, {2, 0, 2}};
  EXPECT_THROW(shadow::light_visibility(scene, flat, {SurfacePoint{0, {0, 0, 0}}}), shadow::InputError);
  Light bowtie = square_light(1, 2);
  bowtie.polygon = {{-1, -1, 2}, {1, 1, 2}, {1, -1, 2}, {-1, 1, 2}};
  EXPECT_THROW(shadow::light_visibility(scene, bowtie, {SurfacePoint{0, {0, 0, 0}}}), shadow::InputError);
  Light no_radius = disk_light(0, 2);
  EXPECT_THROW(shadow::light_visibility(scene, no_radius, {SurfacePoint{0, {0, 0, 0}}}), shadow::InputError);
  EXPECT_THROW(shadow::light_visibility(scene, sun({0, 0, 1}, 200), {SurfacePoint{0, {0, 0, 0}}}), shadow::InputError);
}

TEST(LightIrradiance, UnoccludedSquareAgainstItsClosedForm) {
  const Scene scene = ground_scene();
  const Light light = square_light(1, 2);  // radiance 1
  // Under the centre: four 1 x 1 rectangles seen from below a corner, at distance 2.
  const double centre = 4 * corner_integral(1, 1, 2);
  // Under (0.5, 0.25): rectangles 1.5 x 1.25, 0.5 x 1.25, 1.5 x 0.75, 0.5 x 0.75.
  const double off = corner_integral(1.5, 1.25, 2) + corner_integral(0.5, 1.25, 2) + corner_integral(1.5, 0.75, 2) +
                     corner_integral(0.5, 0.75, 2);
  const auto e = shadow::light_irradiance(scene, light, {SurfacePoint{0, {0, 0, 0}}, SurfacePoint{0, {0.5, 0.25, 0}}}, 1);
  EXPECT_NEAR(e[0], centre, 1e-14);
  EXPECT_NEAR(e[1], off, 1e-14);
  // Half of the light hidden by an edge over the centre: half the irradiance, by symmetry.
  Scene half = ground_scene();
  add_face(half, rect_z(0, 3, -3, 3, 1));
  EXPECT_NEAR(shadow::light_irradiance(half, light, {SurfacePoint{0, {0, 0, 0}}}, 1)[0], centre / 2, 1e-14);
}

TEST(LightIrradiance, DiskAndSun) {
  const Scene scene = ground_scene();
  // A disk of radius R at distance h straight above: E = pi L R^2 / (h^2 + R^2).
  Light disk = disk_light(1, 2);
  disk.intensity = 3;
  EXPECT_NEAR(shadow::light_irradiance(scene, disk, {SurfacePoint{0, {0, 0, 0}}}, 1)[0], 3 * kPi / 5, 3 * kPi / 5 * 7e-6);
  // The sun: intensity * fraction * cos(incidence).
  Light s = sun({1, 0, 1});
  s.intensity = 1000;
  Scene wall = ground_scene();
  add_face(wall, {{10, -100, 0}, {10, 100, 0}, {10, 100, 10}, {10, -100, 10}});
  EXPECT_NEAR(shadow::light_irradiance(wall, s, {SurfacePoint{0, {0, 0, 0}}}, 1)[0], 1000 * 0.5 * std::sqrt(0.5), 1e-9);
}

/// A ground, a light, and `count` random quads between them (seeded).
Scene random_scene(std::mt19937& rng, int count) {
  Scene scene = ground_scene();
  std::uniform_real_distribution<double> pos(-2.5, 2.5), size(0.2, 1.2), height(0.3, 2.7), tilt(-0.4, 0.4);
  for (int i = 0; i < count; ++i) {
    const dvec3 c{pos(rng), pos(rng), height(rng)};
    const double w = size(rng), h = size(rng), t1 = tilt(rng), t2 = tilt(rng);
    add_face(scene, {c + dvec3(-w, -h, -w * t1 - h * t2), c + dvec3(w, -h, w * t1 - h * t2),
                     c + dvec3(w, h, w * t1 + h * t2), c + dvec3(-w, h, -w * t1 + h * t2)});
  }
  return scene;
}

TEST(LightVisibility, AddingAnOccluderNeverRaisesVisibility) {
  std::mt19937 rng(20261126);
  std::uniform_real_distribution<double> on_ground(-3, 3);
  for (int trial = 0; trial < 4; ++trial) {
    const Scene full = random_scene(rng, 6);
    std::vector<SurfacePoint> points;
    for (int i = 0; i < 25; ++i) points.push_back({0, {on_ground(rng), on_ground(rng), 0}});
    for (const Light& light : {square_light(1.5, 3), disk_light(1.5, 3), sun({0.3, -0.2, 1}, 20.0)}) {
      std::vector<double> before(points.size(), 1.0);
      for (std::size_t keep = 1; keep < full.faces.size() + 1; ++keep) {
        Scene partial = full;
        partial.faces.resize(keep);
        partial.meshes.resize(keep);
        const std::vector<double> now = shadow::light_visibility(partial, light, points, 2);
        for (std::size_t i = 0; i < points.size(); ++i) {
          EXPECT_LE(now[i], before[i] + (light.type == LightType::Area ? 0.0 : 1e-13)) << trial << " " << keep << " " << i;
          EXPECT_GE(now[i], 0.0);
        }
        before = now;
      }
    }
  }
}

TEST(LightVisibility, AgreesWithManyRandomRaysPerPoint) {
  // k rays from each point to uniform random points of the light, cast by the tests' own
  // double-precision ray caster. With k = 4,000 the sampled fraction's standard deviation is
  // at most 0.008; the tolerance is 5 of them (rays too close to an edge to decide are dropped).
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0, 1), on_ground(-3, 3);
  const Scene scene = random_scene(rng, 8);
  const Light light = square_light(1.5, 3);
  const Light disk = disk_light(1.5, 3);
  std::vector<SurfacePoint> points;
  for (int i = 0; i < 12; ++i) points.push_back({0, {on_ground(rng), on_ground(rng), 0}});
  const std::vector<double> exact = shadow::light_visibility(scene, light, points, 2);
  const std::vector<double> exact_disk = shadow::light_visibility(scene, disk, points, 2);
  const int k = 4000;
  int partial = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    int lit = 0, decided = 0, lit_disk = 0, decided_disk = 0;
    for (int r = 0; r < k; ++r) {
      Light sample;
      sample.type = LightType::Point;
      sample.position = {-1.5 + 3 * unit(rng), -1.5 + 3 * unit(rng), 3};
      const auto v = shadow::test::cast_shadow_ray(scene, 0, points[i].position, sample, 1e-9);
      if (v != shadow::test::RayVerdict::Unsure) ++decided, lit += v == shadow::test::RayVerdict::Lit;
      const double rho = 1.5 * std::sqrt(unit(rng)), phi = 2 * kPi * unit(rng);
      sample.position = {rho * std::cos(phi), rho * std::sin(phi), 3};
      const auto d = shadow::test::cast_shadow_ray(scene, 0, points[i].position, sample, 1e-9);
      if (d != shadow::test::RayVerdict::Unsure) ++decided_disk, lit_disk += d == shadow::test::RayVerdict::Lit;
    }
    ASSERT_GT(decided, k * 9 / 10);
    ASSERT_GT(decided_disk, k * 9 / 10);
    EXPECT_NEAR(exact[i], double(lit) / decided, 0.04) << "point " << i;
    EXPECT_NEAR(exact_disk[i], double(lit_disk) / decided_disk, 0.04) << "point " << i;
    partial += exact[i] > 0.05 && exact[i] < 0.95;
  }
  EXPECT_GE(partial, 2);  // the scene does put points in penumbrae
}

}  // namespace

namespace {

/// A ground point (face 0) on the outline of the box [-1, 1]^2 standing on it.
bool on_box_foot(std::size_t face, const dvec3& p) {
  return face == 0 && p.z == 0 && std::abs(p.x) <= 1 && std::abs(p.y) <= 1 && (std::abs(p.x) == 1 || std::abs(p.y) == 1);
}

TEST(FragmentVisibility, ComputeShadowsFillsExtendedLightsFragments) {
  // A box on the ground under a 5-degree sun: every fragment vertex carries the visible fraction,
  // equal to light_visibility at that vertex; a hard sun's fragments carry none.
  Scene scene = ground_scene();
  add_face(scene, rect_z(-1, 1, -1, 1, 2));
  add_face(scene, {{-1, -1, 0}, {1, -1, 0}, {1, -1, 2}, {-1, -1, 2}});
  add_face(scene, {{1, -1, 0}, {1, 1, 0}, {1, 1, 2}, {1, -1, 2}});
  add_face(scene, {{1, 1, 0}, {-1, 1, 0}, {-1, 1, 2}, {1, 1, 2}});
  add_face(scene, {{-1, 1, 0}, {-1, -1, 0}, {-1, -1, 2}, {-1, 1, 2}});
  scene.lights = {sun({0.5, 0.3, 1}, 5.0), sun({0.5, 0.3, 1}, 0.0)};
  shadow::ShadowOptions options;
  options.threads = 2;
  const shadow::ShadowResult result = shadow::compute_shadows(scene, options);
  int filled = 0, partial = 0;
  for (const shadow::Fragment& f : result.fragments) {
    if (f.light_id == 1) {
      EXPECT_TRUE(f.visibility.empty());
      continue;
    }
    ASSERT_EQ(f.visibility.size(), f.polygon.size());
    std::vector<SurfacePoint> points;
    for (const dvec3& p : f.polygon) points.push_back({f.face_id, p});
    const std::vector<double> direct = shadow::light_visibility(scene, scene.lights[0], points, 1);
    for (std::size_t i = 0; i < points.size(); ++i) {
      // Off the box's contact edges a vertex's value is the point's own (on them, the side's).
      if (!on_box_foot(f.face_id, f.polygon[i])) EXPECT_EQ(f.visibility[i], direct[i]);
      EXPECT_GE(f.visibility[i], 0.0);
      EXPECT_LE(f.visibility[i], 1.0);
      partial += f.visibility[i] > 0.0 && f.visibility[i] < 1.0;
    }
    ++filled;
  }
  EXPECT_GT(filled, 0);
  EXPECT_GT(partial, 0);  // the hard shadow's outline runs through the penumbra
}

}  // namespace

namespace {

vtkSmartPointer<vtkPolyData> read_vtp(const std::filesystem::path& path) {
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(path.string().c_str());
  reader->Update();
  return reader->GetOutput();
}

TEST(FragmentVisibility, FragmentsFileCarriesVisibilityOnlyForExtendedLights) {
  Scene scene = ground_scene();
  add_face(scene, rect_z(-1, 1, -1, 1, 2));
  add_face(scene, {{-1, -1, 0}, {1, -1, 0}, {1, -1, 2}, {-1, -1, 2}});
  add_face(scene, {{1, -1, 0}, {1, 1, 0}, {1, 1, 2}, {1, -1, 2}});
  scene.lights = {sun({0.5, 0.3, 1}, 5.0), sun({0.5, 0.3, 1}, 0.0)};
  scene.lights[0].intensity = 800;
  shadow::ShadowOptions options;
  options.threads = 2;
  const shadow::ShadowResult result = shadow::compute_shadows(scene, options);
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "libshadow_test_light_visibility";
  std::filesystem::remove_all(dir);
  shadow::write_outputs(dir / "soft", scene, result);
  const auto poly = read_vtp(dir / "soft" / "fragments.vtp");
  vtkDataArray* visibility = poly->GetPointData()->GetArray("visibility");
  vtkDataArray* irradiance = poly->GetPointData()->GetArray("irradiance");
  ASSERT_NE(visibility, nullptr);
  ASSERT_NE(irradiance, nullptr);
  vtkIdType point = 0;
  for (const shadow::Fragment& f : result.fragments) {
    std::vector<SurfacePoint> points;
    for (const dvec3& p : f.polygon) points.push_back({f.face_id, p});
    std::vector<double> e(points.size(), 0.0);
    if (f.light_id == 0) e = shadow::light_irradiance(scene, scene.lights[0], points, 1);
    for (std::size_t i = 0; i < f.polygon.size(); ++i, ++point) {
      if (f.light_id == 0) {
        EXPECT_EQ(visibility->GetTuple1(point), f.visibility[i]);
        if (!on_box_foot(f.face_id, f.polygon[i])) EXPECT_EQ(irradiance->GetTuple1(point), e[i]);
        EXPECT_EQ(irradiance->GetTuple1(point) == 0.0, f.visibility[i] == 0.0);
      } else {
        EXPECT_EQ(visibility->GetTuple1(point), f.lit ? 1.0 : 0.0);
      }
    }
  }
  // Without an extended light, no visibility array.
  Scene hard = scene;
  hard.lights.resize(1);
  hard.lights[0].angular_diameter = 0;
  shadow::write_outputs(dir / "hard", hard, shadow::compute_shadows(hard, options));
  EXPECT_EQ(read_vtp(dir / "hard" / "fragments.vtp")->GetPointData()->GetArray("visibility"), nullptr);
  std::filesystem::remove_all(dir);
}

}  // namespace

namespace {

shadow::Fragment fragment_on(std::size_t face, std::vector<dvec3> polygon) {
  shadow::Fragment f;
  f.face_id = face;
  f.light_id = 0;
  f.lit = true;
  f.polygon = std::move(polygon);
  return f;
}

TEST(FragmentVisibility, ContactEdgesTakeTheFragmentsSide) {
  // A zero-thickness wall x = 0, 3 high, on the ground; the light beyond it at x in [1, 3].
  Scene scene = ground_scene();
  add_face(scene, {{0, -5, 0}, {0, 5, 0}, {0, 5, 3}, {0, -5, 3}});
  Light light;
  light.type = LightType::Area;
  light.polygon = {{1, -1, 4}, {1, 1, 4}, {3, 1, 4}, {3, -1, 4}};  // facing down
  // The shadowed side (x < 0): its vertices on the wall's foot take the limit from x < 0.
  std::vector<shadow::Fragment> fragments{fragment_on(0, rect_z(-2, 0, -1, 1, 0)),
                                          fragment_on(0, rect_z(0, 2, -1, 1, 0))};
  shadow::fill_fragment_visibility(scene, light, fragments, 1);
  for (std::size_t side = 0; side < 2; ++side) {
    const shadow::Fragment& f = fragments[side];
    for (std::size_t i = 0; i < f.polygon.size(); ++i) {
      const dvec3 p = f.polygon[i];
      // Beside the vertex, a hair inside the fragment.
      const dvec3 beside = p + 1e-9 * (dvec3(side == 0 ? -1 : 1, -p.y, 0));
      EXPECT_NEAR(f.visibility[i], visibility_at(scene, light, beside), 1e-6) << side << " " << i;
    }
  }
  EXPECT_EQ(fragments[0].visibility[1], 0.0);  // (0, -1, 0): at the wall's foot, shadow side
  EXPECT_EQ(fragments[1].visibility[0], 1.0);  // the same point, lit side
  // The point itself (no side) sees all of the light: the wall is a line from there.
  EXPECT_EQ(visibility_at(scene, light, {0, -1, 0}), 1.0);

  // A closed room's floor: every vertex of the whole floor, edges and corners too, sees nothing.
  Scene room;
  add_face(room, rect_z(-1, 1, -1, 1, 0, /*up=*/true));
  add_face(room, rect_z(-1, 1, -1, 1, 2, /*up=*/true));
  add_face(room, {{-1, -1, 0}, {1, -1, 0}, {1, -1, 2}, {-1, -1, 2}});
  add_face(room, {{1, -1, 0}, {1, 1, 0}, {1, 1, 2}, {1, -1, 2}});
  add_face(room, {{1, 1, 0}, {-1, 1, 0}, {-1, 1, 2}, {1, 1, 2}});
  add_face(room, {{-1, 1, 0}, {-1, -1, 0}, {-1, -1, 2}, {-1, 1, 2}});
  for (const Light& l : {square_light(3, 5), disk_light(3, 5), sun({0.3, 0.2, 1}, 10.0)}) {
    std::vector<shadow::Fragment> floor{fragment_on(0, {{-1, -1, 0}, {0, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}})};
    shadow::fill_fragment_visibility(room, l, floor, 1);
    for (double v : floor[0].visibility) EXPECT_EQ(v, 0.0);
  }
}

}  // namespace

namespace {

TEST(FragmentVisibility, AgreesWithTheExactRegions) {
  // Two exact routes: the regions on faces (arealight/area_receiver.cpp) and the visible fraction
  // at points (this one). Every vertex and the centroid of a fully lit cell sees all of the
  // light, those of an umbra cell none of it (seeded random scenes, three kinds of light; some
  // quads pierce the ground, making contact lines). Vertices are the exact region corners rounded
  // to doubles, so one may see a sliver of 1e-30 of the light: they are checked to 1e-9.
  std::mt19937 rng(11);
  int checked[3] = {0, 0, 0};
  for (int trial = 0; trial < 3; ++trial) {
    Scene scene = random_scene(rng, 5);
    scene.lights = {square_light(1.5, 3), disk_light(1.5, 3), sun({0.3, -0.2, 1}, 8.0)};
    shadow::ShadowOptions options;
    options.threads = 2;
    const shadow::ShadowResult result = shadow::compute_shadows(scene, options);
    for (const shadow::Fragment& f : result.fragments) {
      ASSERT_EQ(f.visibility.size(), f.polygon.size());
      if (f.face_id != 0 || f.region == shadow::LightRegion::Penumbra) continue;
      dvec3 centroid(0.0);
      for (const dvec3& p : f.polygon) centroid += p / double(f.polygon.size());
      const double inside = visibility_at(scene, scene.lights[f.light_id], centroid);
      const double expected = f.region == shadow::LightRegion::FullyLit ? 1.0 : 0.0;
      bool convex = true;
      for (std::size_t i = 0; i < f.polygon.size(); ++i) {
        const dvec3& a = f.polygon[i];
        const dvec3& b = f.polygon[(i + 1) % f.polygon.size()];
        const dvec3& c = f.polygon[(i + 2) % f.polygon.size()];
        convex = convex && glm::cross(b - a, c - b).z >= 0;
      }
      if (convex) EXPECT_EQ(inside, expected) << "light " << f.light_id << " region " << int(f.region) << " n " << f.polygon.size() << " c " << centroid.x << " " << centroid.y;
      for (std::size_t i = 0; i < f.polygon.size(); ++i)
        EXPECT_NEAR(f.visibility[i], expected, 1e-9) << "trial " << trial << " light " << f.light_id << " region " << int(f.region) << " at " << f.polygon[i].x << " " << f.polygon[i].y << " point " << visibility_at(scene, scene.lights[f.light_id], f.polygon[i]);
      ++checked[f.light_id];
    }
  }
  for (int l = 0; l < 3; ++l) EXPECT_GT(checked[l], 0);
}

}  // namespace

namespace {

TEST(FragmentVisibility, VerticesInTheLightsPlaneTakeTheFragmentsSide) {
  // A wall up to the height of a ceiling luminaire: the wall cell's top vertices lie in the
  // light's plane. The point itself is not in front of the light (0); a hair below it the light
  // is seen whole, edge-on (1), and that is the cell's value there.
  Scene scene;
  add_face(scene, {{0, -2, 0}, {0, 2, 0}, {0, 2, 3}, {0, -2, 3}});  // faces +x
  Light lamp = square_light(0.5, 3);
  lamp.polygon = rect_z(1, 2, -0.5, 0.5, 3, /*up=*/false);
  std::vector<shadow::Fragment> wall{fragment_on(0, {{0, -2, 0}, {0, 2, 0}, {0, 2, 3}, {0, -2, 3}})};
  shadow::fill_fragment_visibility(scene, lamp, wall, 1);
  EXPECT_EQ(visibility_at(scene, lamp, {0, 2, 3}), 0.0);
  for (double v : wall[0].visibility) EXPECT_EQ(v, 1.0);
}

}  // namespace

namespace {

/// A 2 x 2 x 2 box standing on a 10 x 10 ground at the origin (faces 1..5 after the ground).
Scene box_scene(dvec3 offset = dvec3(0.0)) {
  Scene scene;
  auto at = [&](std::vector<dvec3> v) {
    for (dvec3& p : v) p += offset;
    return v;
  };
  add_face(scene, at(rect_z(-5, 5, -5, 5, 0)));
  add_face(scene, at(rect_z(-1, 1, -1, 1, 2)));
  add_face(scene, at({{-1, -1, 0}, {1, -1, 0}, {1, -1, 2}, {-1, -1, 2}}));
  add_face(scene, at({{1, -1, 0}, {1, 1, 0}, {1, 1, 2}, {1, -1, 2}}));
  add_face(scene, at({{1, 1, 0}, {-1, 1, 0}, {-1, 1, 2}, {1, 1, 2}}));
  add_face(scene, at({{-1, 1, 0}, {-1, -1, 0}, {-1, -1, 2}, {-1, 1, 2}}));
  return scene;
}

/// A 2 m high box on a diamond footprint (corners (+-2, 0), (0, +-2)) on a 10 x 10 ground, all
/// moved by `offset`: its walls' feet run at 45 degrees, so the region corners on them are
/// rounded to doubles (a hair off the walls' planes).
Scene diamond_scene(dvec3 offset) {
  Scene scene;
  auto at = [&](std::vector<dvec3> v) {
    for (dvec3& p : v) p += offset;
    return v;
  };
  add_face(scene, at(rect_z(-5, 5, -5, 5, 0)));
  const std::vector<dvec3> foot{{2, 0, 0}, {0, 2, 0}, {-2, 0, 0}, {0, -2, 0}};
  std::vector<dvec3> roof;
  for (const dvec3& p : foot) roof.push_back(p + dvec3(0, 0, 2));
  add_face(scene, at(roof));
  for (std::size_t i = 0; i < 4; ++i) {
    const dvec3& a = foot[i];
    const dvec3& b = foot[(i + 1) % 4];
    add_face(scene, at({a, b, b + dvec3(0, 0, 2), a + dvec3(0, 0, 2)}));
  }
  return scene;
}

TEST(LightVisibility, DirectionsAndNormalsOfAnyScale) {
  // to_light and a disk's normal need only be finite and non-zero: 1e200 (whose frame's squared
  // lengths, ~|n|^4, overflow) and 1e-200 (underflow) give the values of the unit vectors.
  const Scene scene = box_scene();
  std::vector<SurfacePoint> points;
  for (int i = 0; i <= 40; ++i) points.push_back({0, {-4.5 + 0.225 * i, 1.1 + 0.05 * i, 0}});
  const dvec3 dir(0.5, 0.3, 1);
  const std::vector<double> sun_ref = shadow::light_visibility(scene, sun(dir), points, 1);
  Light disk = disk_light(2, 5);
  const std::vector<double> disk_ref = shadow::light_visibility(scene, disk, points, 1);
  int partial = 0;
  for (double v : sun_ref) partial += v > 0 && v < 1;
  for (double v : disk_ref) partial += v > 0 && v < 1;
  EXPECT_GT(partial, 5);
  for (const double scale : {1e200, 1e-200, -1e200, -1e-200}) {
    SCOPED_TRACE(scale);
    if (scale > 0) {
      const std::vector<double> s = shadow::light_visibility(scene, sun(dir * scale), points, 1);
      const std::vector<double> e = shadow::light_irradiance(scene, sun(dir * scale), points, 1);
      const std::vector<double> e_ref = shadow::light_irradiance(scene, sun(dir), points, 1);
      for (std::size_t i = 0; i < points.size(); ++i) {
        EXPECT_NEAR(s[i], sun_ref[i], 1e-9) << i;
        EXPECT_NEAR(e[i], e_ref[i], 1e-9) << i;
      }
    }
    disk.normal = dvec3(0, 0, -std::abs(scale));
    const std::vector<double> d = shadow::light_visibility(scene, disk, points, 1);
    for (std::size_t i = 0; i < points.size(); ++i) EXPECT_NEAR(d[i], disk_ref[i], 1e-12) << i;
  }
  // Through the engine: a 0.53-degree sun given as 1e200 or 1e-200 times a direction.
  std::vector<double> areas_ref;
  for (const double scale : {1.0, 1e200, 1e-200}) {
    SCOPED_TRACE(scale);
    Scene s = box_scene();
    s.lights = {sun(dvec3(0, 0, 1) * scale), sun(dir * scale)};
    Light tiny_disk = disk_light(2, 5);
    tiny_disk.normal = dvec3(0, 0, -scale);
    s.lights.push_back(tiny_disk);
    shadow::ShadowOptions options;
    options.threads = 2;
    const shadow::ShadowResult r = shadow::compute_shadows(s, options);
    int vertices = 0;
    for (const shadow::Fragment& f : r.fragments) {
      ASSERT_EQ(f.visibility.size(), f.polygon.size());
      ASSERT_EQ(f.irradiance.size(), f.polygon.size());
      for (std::size_t i = 0; i < f.polygon.size(); ++i, ++vertices) {
        EXPECT_TRUE(f.visibility[i] >= 0.0 && f.visibility[i] <= 1.0);
        EXPECT_TRUE(std::isfinite(f.irradiance[i]));
      }
    }
    EXPECT_GT(vertices, 0);
    std::vector<double> areas;
    for (const shadow::FaceLighting& fl : r.lighting)
      areas.insert(areas.end(), {fl.fully_lit_area, fl.penumbra_area, fl.umbra_area});
    if (areas_ref.empty()) areas_ref = areas;
    ASSERT_EQ(areas.size(), areas_ref.size());
    for (std::size_t i = 0; i < areas.size(); ++i) EXPECT_NEAR(areas[i], areas_ref[i], 1e-9) << i;
  }
}

TEST(FragmentVisibility, GeoreferencedSceneMatchesTheOrigin) {
  // The same scene at the origin and at UTM-like coordinates (500 km, 5,000 km: every input
  // coordinate stays exact; the region corners on the walls' feet are rounded). The visibility at
  // corresponding vertices agrees to 1e-4. Fragment vertices are rounded to doubles (ulp 1e-9 m at 5e6 m), and
  // a vertex on a contact edge takes its value at most max(1e-6 of its shorter edge, 6e-5 m)
  // inside the fragment there: the values at corresponding vertices agree to 1e-4 (they
  // differed by up to 0.5 when that step was 1e-7 of the coordinates, 0.5 m).
  const dvec3 offset(500000, 5000000, 0);
  double worst = 0.0, worst_e = 0.0;
  std::size_t compared = 0;
  shadow::ShadowOptions options;
  options.threads = 2;
  auto lights = [](dvec3 o) {
    Light area = square_light(3, 5);
    for (dvec3& p : area.polygon) p += o;
    Light disk = disk_light(3, 5);
    disk.position += o;
    Light s = sun({0.5, 0.3, 1}, 5.0);
    for (Light* l : {&area, &disk, &s}) l->intensity = 100;
    return std::vector<Light>{area, disk, s};
  };
  Scene near = diamond_scene(dvec3(0.0));
  near.lights = lights(dvec3(0.0));
  Scene far = diamond_scene(offset);
  far.lights = lights(offset);
  const shadow::ShadowResult a = shadow::compute_shadows(near, options);
  const shadow::ShadowResult b = shadow::compute_shadows(far, options);
  std::vector<bool> used(b.fragments.size(), false);
  std::size_t matched[3] = {0, 0, 0};
  for (const shadow::Fragment& f : a.fragments) {
    bool found = false;
    for (std::size_t k = 0; k < b.fragments.size() && !found; ++k) {
      const shadow::Fragment& g = b.fragments[k];
      if (used[k] || g.face_id != f.face_id || g.light_id != f.light_id || g.polygon.size() != f.polygon.size())
        continue;
      bool same = true;
      for (std::size_t i = 0; i < f.polygon.size() && same; ++i)
        same = glm::length(g.polygon[i] - offset - f.polygon[i]) < 1e-6;
      if (!same) continue;
      found = used[k] = true;
      ASSERT_EQ(f.visibility.size(), f.polygon.size());
      ASSERT_EQ(g.visibility.size(), g.polygon.size());
      for (std::size_t i = 0; i < f.polygon.size(); ++i, ++compared) {
        worst = std::max(worst, std::abs(f.visibility[i] - g.visibility[i]));
        worst_e = std::max(worst_e, std::abs(f.irradiance[i] - g.irradiance[i]) / 100.0);
        EXPECT_NEAR(f.visibility[i], g.visibility[i], 1e-4)
            << "light " << f.light_id << " face " << f.face_id << " at " << f.polygon[i].x << " " << f.polygon[i].y
            << " " << f.polygon[i].z;
      }
    }
    // Cells are compared where they have a twin (same face, light and vertices to 1e-6): the
    // disk's regions come from its circumscribed polygon, built in doubles around its centre, and
    // a cell's rounded vertices may differ in number, so not every cell has one.
    if (found) ++matched[f.light_id];
  }
  EXPECT_GT(compared, 50u);
  for (std::size_t l = 0; l < 3; ++l) EXPECT_GT(matched[l], 0u) << l;
  EXPECT_LE(worst_e, 1e-4);

  // A vertex on a wall's foot at (1/3, 1/3): exactly on the wall x = y at the origin (both
  // coordinates round alike), a rounding error off it at (500 km, 5,000 km). The light straddles
  // the wall, so the value changes with the distance from it: the two must still agree.
  for (const Light& light : lights(dvec3(0.0))) {
    SCOPED_TRACE(light.type == LightType::Area ? "area" : light.type == LightType::Disk ? "disk" : "sun");
    double values[2][3];
    for (int far_away = 0; far_away < 2; ++far_away) {
      const dvec3 o = far_away ? offset : dvec3(0.0);
      Scene scene;
      add_face(scene, rect_z(-5, 5, -5, 5, 0));
      for (dvec3& p : scene.faces[0].vertices) p += o;
      add_face(scene, {dvec3(-3, -3, 0) + o, dvec3(3, 3, 0) + o, dvec3(3, 3, 3) + o, dvec3(-3, -3, 3) + o});
      Light l = lights(o)[light.type == LightType::Area ? 0 : light.type == LightType::Disk ? 1 : 2];
      const double t = 1.0 / 3.0;
      std::vector<shadow::Fragment> cell{
          fragment_on(0, {dvec3(o.x + t, o.y + t, 0), dvec3(o.x + t + 2, o.y + t - 1, 0), dvec3(o.x + t + 2, o.y + t, 0)})};
      if (far_away) EXPECT_NE(cell[0].polygon[0].x - o.x, cell[0].polygon[0].y - o.y);  // off the wall's plane
      shadow::fill_fragment_visibility(scene, l, cell, 1);
      for (int i = 0; i < 3; ++i) values[far_away][i] = cell[0].visibility[i];
    }
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(values[1][i], values[0][i], 1e-4) << i;
    if (light.type != LightType::Directional) {
      EXPECT_GT(values[0][0], 0.0);
      EXPECT_LT(values[0][0], values[0][2]);  // the wall hides more of the light near it
    }
  }
  std::cout << "georeferenced vs origin: " << compared << " vertices, largest difference " << worst
            << " (visibility), " << worst_e << " (irradiance / intensity)\n";
}

TEST(FragmentVisibility, WriterKeepsTheEnginesIrradiance) {
  // The irradiance of an extended light's fragments is computed with their visibility in the
  // engine's pass (on the caller's threads) and written as it is: the VTK writer does not
  // compute it again. Marked values in the result come out in fragments.vtp unchanged.
  Scene scene = box_scene();
  scene.lights = {square_light(3, 5), sun({0.5, 0.3, 1}, 0.0)};
  shadow::ShadowOptions options;
  options.threads = 1;
  shadow::ShadowResult result = shadow::compute_shadows(scene, options);
  // The engine's values: those of light_irradiance at the vertices, off contact edges.
  for (const shadow::Fragment& f : result.fragments) {
    if (f.light_id != 0) {
      EXPECT_TRUE(f.irradiance.empty());
      continue;
    }
    ASSERT_EQ(f.irradiance.size(), f.polygon.size());
    std::vector<SurfacePoint> points;
    for (const dvec3& p : f.polygon) points.push_back({f.face_id, p});
    const std::vector<double> e = shadow::light_irradiance(scene, scene.lights[0], points, 1);
    for (std::size_t i = 0; i < points.size(); ++i)
      if (!on_box_foot(f.face_id, f.polygon[i])) EXPECT_EQ(f.irradiance[i], e[i]);
  }
  double mark = 1000.0;
  for (shadow::Fragment& f : result.fragments)
    for (double& e : f.irradiance) e = mark++;
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "libshadow_test_writer_irradiance";
  std::filesystem::remove_all(dir);
  shadow::write_outputs(dir, scene, result);
  const auto poly = read_vtp(dir / "fragments.vtp");
  vtkDataArray* irradiance = poly->GetPointData()->GetArray("irradiance");
  ASSERT_NE(irradiance, nullptr);
  vtkIdType point = 0;
  for (const shadow::Fragment& f : result.fragments)
    for (std::size_t i = 0; i < f.polygon.size(); ++i, ++point)
      if (f.light_id == 0) EXPECT_EQ(irradiance->GetTuple1(point), f.irradiance[i]);
  std::filesystem::remove_all(dir);
}

/// Integral of cos cos' / r^2 over the rectangle y in [0, b], z in [z0, z1] of the plane x = c,
/// seen from the origin with normal +z (perpendicular rectangles, one edge of the rectangle's
/// span along the receiver's normal): Lambert's contour in closed form, G(z1) - G(z0) with
/// G(h) = (1/2) (atan(b/c) - c / sqrt(c^2 + h^2) atan(b / sqrt(c^2 + h^2))), G(0) = 0.
double perpendicular_integral(double b, double c, double z0, double z1) {
  auto g = [&](double h) {
    const double r = std::sqrt(c * c + h * h);
    return 0.5 * (std::atan(b / c) - c / r * std::atan(b / r));
  };
  return g(z1) - g(z0);
}

TEST(LightIrradiance, TiltedReceiverAgainstPerpendicularRectangles) {
  // A receiver tilted 20 degrees about y, and a rectangular light perpendicular to it
  // (x = +-1.5 in the receiver's frame, y in [-1, 2], z in [0.5, 2.5]), facing the point: once
  // with its normal's dominant (dropped) axis negative, once positive. Radiance 2.
  const double theta = 20.0 * kPi / 180.0, cs = std::cos(theta), sn = std::sin(theta);
  auto rot = [&](dvec3 p) { return dvec3(p.x * cs + p.z * sn, p.y, -p.x * sn + p.z * cs); };
  Scene scene;
  std::vector<dvec3> receiver = rect_z(-0.5, 0.5, -0.5, 0.5, 0);
  for (dvec3& p : receiver) p = rot(p);
  add_face(scene, receiver);
  const double expected = 2.0 * (perpendicular_integral(2, 1.5, 0.5, 2.5) + perpendicular_integral(1, 1.5, 0.5, 2.5));
  for (const double side : {1.0, -1.0}) {
    SCOPED_TRACE(side);
    Light light;
    light.type = LightType::Area;
    light.intensity = 2.0;
    // Facing -x (side 1) or +x (side -1) in the receiver's frame.
    light.polygon = {{1.5, -1, 0.5}, {1.5, -1, 2.5}, {1.5, 2, 2.5}, {1.5, 2, 0.5}};
    for (dvec3& p : light.polygon) p = rot(dvec3(side * p.x, p.y, p.z));
    if (side < 0) std::reverse(light.polygon.begin(), light.polygon.end());
    const dvec3 n = glm::cross(light.polygon[1] - light.polygon[0], light.polygon[2] - light.polygon[1]);
    EXPECT_GT(std::abs(n.x), std::max(std::abs(n.y), std::abs(n.z)));
    EXPECT_EQ(n.x > 0, side < 0);  // the chart's dropped axis is x, with this sign
    const auto e = shadow::light_irradiance(scene, light, {SurfacePoint{0, {0, 0, 0}}}, 1);
    EXPECT_NEAR(e[0], expected, 1e-13 * expected);
    // Independently: a midpoint sum of cos cos' / r^2 over the light (400 x 400 cells).
    const dvec3 nr = rot({0, 0, 1}), nl = glm::normalize(n);
    double sum = 0.0;
    const int cells = 400;
    for (int i = 0; i < cells; ++i)
      for (int j = 0; j < cells; ++j) {
        const dvec3 y = rot({side * 1.5, -1 + 3.0 * (i + 0.5) / cells, 0.5 + 2.0 * (j + 0.5) / cells});
        const double r2 = glm::dot(y, y);
        sum += glm::dot(nr, y) * -glm::dot(nl, y) / (r2 * r2) * (3.0 * 2.0 / (cells * cells));
      }
    EXPECT_NEAR(2.0 * sum, expected, 1e-5 * expected);
  }
}

}  // namespace
