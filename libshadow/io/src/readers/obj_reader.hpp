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

/// parse_obj that also reports the 1-based line of every face in `face_lines` (may be null), and
/// in `face_groups` (may be null) the name of the latest `o` or `g` statement before each face
/// (its names joined by single spaces; empty before any, or after a `g` without a name).
///
/// With `threads` > 1 (0: every hardware thread) a text of at least `min_chunk_bytes` times two
/// is read in parts on that many threads (parts of at least `min_chunk_bytes`, cut at line
/// ends; not when a line is continued with a backslash): the same faces, lines, groups, and
/// the same first error as one thread.
std::vector<std::vector<glm::dvec3>> parse_obj_with_lines(const std::string& obj_text,
                                                          const std::string& display_name,
                                                          std::vector<std::size_t>* face_lines,
                                                          std::vector<std::string>* face_groups = nullptr,
                                                          unsigned threads = 1, std::size_t min_chunk_bytes = 1 << 18);

/// read_obj that also reports the 1-based line of every face in `face_lines` (may be null), and
/// its `o`/`g` name in `face_groups` (may be null) as parse_obj_with_lines.
std::vector<std::vector<glm::dvec3>> read_obj_with_lines(const std::filesystem::path& obj_file,
                                                         const std::string& display_name,
                                                         std::vector<std::size_t>* face_lines,
                                                         std::uintmax_t max_bytes,
                                                         std::vector<std::string>* face_groups = nullptr);

}  // namespace shadow::detail
