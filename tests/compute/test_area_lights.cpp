// SPDX-License-Identifier: GPL-3.0-or-later
// Extended lights (docs/area-lights.md): scene input and its errors, the exact fully-lit,
// penumbra and umbra regions against closed forms, against exact point queries from sampled
// light points (libshadow::testing), and the two exact routes against each other.
#include "arealight/area_receiver.hpp"  // force_separating_planes (tests only)
#include "arealight/light_shape.hpp"    // the sun disk's 32-gon (a direction parallel to a face)
#include "support/scene_builders.hpp"

#include <shadow/shadow.hpp>
#include <shadow/testing.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

namespace shadow::test {
namespace {

constexpr double kPi = 3.14159265358979323846;

Light area_light(const std::string& name, std::vector<glm::dvec3> polygon) {
  Light light;
  light.name = name;
  light.type = LightType::Area;
  light.polygon = std::move(polygon);
  return light;
}

Light disk_light(const std::string& name, glm::dvec3 centre, glm::dvec3 normal, double radius) {
  Light light;
  light.name = name;
  light.type = LightType::Disk;
  light.position = centre;
  light.normal = normal;
  light.radius = radius;
  return light;
}

Light sun_disk(const std::string& name, glm::dvec3 to_light, double degrees) {
  Light light = directional_light(name, to_light);
  light.angular_diameter = degrees;
  return light;
}

/// A square light of side a at height H facing down, centred over the origin.
Light square_light(double a, double H) {
  return area_light("lum", {{-a / 2, -a / 2, H}, {-a / 2, a / 2, H}, {a / 2, a / 2, H}, {a / 2, -a / 2, H}});
}

ShadowResult compute(Scene& scene, unsigned threads = 1, bool polygons = true) {
  validate_scene(scene);
  ShadowOptions options;
  options.threads = threads;
  options.polygons = polygons;
  return compute_shadows(scene, options);
}

// ---- closed forms ------------------------------------------------------------------------------

// A square light (side a, height H) over a parallel square occluder (side b, height h) over the
// ground: from each light vertex the occluder casts a square of side b s (s = H / (H - h)) moved
// by -v t (t = h / (H - h)); the hull of the four is a square of side b s + a t, their
// intersection one of side b s - a t (when positive).
TEST(AreaLightRegions, SquareLightOverParallelSquareMatchesTheClosedForm) {
  struct Case {
    double a, H, b, h;
  };
  for (const Case& c : {Case{1, 4, 2, 2}, Case{0.5, 3, 1, 1}, Case{2, 4, 1, 2}, Case{0.25, 8, 0.75, 3}}) {
    Scene scene;
    add_mesh(scene, "ground", {rectangle_z(-20, -20, 20, 20, 0)});
    add_mesh(scene, "occluder", {rectangle_z(-c.b / 2, -c.b / 2, c.b / 2, c.b / 2, c.h)});
    scene.lights.push_back(square_light(c.a, c.H));
    const ShadowResult r = compute(scene);
    const FaceLighting* ground = r.find(0, 0);
    ASSERT_NE(ground, nullptr);
    const double s = c.H / (c.H - c.h), t = c.h / (c.H - c.h);
    const double outer = c.b * s + c.a * t, inner = std::max(0.0, c.b * s - c.a * t);
    SCOPED_TRACE("a " + std::to_string(c.a) + " b " + std::to_string(c.b));
    EXPECT_NEAR(ground->fully_lit_area, 1600 - outer * outer, 1e-12);
    EXPECT_NEAR(ground->umbra_area, inner * inner, 1e-12);
    EXPECT_NEAR(ground->penumbra_area, outer * outer - inner * inner, 1e-12);
    // The light's centre: a point light there casts the square scaled by s.
    EXPECT_NEAR(ground->shadow_area, (c.b * s) * (c.b * s), 1e-12);
    EXPECT_EQ(r.stats.area_umbra_bounded, 0u);
    // The cells: one region each, adding up; lit means fully lit or penumbra.
    double cells[3] = {0, 0, 0};
    for (const Fragment& f : r.fragments) {
      if (f.face_id != 0) continue;
      ASSERT_NE(f.region, LightRegion::Hard);
      EXPECT_EQ(f.lit, f.region != LightRegion::Umbra);
      // The visible fraction at the cell's vertices (light_visibility.cpp, an independent exact
      // route) agrees with its region: 1 on fully lit cells, 0 on umbra cells.
      ASSERT_EQ(f.visibility.size(), f.polygon.size());
      for (double v : f.visibility) {
        if (f.region == LightRegion::FullyLit) EXPECT_EQ(v, 1.0);
        if (f.region == LightRegion::Umbra) EXPECT_EQ(v, 0.0);
        EXPECT_GE(v, 0.0);
        EXPECT_LE(v, 1.0);
      }
      cells[static_cast<int>(f.region)] += f.area;
    }
    EXPECT_NEAR(cells[0], ground->fully_lit_area, 1e-12);
    EXPECT_NEAR(cells[1], ground->penumbra_area, 1e-12);
    EXPECT_NEAR(cells[2], ground->umbra_area, 1e-12);
    EXPECT_TRUE(testing::check_partition(scene, r)) << testing::check_partition(scene, r).message;
  }
}

// The sun's disk over a long thick wall, the sun square to it at elevation e: the top edge casts
// a penumbra band of width H (cot(e - a) - cot(e + a)), about H x angular diameter / sin^2 e, where
// a is the angular radius; the 32-gon circumscribed about the disk reaches between a and
// a / cos(pi / 32) in that plane.
TEST(AreaLightRegions, SunDiskOverALongWallCastsAPenumbraOfHeightTimesAngularDiameter) {
  const double H = 30, e = 45 * kPi / 180, degrees = 0.53, a = degrees * kPi / 360;
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-100, -10, 100, 200, 0)});
  add_mesh(scene, "wall", box_faces({-1000, 0, 0}, {1000, 0.25, H}));
  scene.lights.push_back(sun_disk("sun", {0, -std::cos(e), std::sin(e)}, degrees));
  const ShadowResult r = compute(scene, 2, false);
  const FaceLighting* ground = r.find(0, 0);
  ASSERT_NE(ground, nullptr);
  auto width = [&](double alpha) { return H / std::tan(e - alpha) - H / std::tan(e + alpha); };
  const double low = width(a), high = width(a / std::cos(kPi / 32));
  const double band = ground->penumbra_area / 200;
  EXPECT_GE(band, low * (1 - 1e-9));
  EXPECT_LE(band, high * (1 + 1e-9));
  // to first order in the angle (the rest, and the 32-gon, are under 1 %)
  EXPECT_NEAR(band, H * (degrees * kPi / 180) / (std::sin(e) * std::sin(e)), 1e-2 * band);
  // Umbra: under the wall and up to the inner edge of the band; fully lit: beyond it.
  const double umbra = ground->umbra_area / 200;
  EXPECT_GE(umbra, 0.25 + H / std::tan(e + a / std::cos(kPi / 32)) - 1e-9);
  EXPECT_LE(umbra, 0.25 + H / std::tan(e + a) + 1e-9);
  EXPECT_NEAR(ground->fully_lit_area + ground->penumbra_area + ground->umbra_area, ground->area, 1e-9);
  // lit_area is the point sun's: its shadow ends at 0.25 + H / tan(e).
  EXPECT_NEAR(ground->shadow_area / 200, 0.25 + H / std::tan(e), 1e-9);
}

