// SPDX-License-Identifier: GPL-3.0-or-later
// What a model reader (CityJSON, EnergyPlus IDF/epJSON) hands to the scene loader.
#pragma once

#include <shadow/error.hpp>
#include <shadow/scene.hpp>
#include <shadow/sun.hpp>

#include <optional>
#include <string>
#include <vector>

namespace shadow::scene_readers {

/// A model read from one file: meshes (a city object, a zone or a group of shading surfaces)
/// with their faces, in mesh order. Mesh::first_face and face_count index `faces`; every face
/// carries its `name`, `kind` and `source` (file and JSON path or IDF object and field).
/// Surfaces with holes (a wall with its windows cut out, a CityJSON inner ring) arrive split
/// into hole-free faces that share the surface's name.
struct Model {
  std::vector<Mesh> meshes;
  std::vector<Face> faces;
  /// The sun the model implies (EnergyPlus Site:Location and RunPeriod); absent if none.
  std::optional<SunPeriod> sun;
  std::vector<Warning> warnings;
  /// A point near the model for the VTK outputs (Scene::origin): set by readers of models at
  /// projected coordinates (CityJSON); absent otherwise.
  std::optional<glm::dvec3> origin;
  /// Surfaces the reader could not make faces of and left out (LoadOptions::skip_invalid; without
  /// it they are an InputError). `mesh` is the model mesh's name; no warning is added for them
  /// here: validation warns about every skipped face in one place.
  std::vector<SkippedFace> skipped;
  /// When LoadOptions::cityjson_lod names a level that no object of the file has: the levels it
  /// has ("1.2, 2"), for an error where the scene has that level nowhere; empty otherwise.
  std::string absent_lod_levels;
};

}  // namespace shadow::scene_readers
