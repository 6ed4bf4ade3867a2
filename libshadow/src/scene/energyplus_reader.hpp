// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: the EnergyPlus reader (IDF and epJSON), called by the scene loader's model dispatch
// (scene/model_dispatch.cpp). Defined in scene/energyplus_reader.cpp.
#pragma once

#include "scene/model.hpp"

#include <shadow/scene_io.hpp>

#include <filesystem>
#include <string>

namespace shadow::scene_readers {

/// Reads the geometry of an EnergyPlus model, IDF or epJSON (told apart by the file's extension,
/// `.idf` or `.epJSON`, or else by its content), from `path`; errors and sources name the file as
/// `display_name` (the path as the user gave it). Surfaces keep their EnergyPlus names; Model::sun
/// is the sun its Site:Location and RunPeriod imply.
/// @throws InputError naming the file, the object and the field.
Model read_energyplus(const std::filesystem::path& path, const std::string& display_name,
                      const LoadOptions& options);

}  // namespace shadow::scene_readers
