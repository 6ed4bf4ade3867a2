// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: radiosity's elements (the receivers: triangles cut from the direct light's fragments)
// and patches (the shooters and sources: coarser triangles that hold consecutive elements), and
// the direct light on each element.
#pragma once

#include "radiosity/triangles.hpp"

#include <shadow/scene.hpp>
#include <shadow/shadows.hpp>

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace shadow::radiosity {

/// An element while solving: a triangle with its receiving points.
struct Element {
  std::size_t face = 0;
  Triangle triangle;
  double area = 0.0;
  glm::dvec3 centroid{0.0};
  double radius = 0.0;  // largest distance from the centroid to a vertex
  std::size_t fragment = SIZE_MAX;  // index into the first light's fragments, or none
  std::size_t patch = 0;            // the patch (a coarser triangle) that holds it
};

/// A patch: the triangle that shoots for the elements it holds (Cohen et al.'s substructuring:
/// shooters coarse, receivers fine).
struct Patch {
  std::size_t face = 0;
  Triangle triangle;
  double area = 0.0;
  glm::dvec3 centroid{0.0};
  double radius = 0.0;
  std::size_t first = 0, count = 0;  // its elements
};

/// The patches and their elements: each face's fragments under the first light (its whole
/// polygon where it has none), cut where other faces meet the face, triangulated, refined to
/// patch_area and, when max_patch_edge > 0, until no edge is longer (the patches), each refined
/// to max_area (its elements, consecutive).
void make_elements(const Scene& scene, const std::vector<Fragment>& fragments, double max_area, double patch_area,
                   double max_patch_edge, std::vector<Patch>& patches, std::vector<Element>& elements);

/// Each element's direct irradiance from each of the scene's lights (one array per light), with
/// exact shadows: the fragment's lit flag for the first light, a lit fragment of the same face
/// holding the centroid for the others (hard lights), the mean of three interior points for
/// extended lights.
std::vector<std::vector<double>> direct_irradiance(const Scene& scene, const std::vector<Fragment>& fragments,
                                                   const std::vector<Element>& elements,
                                                   const std::vector<glm::dvec3>& normals, unsigned threads);

}  // namespace shadow::radiosity
