// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: OBJ reading that also reports where each face was defined, for error messages.
#pragma once

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace shadow::detail {

/// parse_obj that also reports the 1-based line of every face in `face_lines` (may be null).
std::vector<std::vector<glm::dvec3>> parse_obj_with_lines(const std::string& obj_text,
                                                          const std::string& display_name,
                                                          std::vector<std::size_t>* face_lines);

/// read_obj that also reports the 1-based line of every face in `face_lines` (may be null).
std::vector<std::vector<glm::dvec3>> read_obj_with_lines(const std::filesystem::path& obj_file,
                                                         const std::string& display_name,
                                                         std::vector<std::size_t>* face_lines,
                                                         std::uintmax_t max_bytes);

/// The whole file as text; InputError {display_name, ""} "cannot open: <reason>" if unreadable
/// or not a regular file, "file is larger than ..." beyond `max_bytes`.
std::string read_text_file(const std::filesystem::path& file, const std::string& display_name,
                           std::uintmax_t max_bytes);

}  // namespace shadow::detail