// ---- special cases -----------------------------------------------------------------------------

TEST(AreaLightRegions, FacesBehindTheLightAreUmbraAndACrossingLightLeavesNothingFullyLit) {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  // a wall through the light's middle (x = 0, facing +x) and one wholly behind the light
  add_mesh(scene, "walls",
           {{{0, -1, 0.5}, {0, 1, 0.5}, {0, 1, 1.5}, {0, -1, 1.5}},
            {{-1, -1, 4}, {1, -1, 4}, {1, 1, 4}, {-1, 1, 4}}});
  scene.lights.push_back(square_light(1, 3));
  const ShadowResult r = compute(scene);
  const FaceLighting* crossing = r.find(1, 0);
  ASSERT_NE(crossing, nullptr);
  EXPECT_EQ(crossing->fully_lit_area, 0.0);
  EXPECT_EQ(crossing->penumbra_area, crossing->area);  // nothing hides the part it sees
  EXPECT_GE(r.stats.area_light_straddles, 1u);
  const FaceLighting* above = r.find(2, 0);  // above the light, which shines down
  ASSERT_NE(above, nullptr);
  EXPECT_EQ(above->umbra_area, above->area);
  // The ground: the crossing wall stands on x = 0 and hides part of the light from both sides.
  const FaceLighting* ground = r.find(0, 0);
  EXPECT_GT(ground->penumbra_area, 0.0);
  EXPECT_TRUE(testing::check_partition(scene, r)) << testing::check_partition(scene, r).message;
}

