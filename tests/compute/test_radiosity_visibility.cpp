// SPDX-License-Identifier: GPL-3.0-or-later
// Radiosity's visibility in doubles (radiosity/visible_part, radiosity/shaft) against the exact
// route (CGAL, point_form_factors) on occluders that take each of its three paths: disjoint
// convex shadows, overlapping convex shadows (convex pieces), a non-convex shadow (Clipper).
#include "radiosity/shaft.hpp"
#include "radiosity/visible_part.hpp"

#include <shadow/generators.hpp>
#include <shadow/radiosity.hpp>
#include <shadow/scene.hpp>
#include <shadow/validation.hpp>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace {

using glm::dvec3;
using shadow::Scene;
using Polygon3 = std::vector<dvec3>;

const Polygon3 kFloor = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}};            // front +z
const Polygon3 kSource = {{0.5, 0.5, 2}, {0.5, 1.5, 2}, {1.5, 1.5, 2}, {1.5, 0.5, 2}};  // front -z

Scene scene_of(const std::vector<Polygon3>& faces) {
  Scene scene;
  shadow::add_mesh(scene, "faces", faces);
  shadow::validate_scene(scene);
  return scene;
}

/// Doubles against exact at 200 seeded points of the floor (face 0) towards the source (face 1),
/// every other face a candidate, within `tolerance` of the unoccluded value; returns how many
/// points were partly hidden.
int compare_with_exact(const Scene& scene, double tolerance = 1e-9) {
  std::mt19937_64 rng(35);
  std::uniform_real_distribution<double> u(0.02, 1.98);
  std::vector<shadow::SurfacePoint> points;
  for (int i = 0; i < 200; ++i) points.push_back({0, {u(rng), u(rng), 0.0}});
  const std::vector<double> exact = shadow::point_form_factors(scene, 1, points, 1);
  const shadow::radiosity::SourceChart chart(scene.faces[1].vertices);
  shadow::radiosity::VisibleScratch scratch;
  std::vector<const Polygon3*> occluders;
  for (std::size_t f = 2; f < scene.faces.size(); ++f) occluders.push_back(&scene.faces[f].vertices);
  int partly = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double open = chart.unoccluded(points[i].position, {0, 0, 1}, scratch);
    const double seen = chart.form_factor(points[i].position, {0, 0, 1}, occluders, scratch);
    EXPECT_NEAR(seen, exact[i], tolerance * open) << "point " << i;
    partly += seen > 1e-6 * open && seen < (1 - 1e-6) * open ? 1 : 0;
  }
  return partly;
}

TEST(RadiosityVisibility, OneConvexPlateAgreesWithTheExactRoute) {
  const Polygon3 plate = {{0.7, 0.6, 1}, {1.3, 0.6, 1}, {1.3, 1.1, 1}, {0.7, 1.1, 1}};
  EXPECT_GT(compare_with_exact(scene_of({kFloor, kSource, plate})), 50);
}

TEST(RadiosityVisibility, OverlappingPlatesAndABoxAgreeWithTheExactRoute) {
  // Two plates at different heights whose shadows overlap, and a closed box (front and back
  // faces cast overlapping shadows): the convex pieces.
  std::vector<Polygon3> faces = {kFloor, kSource, {{0.6, 0.6, 1.2}, {1.2, 0.6, 1.2}, {1.2, 1.0, 1.2}, {0.6, 1.0, 1.2}},
                                 {{0.9, 0.8, 0.8}, {1.5, 0.8, 0.8}, {1.5, 1.4, 0.8}, {0.9, 1.4, 0.8}}};
  for (const Polygon3& f : shadow::box_faces({0.3, 1.1, 0.9}, {0.7, 1.5, 1.3})) faces.push_back(f);
  EXPECT_GT(compare_with_exact(scene_of(faces)), 50);
}

