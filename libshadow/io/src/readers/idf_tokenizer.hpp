// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: EnergyPlus IDF text split into objects and fields, each with its line number.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace shadow::scene_readers {

/// One field of an IDF object: its text with surrounding blanks removed (empty when blank).
struct IdfField {
  std::string text;
  std::size_t line = 0;  ///< 1-based line where the field starts (or its separator, when blank)
};

/// `Class, field, field, ...;`: fields[0] is the class name as written.
struct IdfObject {
  std::vector<IdfField> fields;
  std::size_t line = 0;  ///< line of the class name
  /// Byte offsets in the text: the class name's first character, and one past the closing `;`
  /// (so that a copy of the file can replace the object: energyplus_writer).
  std::size_t begin = 0, end = 0;
};

/// Splits IDF text into objects. `!` starts a comment up to the end of the line; fields are
/// separated by `,` and an object ends with `;`. Throws InputError {display_name, "line N"}
/// for an object left without its `;` at the end of the text.
std::vector<IdfObject> tokenize_idf(const std::string& text, const std::string& display_name);

}  // namespace shadow::scene_readers
