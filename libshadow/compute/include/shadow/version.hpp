// SPDX-License-Identifier: GPL-3.0-or-later
/// @file version.hpp
/// @brief libshadow's version.
#pragma once

namespace shadow {
/// "MAJOR.MINOR.PATCH"
const char* version() noexcept;
}  // namespace shadow
