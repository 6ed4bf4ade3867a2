// SPDX-License-Identifier: GPL-3.0-or-later
// Internal entry to the Blinn plane-shadow path with faces already prepared (the engine's).
#pragma once

#include "core/face_prep.hpp"

#include <shadow/shadows.hpp>

#include <vector>

namespace shadow::exact {

/// compute_plane_shadows with the faces' preparation given (see FacePrep).
std::vector<PlaneShadow> plane_shadows(const Scene& scene, const std::vector<FacePrep>& prep,
                                       const ShadowOptions& options);

}  // namespace shadow::exact
