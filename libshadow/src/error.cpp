// SPDX-License-Identifier: GPL-3.0-or-later
#include <shadow/error.hpp>
#include <shadow/output.hpp>

#include <utility>

namespace shadow {

std::string SourceLocation::to_string() const {
  if (file.empty()) return place;
  if (place.empty()) return file;
  return file + ": " + place;
}

std::string escape_control(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7F) {
      static const char hex[] = "0123456789abcdef";
      out += "\\x";
      out += hex[byte >> 4];
      out += hex[byte & 0xF];
    } else {
      out += c;
    }
  }
  return out;
}

namespace {

std::string format_error(const SourceLocation& where, const std::string& problem) {
  const std::string location = where.to_string();
  return location.empty() ? problem : location + ": " + problem;
}

}  // namespace

InputError::InputError(SourceLocation where, std::string problem)
    : std::runtime_error(format_error({escape_control(where.file), escape_control(where.place)},
                                      escape_control(problem))),
      where_(std::move(where)),
      problem_(escape_control(problem)) {}

OutputError::OutputError(const std::string& message) : std::runtime_error(escape_control(message)) {}

std::string Warning::to_string() const {
  return format_error({escape_control(where.file), escape_control(where.place)}, escape_control(message));
}

}  // namespace shadow
