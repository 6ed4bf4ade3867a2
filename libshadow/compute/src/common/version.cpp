// SPDX-License-Identifier: GPL-3.0-or-later
#include <shadow/version.hpp>

namespace shadow {
const char* version() noexcept { return LIBSHADOW_VERSION; }
}  // namespace shadow
