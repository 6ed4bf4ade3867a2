// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: the irradiance the output files store at each fragment vertex. The physics lives
// here, beside shadow::irradiance; the VTK writer only stores the numbers.
#pragma once

#include <shadow/scene.hpp>
#include <shadow/shadows.hpp>

namespace shadow::detail {

/// Writes the irradiance at each vertex of `fragment` to out[0 .. fragment.polygon.size()):
/// irradiance(light, vertex, n) where the fragment is lit, 0 where it is in shadow, NaN when its
/// light is not in `scene` (nothing to compute it from). n is the unit normal of the fragment's
/// face, or of the fragment itself when the face is not in `scene` (a fragment sliver could
/// tilt its own normal, so the face's is preferred).
void fragment_irradiance(const Scene& scene, const Fragment& fragment, double* out);

}  // namespace shadow::detail