// A light shines forward only, from its centre as from the rest of it: a wall facing a panel that
// hangs at z = 2 and shines down is umbra above the panel's plane, and lit_area (the centre's)
// must say so too (it once reported the whole wall lit, with 10 m^2 of umbra).
TEST(AreaLightRegions, AWallAboveADownwardPanelIsDarkAboveThePanelsPlane) {
  for (const bool disk : {false, true}) {
    Scene scene;
    // a 10 x 3 m wall in y = 0, facing +y (counter-clockwise seen from +y)
    add_mesh(scene, "wall", {{{-5, 0, 0}, {-5, 0, 3}, {5, 0, 3}, {5, 0, 0}}});
    scene.lights.push_back(disk ? disk_light("disk", {0, 2, 2}, {0, 0, -1}, 1)
                                : area_light("panel", {{-1, 1, 2}, {-1, 3, 2}, {1, 3, 2}, {1, 1, 2}}));
    for (const bool polygons : {true, false}) {
      const ShadowResult r = compute(scene, 2, polygons);
      const FaceLighting* wall = r.find(0, 0);
      ASSERT_NE(wall, nullptr);
      EXPECT_EQ(wall->area, 30.0);
      EXPECT_EQ(wall->umbra_area, 10.0) << (disk ? "disk" : "panel");
      EXPECT_EQ(wall->shadow_area, 10.0) << (disk ? "disk" : "panel");
      EXPECT_EQ(wall->lit_area, 20.0) << (disk ? "disk" : "panel");
      EXPECT_EQ(wall->lit_fraction, 2.0 / 3.0);
      EXPECT_EQ(r.stats.area_centre_behind, 1u);
      if (polygons) EXPECT_TRUE(testing::check_partition(scene, r)) << testing::check_partition(scene, r).message;
    }
    // The fast path's centre is cut the same way (exactly, its bound then 0).
    ShadowOptions fast;
    fast.arithmetic = Arithmetic::Fast;
    fast.polygons = false;
    const ShadowResult f = compute_shadows(scene, fast);
    EXPECT_EQ(f.find(0, 0)->lit_area, 20.0);
    // A series of the light gives the same lit area as compute().
    const ShadowEngine engine(scene, 2);
    const SeriesResult series = engine.compute_series({scene.lights[0]});
    EXPECT_EQ(series.lit_area[0], 20.0);
    EXPECT_EQ(series.lit_fraction[0], 2.0 / 3.0);
    // Wholly behind: a wall above the panel.
    Scene high;
    add_mesh(high, "wall", {{{-5, 0, 2.5}, {-5, 0, 5.5}, {5, 0, 5.5}, {5, 0, 2.5}}});
    high.lights = scene.lights;
    const ShadowResult above = compute(high, 1, false);
    EXPECT_EQ(above.find(0, 0)->lit_area, 0.0);
    EXPECT_EQ(above.find(0, 0)->umbra_area, 30.0);
  }
}

// A face lying in the receiver's plane (the back face of a double-sided floor) casts nothing on
// it (docs/algorithm.md section 2), under an area light and under the sun's disk alike.
TEST(AreaLightRegions, ACoincidentBackFacingQuadLeavesTheReceiverFullyLit) {
  for (const Light& light : {square_light(1, 3), sun_disk("sun", {0.3, 0.2, 1}, 0.53)}) {
    Scene scene;
    add_mesh(scene, "floor", {rectangle_z(-2, -2, 2, 2, 0)});
    std::vector<glm::dvec3> back = rectangle_z(-1, -1, 1, 1, 0);
    std::reverse(back.begin(), back.end());  // facing down, in the floor's plane
    add_mesh(scene, "underside", {back});
    scene.lights.push_back(light);
    const ShadowResult r = compute(scene);
    const FaceLighting* floor = r.find(0, 0);
    ASSERT_NE(floor, nullptr);
    SCOPED_TRACE(light.name);
    EXPECT_EQ(floor->fully_lit_area, floor->area);
    EXPECT_EQ(floor->penumbra_area, 0.0);
    EXPECT_EQ(floor->umbra_area, 0.0);
    EXPECT_LE(floor->umbra_area, floor->shadow_area);
    EXPECT_LE(floor->fully_lit_area, floor->lit_area);
    EXPECT_TRUE(testing::check_partition(scene, r)) << testing::check_partition(scene, r).message;
  }
}

