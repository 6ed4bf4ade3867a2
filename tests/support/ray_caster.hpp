// SPDX-License-Identifier: GPL-3.0-or-later
// An independent shadow-ray test in double precision, to check the exact engine's claims.
#pragma once

#include <shadow/scene.hpp>

namespace shadow::test {

enum class RayVerdict { Lit, Shadowed, Unsure };

/// Does point `p` on face `face_id` see `light`? Casts the segment from `p` to the light against
/// every other non-degenerate face. Answers Unsure when the ray passes within `margin` of an
/// occluder's boundary, hits within `margin` of its ends, or grazes a plane: a double-precision
/// ray cannot decide those, and the exact engine may rightly answer either way.
RayVerdict cast_shadow_ray(const Scene& scene, std::size_t face_id, const glm::dvec3& p,
                           const Light& light, double margin);

}  // namespace shadow::test
