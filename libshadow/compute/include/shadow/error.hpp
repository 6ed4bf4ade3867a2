// SPDX-License-Identifier: GPL-3.0-or-later
/// @file error.hpp
/// @brief Errors that name where bad input is and what is wrong with it.
#pragma once

#include <stdexcept>
#include <string>

namespace shadow {

/// `text` with control bytes (below 0x20, 0x7F) and bytes that are not well-formed UTF-8 as `\xHH`:
/// a NUL would cut a C string, a newline break the one-line rule, a stray byte reach a terminal
/// raw. Every InputError, OutputError and Warning text goes through it; so do the CLI's own.
std::string escape_control(const std::string& text);

/// Where a piece of input came from: a file and a place inside it.
struct SourceLocation {
  std::string file;   ///< path as the user gave it (scene file or mesh file)
  std::string place;  ///< JSON path (`lights[1].to_light`), `line 12` or `line 3, column 7`

  /// "file: place" (or just the part that is set).
  [[nodiscard]] std::string to_string() const;
};

/// Bad user input. The message is one line: `FILE: PLACE: PROBLEM`. Control bytes in any of the
/// three parts (a NUL from a binary file, a newline in a name, a byte not UTF-8) are shown as `\xHH`,
/// in what() and in problem(), so the message is never cut short and stays on one line.
///
/// Library code throws this (never aborts) for anything a user can get wrong:
/// malformed JSON, missing mesh files, NaN coordinates, non-planar faces, ...
class InputError : public std::runtime_error {
 public:
  InputError(SourceLocation where, std::string problem);

  [[nodiscard]] const SourceLocation& where() const noexcept { return where_; }
  [[nodiscard]] const std::string& problem() const noexcept { return problem_; }

 private:
  SourceLocation where_;
  std::string problem_;
};

/// A problem that does not stop the computation (a zero-area face, say).
struct Warning {
  SourceLocation where;
  std::string message;
  /// "file: place: message", control bytes shown as `\xHH` like InputError's
  [[nodiscard]] std::string to_string() const;
};

}  // namespace shadow