// A direction of the sun disk's 32-gon exactly parallel to the receiver's plane (s = 0): it has
// no shadow on the plane, so the projection route does not apply (it divided by zero); the
// separating planes give the regions. The sun straight up: the 32-gon's vertex 0 is (0, -r, 1)
// exactly, and the wall y + r z = 0 contains it while every other direction is in its front.
TEST(AreaLightRegions, ASunDiskDirectionParallelToTheReceiverTakesTheSeparatingRoute) {
  const Light sun = sun_disk("sun", {0, 0, 1}, 0.53);
  const arealight::LightShape shape = arealight::light_shape(sun);
  const double r = -shape.polygon[0].y;
  ASSERT_EQ(shape.polygon[0], glm::dvec3(0, -r, 1));
  for (std::size_t i = 1; i < shape.polygon.size(); ++i) ASSERT_GT(shape.polygon[i].y + r * shape.polygon[i].z, 0.0);
  Scene scene;
  // the wall y + r z = 0 facing (0, 1, r), and a roof over it
  add_mesh(scene, "wall", {{{-1, 0, 0}, {-1, -r, 1}, {1, -r, 1}, {1, 0, 0}}});
  add_mesh(scene, "roof", {rectangle_z(-0.5, -0.01, 0.5, 0.2, 1.5)});
  scene.lights.push_back(sun);
  const ShadowResult r1 = compute(scene, 1, false);
  const FaceLighting* wall = r1.find(0, 0);
  ASSERT_NE(wall, nullptr);
  EXPECT_NEAR(wall->fully_lit_area + wall->penumbra_area + wall->umbra_area, wall->area, 1e-12);
  // Under the roof's middle every direction of the half of the cone in front of the wall meets
  // the roof: umbra; the wall's ends beyond the roof's reach are lit by part of the sun.
  EXPECT_GT(wall->umbra_area, 0.0);
  EXPECT_GT(wall->fully_lit_area + wall->penumbra_area, 0.0);
  EXPECT_GT(wall->fully_lit_area, 0.0);  // the grazing direction is seen along the wall
  // The same regions with every piece on the separating route.
  arealight::force_separating_planes = true;
  const ShadowResult r2 = compute(scene, 1, false);
  arealight::force_separating_planes = false;
  EXPECT_EQ(r2.find(0, 0)->umbra_area, wall->umbra_area);
  EXPECT_EQ(r2.find(0, 0)->penumbra_area, wall->penumbra_area);
}

// lit_area is the point light's at the centre, bit for bit; shrinking the light shrinks the
// penumbra onto that point light's shadow boundary.
TEST(AreaLightRegions, ShrinkingTheLightGivesBackThePointLight) {
  Scene point_scene;
  add_mesh(point_scene, "ground", {rectangle_z(-20, -20, 20, 20, 0)});
  add_mesh(point_scene, "boxes", box_faces({-1, -0.5, 1}, {1.5, 0.75, 2}));
  point_scene.lights.push_back(point_light("p", {0.25, 0.125, 5}));
  const ShadowResult point = compute(point_scene);
  for (double size : {1.0, 1e-3, 1e-6}) {
    Scene scene = point_scene;
    const double h = size / 2;
    scene.lights[0] = area_light("lum", {{0.25 - h, 0.125 - h, 5}, {0.25 - h, 0.125 + h, 5}, {0.25 + h, 0.125 + h, 5},
                                         {0.25 + h, 0.125 - h, 5}});
    const ShadowResult r = compute(scene);
    for (const FaceLighting& fl : r.lighting) {
      const FaceLighting* p = point.find(fl.face_id, 0);
      ASSERT_NE(p, nullptr);
      EXPECT_EQ(fl.lit_area, p->lit_area);
      EXPECT_EQ(fl.shadow_area, p->shadow_area);
      EXPECT_EQ(fl.lit_fraction, p->lit_fraction);
      // The centre is a point of the light: seeing all of the light means seeing it, seeing
      // none of it means not.
      EXPECT_LE(fl.fully_lit_area, p->lit_area + 1e-12);
      EXPECT_LE(fl.umbra_area, p->shadow_area + 1e-12);
      // The penumbra's width is of the order of the light's size.
      EXPECT_LE(fl.penumbra_area, 40 * size + 1e-12) << "face " << fl.face_id << " size " << size;
    }
  }
}

// ---- properties against exact point queries ----------------------------------------------------

