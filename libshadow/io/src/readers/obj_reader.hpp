// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: OBJ reading that also reports where each face was defined, for error messages.
#pragma once

#include "runtime/uninit_vector.hpp"

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
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
std::vector<std::vector<glm::dvec3>> parse_obj_with_lines(std::string_view obj_text,
                                                          const std::string& display_name,
                                                          std::vector<std::size_t>* face_lines,
                                                          std::vector<std::string>* face_groups = nullptr,
                                                          unsigned threads = 1, std::size_t min_chunk_bytes = 1 << 18);

/// The bytes of a user's file under read_input_file's rules and errors (shadow/input_file.hpp),
/// read on `threads` threads (0: every hardware thread) in parts of 8 MiB into a buffer that is
/// not zeroed first: each page is first touched by the thread that reads into it. For the large
/// mesh files of a scene (a million faces: 89 MB, a third of a second of one thread before).
runtime::UninitVector<char> read_input_bytes(const std::filesystem::path& file, const std::string& display_name,
                                             std::uintmax_t max_bytes, const std::string& limit_name, unsigned threads);

/// read_obj that also reports the 1-based line of every face in `face_lines` (may be null), and
/// its `o`/`g` name in `face_groups` (may be null) as parse_obj_with_lines.
std::vector<std::vector<glm::dvec3>> read_obj_with_lines(const std::filesystem::path& obj_file,
                                                         const std::string& display_name,
                                                         std::vector<std::size_t>* face_lines,
                                                         std::uintmax_t max_bytes,
                                                         std::vector<std::string>* face_groups = nullptr);

}  // namespace shadow::detail
