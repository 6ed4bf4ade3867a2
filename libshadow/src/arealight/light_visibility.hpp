// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: the visible fraction and the irradiance of an extended light at points, in one pass
// (light_visibility.cpp). No CGAL here.
#pragma once

#include <shadow/area_lights.hpp>

#include <utility>
#include <vector>

namespace shadow::detail {

/// For each point: (visible fraction, irradiance); the irradiance is computed only when
/// `irradiance` is true (0 otherwise). Errors as light_visibility.
std::vector<std::pair<double, double>> light_visibility_irradiance(const Scene& scene, const Light& light,
                                                                   const std::vector<SurfacePoint>& points,
                                                                   unsigned threads, bool irradiance);

}  // namespace shadow::detail