/// Seeded points of the extended light (for a sun disk: directions) and the lights they make.
std::vector<Light> sample_lights(const Light& light, std::mt19937_64& rng, int count) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Light> out;
  if (light.type == LightType::Area) {
    for (const glm::dvec3& v : light.polygon) out.push_back(point_light("v", v));
    const glm::dvec3& a = light.polygon[0];
    for (int i = 0; i < count; ++i) {  // in the fan triangles of a convex polygon
      const std::size_t t = 1 + static_cast<std::size_t>(unit(rng) * (light.polygon.size() - 2));
      double u = unit(rng), v = unit(rng);
      if (u + v > 1) u = 1 - u, v = 1 - v;
      out.push_back(point_light("s", a + u * (light.polygon[t] - a) + v * (light.polygon[t + 1] - a)));
    }
    return out;
  }
  const glm::dvec3 n = glm::normalize(light.type == LightType::Disk ? light.normal : light.to_light);
  const glm::dvec3 u = glm::normalize(glm::cross(n, std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
  const glm::dvec3 v = glm::cross(n, u);
  const double radius =
      light.type == LightType::Disk ? light.radius : std::tan(light.angular_diameter * kPi / 360);
  for (int i = 0; i < count + 8; ++i) {
    // the rim (8 points) and the inside, a hair within the disk
    const double angle = 2 * kPi * unit(rng);
    const double r = (i < 8 ? 1.0 : std::sqrt(unit(rng))) * radius * (1 - 1e-7);
    const glm::dvec3 offset = r * (std::cos(angle) * u + std::sin(angle) * v);
    if (light.type == LightType::Disk)
      out.push_back(point_light("s", light.position + offset));
    else
      out.push_back(directional_light("s", n + offset));
  }
  return out;
}

/// Fully lit cells see every sampled light point, umbra cells none (exact point queries).
void check_regions_against_samples(const Scene& scene, const ShadowResult& r, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const std::vector<Light> samples = sample_lights(scene.lights[0], rng, 6);
  Scene probe = scene;
  for (const Light& l : samples) probe.lights.push_back(l);
  for (std::size_t s = 0; s < samples.size(); ++s) {
    ShadowResult claims;
    for (const Fragment& f : r.fragments) {
      if (f.region == LightRegion::Penumbra) continue;
      Fragment claim = f;
      claim.light_id = 1 + s;
      claims.fragments.push_back(claim);
    }
    if (claims.fragments.empty()) continue;
    const testing::Verdict verdict = testing::check_lit_claims(probe, claims, seed + s, 2);
    EXPECT_TRUE(verdict.ok) << "seed " << seed << " light sample " << s << ": " << verdict.message;
  }
}

Light random_extended_light(std::mt19937_64& rng, int kind) {
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  if (kind == 0) {  // a tilted rectangle over the scene, facing down
    const glm::dvec3 c(3 * U(rng), 3 * U(rng), 15 + U(rng));
    const glm::dvec3 a(1.5 + U(rng), 0.3 * U(rng), 0.5 * U(rng)), b(0.3 * U(rng), 1 + 0.5 * U(rng), 0.5 * U(rng));
    return area_light("lum", {c - a - b, c - a + b, c + a + b, c + a - b});  // counter-clockwise seen from below
  }
  if (kind == 1)
    return disk_light("disk", {3 * U(rng), 3 * U(rng), 16 + U(rng)}, {0.2 * U(rng), 0.2 * U(rng), -1}, 1 + 0.5 * U(rng));
  return sun_disk("sun", {U(rng), U(rng), 1.5 + U(rng) * 0.5}, 4 + 2 * U(rng));
}

TEST(AreaLightProperties, RegionsAgreeWithExactPointQueriesFromSampledLightPoints) {
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    Scene scene = random_scene(seed);
    std::mt19937_64 rng(seed * 7919);
    scene.lights.assign(1, random_extended_light(rng, static_cast<int>(seed % 3)));
    const ShadowResult r = compute(scene, 2);
    const testing::Verdict partition = testing::check_partition(scene, r);
    EXPECT_TRUE(partition.ok) << "seed " << seed << ": " << partition.message;
    for (const FaceLighting& fl : r.lighting) {
      EXPECT_GE(fl.fully_lit_area, 0.0);
      EXPECT_GE(fl.penumbra_area, 0.0);
      EXPECT_GE(fl.umbra_area, 0.0);
      EXPECT_LE(fl.fully_lit_area, fl.lit_area + 1e-9 * (1 + fl.area)) << "seed " << seed;
      EXPECT_LE(fl.umbra_area, fl.shadow_area + 1e-9 * (1 + fl.area)) << "seed " << seed;
    }
    check_regions_against_samples(scene, r, seed);
  }
}

