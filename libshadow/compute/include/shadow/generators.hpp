// SPDX-License-Identifier: GPL-3.0-or-later
/// @file generators.hpp
/// @brief Procedural scenes: the benchmark cities and rooms, and building blocks for tests.
#pragma once

#include <shadow/scene.hpp>

#include <glm/vec3.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace shadow {

using Polygon3 = std::vector<glm::dvec3>;

/// Appends a mesh made of `polygons` (face sources named "<name>[i]") and returns the face_id
/// of its first face.
std::size_t add_mesh(Scene& scene, const std::string& name, const std::vector<Polygon3>& polygons,
                     bool receiver = true);

/// The six faces of an axis-aligned box, fronts outward; order: top, bottom, south (-y),
/// north (+y), east (+x), west (-x).
std::vector<Polygon3> box_faces(glm::dvec3 lo, glm::dvec3 hi);

/// The six faces of an axis-aligned box, fronts inward (a room seen from inside).
std::vector<Polygon3> room_faces(glm::dvec3 lo, glm::dvec3 hi);

/// An axis-aligned rectangle at height z, front facing +z (or -z when `up` is false).
Polygon3 rectangle_z(double x0, double y0, double x1, double y1, double z, bool up = true);

/// A comb in the plane at height z, front facing +z: `teeth` teeth 0.5 wide and 9 long (x from
/// k - 0.5 to k for k = 1..teeth, y from 1 to 10) on a spine 1 wide (x from 0 to teeth, y from 0
/// to 1). 4 x teeth + 3 vertices, area 5.5 x teeth: a large non-convex face (benchmarks, tests).
Polygon3 comb_polygon(std::size_t teeth, double z = 0);

Light directional_light(const std::string& name, glm::dvec3 to_light);
Light point_light(const std::string& name, glm::dvec3 position);

/// Direction toward the sun from its elevation above the horizon and its azimuth (degrees,
/// clockwise from +y, "north"): (cos e sin a, cos e cos a, sin e).
glm::dvec3 sun_direction(double elevation_deg, double azimuth_deg);

/// A city of `boxes` random boxes (footprints 2..10 m, heights 3..30 m, centimetre coordinates,
/// possibly overlapping) on a ground square of side `extent` (plus a 10 m margin). Mesh 0 is
/// "ground" (one face), mesh 1 "buildings" (6 faces per box). No lights. Same seed, same city.
Scene make_city(std::size_t boxes, double extent, std::uint64_t seed);

/// A furnished room (8 x 6 x 3 m, faces looking inward) with `tables` tables (top and four
/// legs, each a box) and a few shelves against the walls, and a ceiling lamp (point light)
/// 0.3 m under the ceiling: geometry on every side of the light. Seeded.
Scene make_furnished_room(std::size_t tables, std::uint64_t seed);

/// A field of `spheres` polyhedral spheres (UV spheres of 12 longitudes and 6 latitude bands,
/// 120 triangles each: closed convex solids) of random radius 1..4 m resting on a ground square
/// of side `extent` (plus a 10 m margin; each sphere touches it at its south pole). Spheres may
/// interpenetrate. Mesh 0 is "ground" (one face), mesh 1 "spheres". No lights. Seeded.
Scene make_sphere_field(std::size_t spheres, double extent, std::uint64_t seed);

}  // namespace shadow
