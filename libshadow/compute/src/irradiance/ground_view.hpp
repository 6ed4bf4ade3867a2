// SPDX-License-Identifier: GPL-3.0-or-later
// Internal to compute_irradiance: each row's view of the ground (ground.cpp).
#pragma once

#include <shadow/irradiance.hpp>

namespace shadow::irradiance_detail {

/// Fills r.on_ground, r.ground (the lit fractions of r.ground_patches, the ground faces casting
/// no shadow), r.ground_view and r.ground_view_factor_error_bound for the rows r.faces with
/// normals r.normal and areas r.area.
void ground_views(IrradianceResult& r, const ShadowEngine& engine, const Scene& scene, const SeriesOptions& series);

}  // namespace shadow::irradiance_detail