// Lights among the geometry, facing any way, so that faces lie behind them or cross their plane:
// the documented inequalities hold exactly (both sides are exact values rounded once, and
// rounding keeps order), in the exact engine, and with the fast path's lit areas within bounds.
TEST(AreaLightProperties, LitAndShadowAreasBoundTheRegionsForLightsFacingAnyWay) {
  std::uint64_t behind = 0;
  for (std::uint64_t seed = 11; seed <= 22; ++seed) {
    Scene scene = random_scene(seed);
    std::mt19937_64 rng(seed * 104729);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    const glm::dvec3 c(3 * U(rng), 3 * U(rng), 1.5 + U(rng));
    const glm::dvec3 n = glm::normalize(glm::dvec3(U(rng), U(rng), U(rng)) + glm::dvec3(0, 0, 1e-3));
    const glm::dvec3 a = 0.7 * glm::normalize(glm::cross(n, glm::dvec3(0.3, 0.5, 0.8)));
    const glm::dvec3 b = glm::cross(n, a);  // a, b, n right-handed: a, b, -a, -b runs counter-clockwise seen from n
    scene.lights.assign(1, seed % 2 ? disk_light("disk", c, n, 0.6)
                                    : area_light("lum", {c + a, c + b, c - a, c - b}));
    const ShadowResult r = compute(scene, 2, seed % 4 < 2);
    behind += r.stats.area_centre_behind;
    for (const FaceLighting& fl : r.lighting) {
      EXPECT_LE(fl.fully_lit_area, fl.lit_area) << "seed " << seed << " face " << fl.face_id;
      EXPECT_LE(fl.umbra_area, fl.shadow_area) << "seed " << seed << " face " << fl.face_id;
    }
    ShadowOptions fast;
    fast.arithmetic = Arithmetic::Fast;
    fast.polygons = false;
    const ShadowResult f = compute_shadows(scene, fast);
    ASSERT_EQ(f.lighting.size(), r.lighting.size());
    for (std::size_t i = 0; i < f.lighting.size(); ++i)
      EXPECT_LE(std::abs(f.lighting[i].lit_area - r.lighting[i].lit_area), f.lighting[i].lit_area_error_bound)
          << "seed " << seed << " face " << f.lighting[i].face_id;
  }
  EXPECT_GT(behind, 20u);  // the scenes did put faces behind the lights
}

// The projection route and the separating-plane route compute the same not-fully-lit set: equal
// fully lit areas, rounded from the same exact values.
// A closed convex box is one convex occluder: its umbra is exact (not a union of its faces',
// which is inside it), and checked by exact point queries.
TEST(AreaLightProperties, AConvexSolidCastsAsOneOccluder) {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-20, -20, 20, 20, 0)});
  add_mesh(scene, "box", box_faces({-1, -1, 0.9}, {1, 1, 3}));
  scene.lights.push_back(square_light(0.5, 5));
  const ShadowResult whole = compute(scene);
  EXPECT_EQ(whole.stats.area_umbra_bounded, 0u);
  arealight::force_separating_planes = true;  // faces one by one
  const ShadowResult faces = compute(scene);
  arealight::force_separating_planes = false;
  const FaceLighting *a = whole.find(0, 0), *b = faces.find(0, 0);
  EXPECT_EQ(a->fully_lit_area, b->fully_lit_area);
  // Here the top face's umbra is the box's (b s - a t)^2 with s = 5 / 2, t = 3 / 2, b = 2, a = 0.5.
  EXPECT_GE(a->umbra_area, b->umbra_area);
  EXPECT_NEAR(a->umbra_area, 4.25 * 4.25, 1e-12);
  EXPECT_GT(faces.stats.area_umbra_bounded, 0u);
  check_regions_against_samples(scene, whole, 77);
}

TEST(AreaLightProperties, ProjectionAndSeparatingPlaneRoutesAgree) {
  for (std::uint64_t seed = 11; seed <= 14; ++seed) {
    Scene scene = random_scene(seed);
    std::mt19937_64 rng(seed * 104729);
    scene.lights.assign(1, random_extended_light(rng, static_cast<int>(seed % 3)));
    const ShadowResult by_projection = compute(scene, 2, false);
    arealight::force_separating_planes = true;
    const ShadowResult by_planes = compute(scene, 2, false);
    arealight::force_separating_planes = false;
    EXPECT_GT(by_projection.stats.area_projection_pieces, 0u);
    EXPECT_EQ(by_planes.stats.area_projection_pieces, 0u);
    ASSERT_EQ(by_projection.lighting.size(), by_planes.lighting.size());
    for (std::size_t i = 0; i < by_planes.lighting.size(); ++i) {
      const FaceLighting &a = by_projection.lighting[i], &b = by_planes.lighting[i];
      EXPECT_EQ(a.fully_lit_area, b.fully_lit_area) << "seed " << seed << " face " << a.face_id;
      // The separating route takes a convex solid face by face: its umbra is the union of its
      // faces' umbras, inside the solid's own (which the projection route computes whole).
      EXPECT_LE(b.umbra_area, a.umbra_area + 1e-12 * (1 + a.area)) << "seed " << seed << " face " << a.face_id;
      EXPECT_NEAR(a.penumbra_area + a.umbra_area, b.penumbra_area + b.umbra_area, 1e-12 * (1 + a.area));
    }
  }
}

