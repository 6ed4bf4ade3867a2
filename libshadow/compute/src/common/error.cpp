// SPDX-License-Identifier: GPL-3.0-or-later
#include <shadow/error.hpp>

#include <utility>

namespace shadow {

std::string SourceLocation::to_string() const {
  if (file.empty()) return place;
  if (place.empty()) return file;
  return file + ": " + place;
}

namespace {

/// The length of the well-formed UTF-8 sequence at `text[i]` (a byte >= 0x80), or 0 if there is
/// none: a stray continuation byte, a cut sequence, an overlong form, a surrogate, beyond U+10FFFF.
std::size_t utf8_length(const std::string& text, std::size_t i) {
  const auto byte = [&](std::size_t k) { return k < text.size() ? static_cast<unsigned char>(text[k]) : 0u; };
  const unsigned lead = byte(i);
  std::size_t n = 0;
  unsigned low = 0x80, high = 0xBF;  // the allowed range of the second byte
  if (lead >= 0xC2 && lead <= 0xDF) {
    n = 2;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    n = 3;
    if (lead == 0xE0) low = 0xA0;   // overlong
    if (lead == 0xED) high = 0x9F;  // surrogates
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    n = 4;
    if (lead == 0xF0) low = 0x90;   // overlong
    if (lead == 0xF4) high = 0x8F;  // beyond U+10FFFF
  } else {
    return 0;
  }
  if (byte(i + 1) < low || byte(i + 1) > high) return 0;
  for (std::size_t k = 2; k < n; ++k)
    if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return 0;
  return n;
}

}  // namespace

std::string escape_control(const std::string& text) {
  static const char hex[] = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const auto byte = static_cast<unsigned char>(text[i]);
    // Control bytes would break the line; bytes that are not UTF-8 would reach a terminal raw.
    const std::size_t n = byte < 0x80 ? (byte < 0x20 || byte == 0x7F ? 0 : 1) : utf8_length(text, i);
    if (n == 0) {
      out += "\\x";
      out += hex[byte >> 4];
      out += hex[byte & 0xF];
      ++i;
    } else {
      out.append(text, i, n);
      i += n;
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

std::string Warning::to_string() const {
  return format_error({escape_control(where.file), escape_control(where.place)}, escape_control(message));
}

}  // namespace shadow
