// SPDX-License-Identifier: GPL-3.0-or-later
// Scenes for tests: random ones for property tests, similarity transforms, a furnace room, an
// L-shaped prism (more builders: shadow/generators.hpp).
#pragma once

#include <shadow/generators.hpp>
#include <shadow/scene.hpp>

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace shadow::test {

/// A small random scene for property tests, seeded: a ground square, 1..6 boxes (some resting on
/// the ground, some floating, possibly interpenetrating), 1..4 planar polygons (convex or star
/// shaped, 3..8 vertices, arbitrary orientation, so not exactly planar in doubles), and one light
/// (directional 10..80 degrees up, or a point light anywhere above the ground).
Scene random_scene(std::uint64_t seed);

/// Applies p -> scale * R p + t to every face, light and plane (directions are rotated).
Scene transformed(const Scene& scene, double scale, glm::dvec3 axis, double angle_rad, glm::dvec3 t);

/// A closed 2 x 1 x 1.5 room (fronts inward) whose faces all emit `e` and reflect `rho`: the
/// radiosity furnace, B = E / (1 - rho) everywhere.
Scene furnace_room(double e, double rho);

/// An L-shaped prism (not convex: an L of arms 6 x 3 at `at`) in triangles, fronts outward: its
/// walls, with `roof` its roof at z = at.z + height, with `floor` its floor at z = at.z.
std::vector<Polygon3> l_prism_triangles(glm::dvec3 at, double height, bool floor, bool roof = true);

/// The ids of the faces of mesh `mesh`, ascending.
std::vector<std::size_t> faces_of_mesh(const Scene& scene, std::size_t mesh);

}  // namespace shadow::test
