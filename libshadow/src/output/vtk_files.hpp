// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: the VTK datasets of the output files and their writers.
// VTK types stay here, out of the public headers.
#pragma once

#include <shadow/scene.hpp>
#include <shadow/shadows.hpp>

#include <vtkSmartPointer.h>

#include <filesystem>
#include <string>
#include <vector>

class vtkPolyData;

namespace shadow::detail {

/// One polygon cell per fragment; cell arrays face_id, light_id, lit, area, fragment_id; point
/// array irradiance (from the cell's light; NaN for lights that are not in `scene`).
vtkSmartPointer<vtkPolyData> make_fragments_polydata(const Scene& scene, const ShadowResult& result);

/// Every input face; cell arrays face_id, mesh_id, mesh, receiver, area and, per light with
/// results, lit_fraction_<name> and lit_area_<name> (NaN where nothing was computed).
vtkSmartPointer<vtkPolyData> make_faces_polydata(const Scene& scene, const ShadowResult& result);

/// plane_shadows.vtp: one polygon cell per plane-shadow polygon; cell arrays plane_id, light_id,
/// region_id, area.
vtkSmartPointer<vtkPolyData> make_plane_shadows_polydata(const ShadowResult& result);

/// One vertex per light; point arrays light_id, type, to_light, direction, name, intensity, color.
vtkSmartPointer<vtkPolyData> make_lights_polydata(const Scene& scene);

/// Writes `data` as a binary, appended, zlib-compressed .vtp file.
/// @throws OutputError naming `shown_as` (default: `path`) and VTK's reason.
void write_polydata(vtkPolyData* data, const std::filesystem::path& path,
                    const std::filesystem::path& shown_as = {});

/// A block of the ParaView multiblock file: its name and its file relative to the .vtm.
struct VtmBlock {
  std::string name;
  std::string file;
};

/// Writes a .vtm multiblock file in the form vtkXMLMultiBlockDataWriter (VTK 9.1) writes.
/// @throws OutputError naming `shown_as` (default: `path`) and the system's reason.
void write_vtm(const std::vector<VtmBlock>& blocks, const std::filesystem::path& path,
               const std::filesystem::path& shown_as = {});

/// `name` reduced to [A-Za-z0-9_] (anything else becomes '_'), so it can be part of an array name.
std::string sanitize_array_name(const std::string& name);

/// The names used for per-light arrays (`lit_fraction_<name>`): sanitized, never empty, and
/// unique among `light_ids` (a clash gets the light id appended).
std::vector<std::string> light_array_names(const Scene& scene,
                                           const std::vector<std::size_t>& light_ids);

/// The light ids that have at least one FaceLighting entry, ascending.
std::vector<std::size_t> lights_with_results(const ShadowResult& result);

/// The name of light `light_id`, or "light<id>" for a light that is not in the scene
/// (ShadowEngine::compute can be given any light).
std::string light_display_name(const Scene& scene, std::size_t light_id);

}  // namespace shadow::detail
