// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: the visible fraction and the irradiance of an extended light at points, in one pass
// (light_visibility.cpp). No CGAL here.
#pragma once

#include <shadow/area_lights.hpp>

#include <cstddef>
#include <utility>
#include <vector>

namespace shadow::detail {

/// For each point: (visible fraction, irradiance); the irradiance is computed only when
/// `irradiance` is true (0 otherwise). `toward[i]`, where given and non-zero, is a direction
/// along point i's face: the values are then the limits from that side (they differ from the
/// point's own only where a face passes through the point: a contact edge). Errors as
/// light_visibility.
std::vector<std::pair<double, double>> light_visibility_irradiance(const Scene& scene, const Light& light,
                                                                   const std::vector<SurfacePoint>& points,
                                                                   unsigned threads, bool irradiance,
                                                                   const std::vector<glm::dvec3>& toward = {});

/// Sets Fragment::visibility and Fragment::irradiance of the fragments in `fragments` whose
/// light_id is `light_id` (`light`, extended), in one batch over all their vertices on `threads`
/// threads; other fragments are left as they are.
void fill_light_fragment_visibility(const Scene& scene, const Light& light, std::size_t light_id,
                                    std::vector<Fragment>& fragments, unsigned threads);

}  // namespace shadow::detail
