// SPDX-License-Identifier: GPL-3.0-or-later
// validate_scene as it was before its per-face checks ran in parallel on Epick's predicates:
// the reference that tests compare validate_scene with, and that shadow-bench times it against.
#pragma once

#include <shadow/scene.hpp>
#include <shadow/validation.hpp>

namespace shadow::detail {

/// validate_scene with the faces checked one after the other on one thread, each face's shape
/// decided by classify_face_shape_exact (all in Epeck's lazy exact numbers). Same outcome as
/// validate_scene: same changes to the scene, same warnings, same first error.
void validate_scene_reference(Scene& scene, const LoadOptions& options = {});

/// validate_scene's orientation check alone, on a validated scene: every mesh's closed parts,
/// the warnings returned in mesh order, faces reversed where orient outward asks. On
/// LoadOptions::threads threads (meshes of 4,096 faces or more one after the other, each on every
/// thread; smaller ones many at once), or with `reference` the serial one (one mesh after the
/// other, its edges sorted by their end points' coordinates). Same warnings, same faces.
std::vector<Warning> check_mesh_orientation(Scene& scene, const LoadOptions& options, bool reference);

}  // namespace shadow::detail
