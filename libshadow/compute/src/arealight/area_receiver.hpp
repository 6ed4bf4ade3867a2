// SPDX-License-Identifier: GPL-3.0-or-later
// The exact regions of one receiving face under one extended light (docs/area-lights.md): the
// points that see all of the light (fully lit), part of it (penumbra) and none of it (umbra).
// Include only from CGAL translation units (engine/).
#pragma once

#include "arealight/light_shape.hpp"
#include "core/face_prep.hpp"
#include "core/prepared_scene.hpp"
#include "exact/exact_receiver.hpp"

#include <shadow/scene.hpp>
#include <shadow/shadows.hpp>

#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <memory>
#include <vector>

namespace shadow::arealight {

/// What one extended light needs, prepared once and shared by the threads (no Epeck values).
struct AreaLightPrep {
  LightShape shape;
  core::FacePrep prep;  ///< the shape's polygon as a face: exact plane, chart, convex pieces
  /// Per scene face: its bounding box (min x, y, z, max x, y, z) in doubles, for culling.
  std::vector<std::array<double, 6>> boxes;
  double diagonal = 1.0;  ///< of the scene's faces' bounding box (the sun's prisms stop there)
  /// Sun disks: the frame of the central direction c (u, v across it), the cone's spread across
  /// c per unit along it, and every face's box in that frame (min u, v, c, max u, v, c).
  glm::dvec3 u{1, 0, 0}, v{0, 1, 0}, c{0, 0, 1};
  double spread = 0.0;
  std::vector<std::array<double, 6>> sun_boxes;
};

/// Prepares `light` (extended, already checked) over the prepared scene.
/// @throws InputError when the light's polygon is degenerate in exact arithmetic.
AreaLightPrep prepare_area_light(const core::PreparedScene& ctx, const Light& light, std::size_t light_id);

/// Tests only (tests/compute/test_area_lights.cpp): every occluder piece takes the separating-plane
/// route, so that the two exact routes can be compared on the same scenes. Off by default; set
/// it only while no computation runs.
extern bool force_separating_planes;

/// Per-thread state: the light's exact polygon (Epeck values are never shared between threads).
struct AreaWorker {
  struct Exact;
  std::shared_ptr<Exact> exact;
};

/// The regions of receiver `face_id`: FaceLighting's face_id, light_id, area, fully_lit_area,
/// penumbra_area and umbra_area (the caller fills the rest from the light's centre), and with
/// `polygons` the cells of the three regions as fragments (region set, lit = not umbra).
exact::ReceiverResult compute_area_receiver(const core::PreparedScene& ctx, exact::ExactWorker& w, AreaWorker& aw,
                                            const AreaLightPrep& light, std::size_t face_id, std::size_t light_id,
                                            bool polygons, ShadowStats& stats);

/// A finite extended light (area, disk) shines forward only: a point behind its plane receives
/// nothing, from the centre as from the rest of it. `out` holds the receiver's areas under the
/// light's centre as a point light (lit_area, shadow_area, lit_fraction, lit_area_error_bound);
/// where part of the face lies behind the light's plane, they become those of the centre's lit
/// region cut to the front of that plane (the same plane as the regions', so that
/// umbra_area <= shadow_area and fully_lit_area <= lit_area hold), exact and rounded once (the
/// fast path's bound is then 0). Sun disks and faces wholly in front are left as they are.
void restrict_centre_to_emitting_side(const core::PreparedScene& ctx, exact::ExactWorker& w, AreaWorker& aw,
                                      const AreaLightPrep& light, std::size_t face_id, std::size_t light_id,
                                      const Light& centre, ShadowStats& stats, FaceLighting& out);

}  // namespace shadow::arealight