TEST(AreaLightProperties, ResultsDoNotDependOnThreadsOrEntryPoint) {
  Scene scene = random_scene(42);
  std::mt19937_64 rng(42);
  scene.lights.assign(1, random_extended_light(rng, 0));
  const ShadowResult one = compute(scene, 1);
  const ShadowResult two = compute(scene, 2);
  const ShadowEngine engine(scene, 2);
  const ShadowResult via_engine = engine.compute(scene.lights[0], 0, {});
  ASSERT_EQ(one.lighting.size(), two.lighting.size());
  ASSERT_EQ(one.lighting.size(), via_engine.lighting.size());
  for (std::size_t i = 0; i < one.lighting.size(); ++i)
    for (const ShadowResult* other : {&two, &via_engine}) {
      EXPECT_EQ(one.lighting[i].fully_lit_area, other->lighting[i].fully_lit_area);
      EXPECT_EQ(one.lighting[i].penumbra_area, other->lighting[i].penumbra_area);
      EXPECT_EQ(one.lighting[i].umbra_area, other->lighting[i].umbra_area);
      EXPECT_EQ(one.lighting[i].lit_area, other->lighting[i].lit_area);
    }
  EXPECT_EQ(one.fragments.size(), two.fragments.size());
  // A series of sun disks keeps the point suns' lit areas.
  Scene sunny = random_scene(43);
  const ShadowEngine sunny_engine(sunny, 2);
  const Light point_sun = directional_light("sun", {0.3, -0.4, 1});
  const SeriesResult plain = sunny_engine.compute_series({point_sun});
  const SeriesResult disk = sunny_engine.compute_series({sun_disk("sun", {0.3, -0.4, 1}, 0.53)});
  EXPECT_EQ(plain.lit_area, disk.lit_area);
}

// ---- scene input -------------------------------------------------------------------------------

std::string scene_with_light(const std::string& light) {
  return R"({"meshes": [{"name": "g", "polygons": [{"vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]]}]}], "lights": [)" + light + "]}";
}

TEST(AreaLightInput, ReadsAreaDiskAndSunDiskLights) {
  const Scene scene = parse_scene(
      R"({"meshes": [{"name": "g", "polygons": [{"vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]]}]}], "lights": [
        {"name": "a", "type": "area", "polygon": [[0,0,2],[0,1,2],[1,1,2],[1,0,2]], "intensity": 3, "color": [1, 0.5, 0.25]},
        {"name": "d", "type": "disk", "position": [0,0,3], "normal": [0,0,-1], "radius": 0.5},
        {"name": "s", "type": "directional", "to_light": [0,0,1], "angular_diameter": 0.53},
        {"name": "p", "type": "directional", "to_light": [0,0,1], "angular_diameter": 0}]})",
      "inline.json");
  ASSERT_EQ(scene.lights.size(), 4u);
  EXPECT_EQ(scene.lights[0].type, LightType::Area);
  EXPECT_EQ(scene.lights[0].polygon.size(), 4u);
  EXPECT_EQ(scene.lights[0].intensity, 3.0);
  EXPECT_EQ(scene.lights[1].type, LightType::Disk);
  EXPECT_EQ(scene.lights[1].radius, 0.5);
  EXPECT_EQ(scene.lights[2].angular_diameter, 0.53);
  EXPECT_TRUE(scene.lights[2].is_extended());
  EXPECT_FALSE(scene.lights[3].is_extended());
}

TEST(AreaLightInput, ASunBlockGivesItsSunsTheAngularDiameter) {
  const std::string head = R"({"meshes": [{"name": "g", "polygons": [{"vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]]}]}],
    "sun": {"latitude": 52.5, "longitude": 13.4, "times": ["2026-06-21T10:00:00Z", "2026-06-21T12:00:00Z"], )";
  const Scene scene = parse_scene(head + R"("angular_diameter": 0.53}})", "sun.json");
  ASSERT_EQ(scene.lights.size(), 2u);
  for (const Light& light : scene.lights) {
    EXPECT_EQ(light.angular_diameter, 0.53);
    EXPECT_TRUE(light.is_extended());
  }
  try {
    (void)parse_scene(head + R"("angular_diameter": 61}})", "sun.json");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().place, "sun.angular_diameter");
    EXPECT_NE(std::string(e.what()).find("angular_diameter must be in [0, 60]"), std::string::npos) << e.what();
  }
}

