// SPDX-License-Identifier: GPL-3.0-or-later
// The library's own computations over a prepared ShadowEngine (the sun-hours map): the
// engine's prepared scene, shared read-only, so that faces are prepared once for everything.
// No CGAL type here.
#pragma once

#include "core/prepared_scene.hpp"

#include <shadow/shadows.hpp>

namespace shadow::engine {

/// The engine's prepared faces, areas, culling data and convex solids (valid while the engine
/// lives).
core::PreparedScene prepared_scene(const ShadowEngine& engine);

}  // namespace shadow::engine
