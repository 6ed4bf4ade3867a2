// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: checks shared by validate_scene and the engine (which also takes lights that were
// never part of a validated scene).
#pragma once

#include <shadow/scene.hpp>

#include <string>

namespace shadow::detail {

/// Throws InputError {file, path + ".<key>"} if the light is unusable: non-finite or zero
/// direction, non-finite position, unknown type, bad intensity or colour.
void check_light(const Light& light, const std::string& file, const std::string& path);

}  // namespace shadow::detail