TEST(AreaLightInput, EveryBadValueIsOneInputErrorNamingThePlace) {
  struct Case {
    std::string light, place, words;
  };
  const std::vector<Case> cases = {
      {R"({"name": "a", "type": "area", "polygon": [[0,0,2],[0,1,2]]})", "lights[0].polygon", "at least 3 vertices"},
      {R"({"name": "a", "type": "area", "polygon": [[0,0,2],[1,0,2],[2,0,2]]})", "lights[0].polygon", "zero area"},
      {R"({"name": "a", "type": "area", "polygon": [[0,0,2],[0,1,2],[1,1,2.5],[1,0,2]]})", "lights[0].polygon[",
       "not planar"},
      {R"({"name": "a", "type": "area", "polygon": [[0,0,2],[2,2,2],[2,0,2],[0,1,2]]})", "lights[0].polygon",
       "not simple"},
      {R"({"name": "a", "type": "area", "polygon": [[0,0,2],[0,0,2],[1,1,2],[1,0,2]]})", "lights[0].polygon[1]",
       "repeats"},
      {R"({"name": "a", "type": "area"})", "lights[0]", "missing \"polygon\""},
      {R"({"name": "a", "type": "area", "polygon": [[0,0,2],[0,1,2],[1,1,2]], "position": [0,0,1]})",
       "lights[0].position", "no \"position\""},
      {R"({"name": "d", "type": "disk", "position": [0,0,3], "normal": [0,0,-1], "radius": 0})", "lights[0].radius",
       "radius must be > 0"},
      {R"({"name": "d", "type": "disk", "position": [0,0,3], "normal": [0,0,0], "radius": 1})", "lights[0].normal",
       "zero length"},
      {R"({"name": "d", "type": "disk", "position": [0,0,3], "radius": 1})", "lights[0]", "missing \"normal\""},
      {R"({"name": "d", "type": "disk", "position": [0,0,3], "normal": [0,0,-1]})", "lights[0]", "missing \"radius\""},
      {R"({"name": "d", "type": "disk", "normal": [0,0,-1], "radius": 1})", "lights[0]", "missing \"position\""},
      {R"({"name": "s", "type": "directional", "to_light": [0,0,1], "angular_diameter": -1})",
       "lights[0].angular_diameter", "angular_diameter must be in"},
      {R"({"name": "s", "type": "directional", "to_light": [0,0,1], "angular_diameter": 90})",
       "lights[0].angular_diameter", "angular_diameter must be in"},
      {R"({"name": "p", "type": "point", "position": [0,0,1], "angular_diameter": 1})", "lights[0].angular_diameter",
       "only a directional light"},
      {R"({"name": "p", "type": "point", "position": [0,0,1], "polygon": [[0,0,1]]})", "lights[0].polygon",
       "only an area light"},
      {R"({"name": "p", "type": "directional", "to_light": [0,0,1], "radius": 1})", "lights[0].radius",
       "only a disk light"},
      {R"({"name": "x", "type": "spot", "position": [0,0,1]})", "lights[0].type", "unknown light type"},
  };
  for (const Case& c : cases) {
    try {
      (void)parse_scene(scene_with_light(c.light), "bad.json");
      ADD_FAILURE() << "no error for " << c.light;
    } catch (const InputError& e) {
      EXPECT_EQ(e.where().file, "bad.json") << c.light;
      EXPECT_EQ(e.where().place.rfind(c.place, 0), 0u) << c.light << " -> " << e.what();
      EXPECT_NE(std::string(e.what()).find(c.words), std::string::npos) << c.light << " -> " << e.what();
    }
  }
}

TEST(AreaLightInput, LightsBuiltInCodeAreCheckedByTheEngine) {
  Scene scene;
  add_mesh(scene, "ground", {rectangle_z(-5, -5, 5, 5, 0)});
  scene.lights.push_back(disk_light("d", {0, 0, 3}, {0, 0, -1}, -1));
  EXPECT_THROW((void)compute_shadows(scene), InputError);
  scene.lights[0] = sun_disk("s", {0, 0, 1}, std::nan(""));
  EXPECT_THROW((void)compute_shadows(scene), InputError);
  scene.lights[0] = area_light("a", {{0, 0, 1}, {2, 2, 1}, {2, 0, 1}, {0, 1, 1}});  // a bow tie
  EXPECT_THROW((void)compute_shadows(scene), InputError);
}

}  // namespace
}  // namespace shadow::test
