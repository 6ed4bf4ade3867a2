// SPDX-License-Identifier: GPL-3.0-or-later
// Internal entry to the Blinn plane-shadow path with faces already prepared (the engine's).
#pragma once

#include "core/face_prep.hpp"

#include <shadow/shadows.hpp>

#include <vector>

namespace shadow::planes {

/// compute_plane_shadows with the faces' preparation given (see core::FacePrep).
std::vector<PlaneShadow> plane_shadows(const Scene& scene, const std::vector<core::FacePrep>& prep,
                                       const ShadowOptions& options);

}  // namespace shadow::planes
