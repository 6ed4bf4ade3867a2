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
std::string format_error(const SourceLocation& where, const std::string& problem) {
  const std::string location = where.to_string();
  return location.empty() ? problem : location + ": " + problem;
}
}  // namespace

InputError::InputError(SourceLocation where, std::string problem)
    : std::runtime_error(format_error(where, problem)),
      where_(std::move(where)),
      problem_(std::move(problem)) {}

std::string Warning::to_string() const { return format_error(where, message); }

}  // namespace shadow
