// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: report.json written a member at a time, the same bytes as nlohmann's dump(2) of the
// whole document, so that a large array (the faces) is never held as one document.
#pragma once

#include <nlohmann/json.hpp>

#include <ostream>
#include <string>

namespace shadow::detail {

/// Pretty-printed (indent > 0) or compact text. Names come from user files: bytes that are not
/// UTF-8 are replaced rather than failing the whole report.
inline std::string dump_json(const nlohmann::ordered_json& value, int indent = -1) {
  return value.dump(indent, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

/// Appends `text` (a pretty-printed value) to `out`, indented by `indent` more spaces after each
/// newline. JSON strings never hold a raw newline, so this cannot touch their content.
inline void append_indented(std::string& out, const std::string& text, std::size_t indent) {
  std::size_t from = 0;
  for (std::size_t nl = text.find('\n'); nl != std::string::npos; nl = text.find('\n', from)) {
    out.append(text, from, nl + 1 - from);
    out.append(indent, ' ');
    from = nl + 1;
  }
  out.append(text, from, std::string::npos);
}

inline std::string indent_more(const std::string& text, std::size_t indent) {
  std::string out;
  out.reserve(text.size() + text.size() / 8);
  append_indented(out, text, indent);
  return out;
}

/// One member of the top-level object, `value_text` being its value's dump(2): as the whole
/// document's dump(2) writes it (two spaces in, a comma unless last).
inline void write_member(std::ostream& out, const std::string& key, const std::string& value_text, bool last = false) {
  out << "  " << dump_json(nlohmann::ordered_json(key)) << ": " << indent_more(value_text, 2) << (last ? "\n" : ",\n");
}

}  // namespace shadow::detail
