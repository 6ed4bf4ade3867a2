// SPDX-License-Identifier: GPL-3.0-or-later
/// @file scene_io.hpp
/// @brief Reading scenes (JSON + Wavefront OBJ) with validation that names the place of every error.
#pragma once

#include <shadow/scene.hpp>
#include <shadow/validation.hpp>  // LoadOptions, max_coordinate, validate_scene

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace shadow {

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
/// Reads at most `max_bytes` bytes, and regular files only (see LoadOptions::max_file_bytes).
std::vector<std::vector<glm::dvec3>> read_obj(const std::filesystem::path& obj_file,
                                             const std::string& display_name,
                                             std::uintmax_t max_bytes = LoadOptions{}.max_file_bytes);

/// Parses OBJ text (for tests and in-memory meshes).
std::vector<std::vector<glm::dvec3>> parse_obj(const std::string& obj_text,
                                              const std::string& display_name);

}  // namespace shadow
