// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: the VTK datasets of the output files (written by vtp_writer.hpp).
// VTK types stay here, out of the public headers.
#pragma once

#include <shadow/scene.hpp>
#include <shadow/shadows.hpp>
#include <shadow/sun_hours.hpp>

#include <vtkSmartPointer.h>

class vtkPolyData;

namespace shadow::detail {

/// One polygon cell per fragment; cell arrays face_id, light_id, lit, area, fragment_id; point
/// array irradiance (from the cell's light; NaN for lights that are not in `scene`).
vtkSmartPointer<vtkPolyData> make_fragments_polydata(const Scene& scene, const ShadowResult& result);

/// Every input face; cell arrays face_id, mesh_id, mesh, receiver, area, the face's identity
/// (strings name, kind, source) and orientation (normal, 3 components; azimuth, tilt in degrees)
/// and, per light with results, lit_fraction_<name> and lit_area_<name> (NaN where nothing was
/// computed). The faces are filled on `threads` threads (the same dataset for any count).
vtkSmartPointer<vtkPolyData> make_faces_polydata(const Scene& scene, const ShadowResult& result,
                                                 unsigned threads = 1);

/// plane_shadows.vtp: one polygon cell per plane-shadow polygon; cell arrays plane_id, light_id,
/// region_id, area.
vtkSmartPointer<vtkPolyData> make_plane_shadows_polydata(const ShadowResult& result);

/// One vertex per light; point arrays light_id, type, to_light, direction, name, intensity, color.
/// The scene's box (where a sun's glyph stands) is found on `threads` threads.
vtkSmartPointer<vtkPolyData> make_lights_polydata(const Scene& scene, unsigned threads = 1);

/// sun_hours.vtp: one polygon cell per SunHoursCell; cell arrays sun_hours (active scalars),
/// face_id, region_id, area; field data total_hours.
vtkSmartPointer<vtkPolyData> make_sun_hours_polydata(const SunHoursMap& map, bool levels = false);
/// Subtracts Scene::origin from every point of `poly` and records it as the field array `origin`
/// (nothing when the scene has no origin): a model at projected coordinates renders in ParaView
/// without float32 jitter, and the origin tells where it really is.
void shift_to_origin(vtkPolyData* poly, const Scene& scene);

}  // namespace shadow::detail
