// SPDX-License-Identifier: GPL-3.0-or-later
// Building scenes in code for tests: boxes, squares, lights, random cities.
#pragma once

#include <shadow/scene.hpp>

#include <glm/vec3.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace shadow::test {

using Polygon3 = std::vector<glm::dvec3>;

/// Appends a mesh made of `polygons` and returns the face_id of its first face.
std::size_t add_mesh(Scene& scene, const std::string& name, const std::vector<Polygon3>& polygons,
                     bool receiver = true);

/// The six faces of an axis-aligned box, fronts outward.
std::vector<Polygon3> box_faces(glm::dvec3 lo, glm::dvec3 hi);

/// An axis-aligned rectangle at height z, front facing +z (or -z when `up` is false).
Polygon3 rectangle_z(double x0, double y0, double x1, double y1, double z, bool up = true);

Light directional_light(const std::string& name, glm::dvec3 to_light);
Light point_light(const std::string& name, glm::dvec3 position);

/// A sun direction (toward the sun) from elevation and azimuth in degrees.
glm::dvec3 sun_direction(double elevation_deg, double azimuth_deg);

/// A city of `boxes` random boxes on a ground square of side `extent`, seeded. Boxes have
/// footprints of 2..10 and heights of 3..30 and may overlap (interpenetrate). The ground is
/// mesh 0 ("ground"), the boxes mesh 1 ("buildings").
Scene make_city(std::size_t boxes, double extent, std::uint64_t seed);

/// A small random scene for property tests, seeded: a ground square, 1..6 boxes (some resting on
/// the ground, some floating, possibly interpenetrating), 1..4 planar polygons (convex or star
/// shaped, 3..8 vertices, arbitrary orientation, so not exactly planar in doubles), and one light
/// (directional 10..80 degrees up, or a point light anywhere above the ground).
Scene random_scene(std::uint64_t seed);

/// Applies p -> scale * R p + t to every face, light and plane (directions are rotated).
Scene transformed(const Scene& scene, double scale, glm::dvec3 axis, double angle_rad, glm::dvec3 t);

}  // namespace shadow::test
