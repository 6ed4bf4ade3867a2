// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: where other faces touch or pierce a face (a box standing on a floor), the lines along
// which radiosity's elements must be cut: on one side the face sees the room, on the other it is
// closed off (discontinuity meshing of order 0, Heckbert 1992; docs/radiosity.md).
#pragma once

#include "radiosity/triangles.hpp"

#include <shadow/scene.hpp>

#include <glm/vec3.hpp>

#include <vector>

namespace shadow::radiosity {

/// A segment in a face's plane.
struct Segment {
  glm::dvec3 a{0.0}, b{0.0};
};

/// For each face, the segments where the other faces (not parallel to it) meet its plane within
/// its box: an edge lying in the plane, or the crossing of a face that passes through it.
std::vector<std::vector<Segment>> contact_segments(const Scene& scene);

/// Appends to `out` the pieces of `t` cut along the line of every segment that crosses its
/// interior (each piece a triangle, oriented as t; a cut that would leave a sliver thinner than
/// 1e-9 of t's size is not made).
void cut_along(const Triangle& t, const glm::dvec3& normal, const std::vector<Segment>& segments,
               std::vector<Triangle>& out);

}  // namespace shadow::radiosity
