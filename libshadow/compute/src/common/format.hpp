// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: numbers in messages. One rule for every message that names a user's number (the
// engine's input checks, validation, the sun, the readers): the fewest significant digits that
// read back as the same double, so a message never shows a value the user did not give
// (%g's six digits could) nor 17 digits where 0.1 was written.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace shadow::detail {

/// `x` printed in the shortest %g form that parses back to `x` exactly ("0.1", "1e+150",
/// "3.2733906078961419e+150"), without an exponent where the number has up to 16 digits before
/// the point ("100", not %g's "1e+02"); "inf", "-inf" and "nan" as printf writes them.
inline std::string format_number(double x) {
  char buffer[32];
  int digits = 1;
  for (; digits <= 17; ++digits) {
    std::snprintf(buffer, sizeof buffer, "%.*g", digits, x);
    if (std::strtod(buffer, nullptr) == x) break;  // NaN never compares equal: ends at 17 digits
  }
  const double magnitude = x < 0 ? -x : x;
  if (magnitude >= 1 && magnitude < 1e16) {
    char plain[32];
    for (int more = digits; more <= 17; ++more) {
      std::snprintf(plain, sizeof plain, "%.*g", more, x);
      if (std::strchr(plain, 'e') == nullptr && std::strtod(plain, nullptr) == x) return plain;
    }
  }
  return buffer;
}

}  // namespace shadow::detail
