// SPDX-License-Identifier: GPL-3.0-or-later
// The orientation check of a scene's meshes (validate.cpp's last step). Internal to scene/.
#pragma once

#include <shadow/scene.hpp>
#include <shadow/validation.hpp>

#include <vector>

namespace shadow::validation {

/// Every mesh's orientation check, the warnings in mesh order. Meshes below kLargeMesh faces
/// (a building each, say) are checked many at once, one thread each; larger ones one after the
/// other on every thread. `reference`: one mesh after the other, one thread, the coordinate sort.
void check_orientations(Scene& scene, const LoadOptions& options, bool reference, unsigned threads,
                        std::vector<Warning>& warnings);

}  // namespace shadow::validation