TEST(RadiosityVisibility, ANonConvexPlateAgreesWithTheExactRoute) {
  const Polygon3 l_shape = {{0.6, 0.6, 1}, {1.4, 0.6, 1}, {1.4, 0.9, 1}, {0.9, 0.9, 1}, {0.9, 1.4, 1}, {0.6, 1.4, 1}};
  // Clipper's grid is about 3e-9 of the source's size: the tolerance is 1e-8 here.
  EXPECT_GT(compare_with_exact(scene_of({kFloor, kSource, l_shape}), 1e-8), 50);
}

TEST(RadiosityVisibility, ShaftKeepsFacesBetweenAndDropsOthers) {
  const Polygon3 between = {{0.8, 0.8, 1}, {1.2, 0.8, 1}, {1.2, 1.2, 1}, {0.8, 1.2, 1}};
  const Polygon3 aside = {{5, 5, 1}, {6, 5, 1}, {6, 6, 1}, {5, 6, 1}};
  const Polygon3 below = {{0, 0, -1}, {2, 0, -1}, {2, 2, -1}, {0, 2, -1}};
  // A wall standing on the floor's edge: it only touches the shaft.
  const Polygon3 wall = {{0, 0, 0}, {0, 2, 0}, {0, 2, 2}, {0, 0, 2}};
  const Scene scene = scene_of({kFloor, kSource, between, aside, below, wall});
  const shadow::radiosity::ShaftCuller culler(scene);
  shadow::radiosity::ShaftCuller::Scratch scratch;
  std::vector<std::size_t> found;
  EXPECT_FALSE(culler.candidates(kFloor, 0, kSource, 1, scratch, found));
  EXPECT_EQ(found, std::vector<std::size_t>{2});
  // A plate wider than both, between them, hides everything.
  const Polygon3 lid = {{-1, -1, 1}, {3, -1, 1}, {3, 3, 1}, {-1, 3, 1}};
  const Scene covered = scene_of({kFloor, kSource, lid, aside});
  const shadow::radiosity::ShaftCuller covered_culler(covered);
  EXPECT_TRUE(covered_culler.candidates(kFloor, 0, kSource, 1, scratch, found));
  EXPECT_TRUE(found.empty());
}

TEST(RadiosityVisibility, SolverInDoublesMatchesTheExactRoute) {
  // A closed room with a box on the floor and an area light under the ceiling.
  Scene scene;
  shadow::Material white;
  white.name = "white";
  white.reflectance = 0.7;
  scene.materials.push_back(white);
  shadow::add_mesh(scene, "room", shadow::room_faces({0, 0, 0}, {3, 3, 2.5}));
  shadow::add_mesh(scene, "box", shadow::box_faces({0.8, 0.9, 0}, {1.8, 1.7, 1.2}));
  scene.meshes[0].material = scene.meshes[1].material = "white";
  shadow::Light lamp;
  lamp.name = "lamp";
  lamp.type = shadow::LightType::Area;
  lamp.polygon = {{1.2, 1.2, 2.4}, {1.8, 1.2, 2.4}, {1.8, 1.8, 2.4}, {1.2, 1.8, 2.4}};
  lamp.intensity = 50;
  scene.lights.push_back(lamp);
  shadow::validate_scene(scene);
  shadow::RadiosityOptions options;
  options.max_element_area = 2.0;
  options.tolerance = 1e-2;
  options.threads = 2;
  const shadow::RadiosityResult doubles = shadow::solve_radiosity(scene, options);
  options.exact_visibility = true;
  const shadow::RadiosityResult exact = shadow::solve_radiosity(scene, options);
  EXPECT_EQ(doubles.exact_evaluations, 0u);
  EXPECT_GT(exact.exact_evaluations, 0u);
  ASSERT_EQ(doubles.faces.size(), exact.faces.size());
  EXPECT_EQ(doubles.shots, exact.shots);
  for (std::size_t f = 0; f < exact.faces.size(); ++f) {
    EXPECT_NEAR(doubles.faces[f].irradiance, exact.faces[f].irradiance, 1e-8 * exact.faces[f].irradiance + 1e-12)
        << "face " << f;
  }
}

}  // namespace
