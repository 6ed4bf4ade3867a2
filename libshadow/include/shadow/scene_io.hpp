// SPDX-License-Identifier: GPL-3.0-or-later
/// @file scene_io.hpp
/// @brief Reading scenes (JSON + Wavefront OBJ) with validation that names the place of every error.
#pragma once

#include <shadow/scene.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace shadow {

/// How strictly face geometry is checked.
struct LoadOptions {
  /// A face is planar when every vertex lies within `planarity_tolerance * diameter` of the
  /// plane through its centroid with its Newell normal (diameter: the largest extent of its
  /// bounding box). The allowed distance is never below 8 ulps of the face's largest coordinate
  /// (rounding alone moves coordinates that much), and faces whose normal is numerically zero
  /// skip this test and go to the exact zero-area check. Must be > 0. Faces beyond it are an
  /// InputError. Within it, the library works on the face lifted exactly onto that plane
  /// (docs/numeric-contract.md).
  double planarity_tolerance = 1e-6;
};

/// Reads a scene file and every mesh it references, and validates it.
/// @throws InputError naming the file, the place and the problem.
Scene load_scene(const std::filesystem::path& scene_file, const LoadOptions& options = {});

/// Parses scene JSON text. `scene_file` names the text in errors and anchors relative mesh paths.
/// @throws InputError
Scene parse_scene(const std::string& json_text, const std::filesystem::path& scene_file,
                  const LoadOptions& options = {});

/// Reads the faces of a Wavefront OBJ file (v and f statements; `f v`, `v/t`, `v//n`, `v/t/n`,
/// negative indices; other statements ignored). `display_name` is used in error messages.
/// @throws InputError with the OBJ line number.
std::vector<std::vector<glm::dvec3>> read_obj(const std::filesystem::path& obj_file,
                                             const std::string& display_name);

/// Parses OBJ text (for tests and in-memory meshes).
std::vector<std::vector<glm::dvec3>> parse_obj(const std::string& obj_text,
                                              const std::string& display_name);

/// Checks every face's geometry: finite coordinates, planarity within tolerance, a simple
/// (non-self-intersecting) boundary; and the lights and planes. It changes the scene: removes
/// consecutive duplicate vertices, marks zero-area faces `degenerate` and adds a warning for
/// each. Scenes built in code must call this before computing shadows; calling it twice is
/// harmless.
/// @throws InputError naming the face's source.
void validate_scene(Scene& scene, const LoadOptions& options = {});

}  // namespace shadow
