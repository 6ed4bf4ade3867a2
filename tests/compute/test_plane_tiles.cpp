// SPDX-License-Identifier: GPL-3.0-or-later
// Plane shadows in parallel (tiles united on their own threads, joined back by their borders)
// and with closed convex solids casting as one: neither the thread count, nor the tiling, nor
// the shortcut may change a result, and the tiled union must still equal the per-face
// (Atherton) engine's shadow on a face lying in the plane.
#include "planes/plane_shadows.hpp"

#include <shadow/shadow.hpp>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <vector>

namespace shadow {
namespace {

/// A city of `boxes` on [0, extent]^2 whose ground is a square of half side `half` centred on
/// it, with the ground plane, a tilted plane under the city, a low sun and a lamp above it.
Scene city(std::size_t boxes, double extent, double half) {
  Scene scene = make_city(boxes, extent, 7);
  const double c = extent / 2;
  scene.faces[0].vertices = {{c - half, c - half, 0}, {c + half, c - half, 0}, {c + half, c + half, 0}, {c - half, c + half, 0}};
  scene.lights.push_back(directional_light("sun", sun_direction(35, 120)));
  scene.lights.push_back(point_light("lamp", {c + 13, c - 7, 80}));
  scene.planes.push_back({"ground", {0, 0, 0}, {0, 0, 1}});
  scene.planes.push_back({"tilted", {c, c, -4}, {0.1, -0.2, 1}});
  validate_scene(scene);
  return scene;
}

/// Small tiles on a small city: every pair is cut into several tiles.
planes::Tiling small_tiles() {
  planes::Tiling tiling;
  tiling.tile_from = 20;
  tiling.per_tile = 25;
  tiling.tile_over_image = 0;
  return tiling;
}

planes::Tiling one_tile() {
  planes::Tiling tiling;
  tiling.tile_from = static_cast<std::size_t>(-1);
  return tiling;
}

std::vector<PlaneShadow> planes_of(const Scene& scene, unsigned threads, const planes::Tiling& tiling) {
  ShadowOptions options;
  options.threads = threads;
  options.plane_window = 160;
  return planes::compute_plane_shadows(scene, options, tiling);
}

std::size_t regions_of(const PlaneShadow& s) {
  return std::set<std::size_t>(s.region_id.begin(), s.region_id.end()).size();
}

TEST(PlaneTiles, ResultsDoNotDependOnTheThreadCount) {
  const Scene scene = city(250, 120, 150);
  const std::vector<PlaneShadow> one = planes_of(scene, 1, small_tiles());
  ASSERT_EQ(one.size(), 4u);
  for (unsigned threads : {2u, 3u}) {
    const std::vector<PlaneShadow> other = planes_of(scene, threads, small_tiles());
    ASSERT_EQ(other.size(), one.size());
    for (std::size_t a = 0; a < one.size(); ++a) {
      SCOPED_TRACE("pair " + std::to_string(a) + ", " + std::to_string(threads) + " threads");
      EXPECT_GT(one[a].area, 0.0);
      EXPECT_EQ(other[a].area, one[a].area);  // bit for bit
      EXPECT_EQ(other[a].reaches_window, one[a].reaches_window);
      EXPECT_EQ(other[a].polygons, one[a].polygons);
      EXPECT_EQ(other[a].region_id, one[a].region_id);
      EXPECT_EQ(other[a].polygon_area, one[a].polygon_area);
    }
  }
}

TEST(PlaneTiles, TilesJoinedBackAreOneUnion) {
  // The same exact area whatever the tiles, and the same connected regions: pieces of a region
  // cut by tile borders are joined back into one region by the border stretches they share.
  const Scene scene = city(250, 120, 150);
  const std::vector<PlaneShadow> whole = planes_of(scene, 2, one_tile());
  const std::vector<PlaneShadow> tiled = planes_of(scene, 2, small_tiles());
  ASSERT_EQ(whole.size(), tiled.size());
  for (std::size_t a = 0; a < whole.size(); ++a) {
    SCOPED_TRACE("pair " + std::to_string(a));
    EXPECT_EQ(tiled[a].area, whole[a].area);
    EXPECT_EQ(tiled[a].reaches_window, whole[a].reaches_window);
    EXPECT_EQ(regions_of(tiled[a]), regions_of(whole[a]));
    EXPECT_NE(tiled[a].polygons, whole[a].polygons) << "the small tiles did not cut anything";
    double sum = 0;
    for (double x : tiled[a].polygon_area) sum += x;
    EXPECT_NEAR(sum, tiled[a].area, 1e-9 * tiled[a].area);
  }
}

TEST(PlaneTiles, ConvexSolidsCastTheSameShadowAsTheirFaces) {
  // Two routes, one answer: each box as the hull of its projected vertices, or face by face. The
  // lamp stands lower than some boxes, whose faces then cast one by one (and without end).
  Scene scene = city(120, 80, 100);
  scene.lights.push_back(point_light("low lamp", {41.5, 38.25, 21}));
  for (const planes::Tiling& base : {one_tile(), small_tiles()}) {
    planes::Tiling faces = base;
    faces.solids = false;
    const std::vector<PlaneShadow> a = planes_of(scene, 2, base);
    const std::vector<PlaneShadow> b = planes_of(scene, 2, faces);
    ASSERT_EQ(a.size(), 6u);
    for (std::size_t p = 0; p < a.size(); ++p) {
      SCOPED_TRACE("pair " + std::to_string(p));
      EXPECT_EQ(a[p].area, b[p].area);
      EXPECT_EQ(a[p].reaches_window, b[p].reaches_window);
      EXPECT_EQ(regions_of(a[p]), regions_of(b[p]));
    }
    EXPECT_TRUE(a[2].reaches_window);  // ground, low lamp: boxes taller than the lamp
  }
}

TEST(PlaneTiles, TiledShadowOnThePlaneEqualsTheFaceEnginesOnTheGround) {
  // The ground face is the window's square on the ground plane: the Atherton split of that face
  // (the per-face engine, its own clipping and projection) and the tiled Blinn union must agree
  // bit for bit.
  const Scene scene = city(250, 120, 160);
  ShadowOptions options;
  options.threads = 2;
  options.planes = false;
  options.polygons = false;
  const ShadowResult faces = compute_shadows(scene, options);
  const std::vector<PlaneShadow> tiled = planes_of(scene, 2, small_tiles());
  for (std::size_t light = 0; light < 2; ++light) {
    SCOPED_TRACE("light " + std::to_string(light));
    const PlaneShadow& plane = tiled.at(light);  // the ground plane's pairs come first
    ASSERT_EQ(plane.plane_id, 0u);
    ASSERT_FALSE(plane.reaches_window);
    EXPECT_EQ(plane.area, faces.find(0, light)->shadow_area);
  }
}

TEST(PlaneTiles, StripsAlongTheShadowsGiveTheSameUnion) {
  // Under a directional light the images are united in the chart sheared along the shadows
  // (tiles are strips parallel to them). A shear has determinant 1: the exact area, the regions
  // and the window flag must be those of the chart's own axes, bit for bit, for suns whose
  // shadows run mostly along either chart axis (the shear's two forms) and on a tilted plane
  // (vertices back from the frame onto it).
  Scene scene = city(250, 120, 150);
  scene.lights.clear();
  scene.lights.push_back(directional_light("low sun, east", sun_direction(6, 100)));
  scene.lights.push_back(directional_light("low sun, south", sun_direction(5, 190)));
  scene.lights.push_back(directional_light("diagonal", sun_direction(20, 225)));
  scene.lights.push_back(directional_light("overhead", sun_direction(88, 30)));  // short shadows: no shear
  const planes::Tiling one = one_tile(), small = small_tiles();
  int sheared_differently = 0;  // pairs whose strips cut other cells than the chart's tiles
  for (const planes::Tiling& base : {one, small}) {
    planes::Tiling axes = base;
    axes.shear = false;
    const std::vector<PlaneShadow> strips = planes_of(scene, 2, base);
    const std::vector<PlaneShadow> chart = planes_of(scene, 2, axes);
    ASSERT_EQ(strips.size(), 8u);
    ASSERT_EQ(chart.size(), strips.size());
    for (std::size_t a = 0; a < strips.size(); ++a) {
      SCOPED_TRACE("pair " + std::to_string(a));
      const PlaneShadow& s = strips[a];
      EXPECT_GT(s.area, 0.0);
      EXPECT_EQ(s.area, chart[a].area);
      EXPECT_EQ(s.reaches_window, chart[a].reaches_window);
      EXPECT_EQ(regions_of(s), regions_of(chart[a]));
      // The shear took place (the union in other coordinates cuts the regions into other
      // cells), except for the overhead sun (the fourth light), whose shadows are short: counted
      // below. (Vertices are the exact points rounded to nearest, so where both routes happen to
      // cut the same cells they write the same polygons.)
      if (&base != &one && a % 4 != 3 && s.polygons != chart[a].polygons) ++sheared_differently;
      // Every polygon vertex lies on its plane (to rounding) and the pieces add up to the area.
      const Plane& plane = scene.planes[s.plane_id];
      const glm::dvec3 n = glm::normalize(plane.normal);
      double sum = 0;
      for (std::size_t p = 0; p < s.polygons.size(); ++p) {
        sum += s.polygon_area[p];
        for (const glm::dvec3& v : s.polygons[p]) EXPECT_NEAR(glm::dot(n, v - plane.point), 0.0, 1e-9);
      }
      EXPECT_NEAR(sum, s.area, 1e-9 * s.area);
    }
  }
  EXPECT_GE(sheared_differently, 2) << "the strips cut the same cells as the chart's tiles: no shear";
}

TEST(PlaneTiles, GridKeepsTilesWideAlongLongShadows) {
  // The library's rule (tiles at least so many median images wide along each axis: ten by
  // default, three on this 120 m city so that a cut fits at all) on a city small enough to test:
  // under a 5 degree sun the images are much longer along the shear's lead axis than its
  // width allows, so the cuts go to the other axis (strips). The union is the same whatever the
  // grid.
  Scene scene = city(250, 120, 150);
  scene.lights.clear();
  scene.lights.push_back(directional_light("low sun", sun_direction(5, 200)));
  scene.planes.resize(1);
  planes::Tiling strips;
  strips.tile_from = 20;
  strips.per_tile = 25;  // about ten tiles wanted
  strips.tile_over_image = 3;
  const std::vector<PlaneShadow> whole = planes_of(scene, 2, one_tile());
  const std::vector<PlaneShadow> tiled = planes_of(scene, 2, strips);
  ASSERT_EQ(tiled.size(), 1u);
  EXPECT_EQ(tiled[0].area, whole[0].area);
  EXPECT_EQ(tiled[0].reaches_window, whole[0].reaches_window);
  EXPECT_EQ(regions_of(tiled[0]), regions_of(whole[0]));
  EXPECT_NE(tiled[0].polygons, whole[0].polygons) << "the grid cut nothing";
}

TEST(PlaneTiles, LowSunStripsMatchTheFaceEngine) {
  // The ground face under a 5 degree sun from the south-west (long diagonal shadows, strips of
  // the sheared chart): the Atherton split of that face and the tiled Blinn union agree bit for bit.
  Scene scene = city(250, 120, 1500);  // a ground wide enough for every shadow
  scene.lights.clear();
  scene.lights.push_back(directional_light("low sun", sun_direction(5, 225)));
  ShadowOptions options;
  options.threads = 2;
  options.planes = false;
  options.polygons = false;
  const ShadowResult faces = compute_shadows(scene, options);
  const std::vector<PlaneShadow> tiled = planes::compute_plane_shadows(scene, options, small_tiles());
  const PlaneShadow& plane = tiled.at(0);
  ASSERT_EQ(plane.plane_id, 0u);
  ASSERT_FALSE(plane.reaches_window);
  EXPECT_EQ(plane.area, faces.find(0, 0)->shadow_area);
}

}  // namespace
}  // namespace shadow
