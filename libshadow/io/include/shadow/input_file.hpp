// SPDX-License-Identifier: GPL-3.0-or-later
/// @file input_file.hpp
/// @brief Reading a user's file the way the scene readers do: regular files only, bounded.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace shadow {

/// The whole of a user's file as bytes, as the scene and model readers read theirs: regular
/// files only (symlinks followed; a FIFO, a device, a socket or a directory is refused at once,
/// without blocking on it), and at most `max_bytes` bytes (checked while reading too, so a file
/// that grows is stopped). For programs on the library that read files of their own, such as
/// `shadow series --resume` its checkpoint.
/// @param display_name the file's name in messages
/// @param limit_name what sets `max_bytes`, for the message of a file beyond it
/// @throws InputError {display_name, ""}: "cannot open: <reason>", "cannot open: not a regular
/// file (a device, FIFO or socket)", "cannot read: <reason>", or "file is larger than the limit
/// of N bytes (<limit_name>)".
std::string read_input_file(const std::filesystem::path& file, const std::string& display_name,
                            std::uintmax_t max_bytes,
                            const std::string& limit_name = "LoadOptions::max_file_bytes");

}  // namespace shadow
