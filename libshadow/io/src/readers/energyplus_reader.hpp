// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: EnergyPlus geometry (IDF text or epJSON) read into a scene_readers::Model.
// What is read and how it maps onto libshadow's conventions: docs/energyplus.md.
#pragma once

#include <shadow/scene_io.hpp>

#include "readers/model.hpp"

#include <filesystem>
#include <string>
#include <string_view>

namespace shadow::scene_readers {

/// Reads an EnergyPlus model: IDF text, or epJSON when the file name ends in `.epJSON` (any
/// case) or the text starts with `{`. Surfaces become faces named as in the file (meshes: one
/// per zone, `Shading:Site` and `Shading:Building`, and `Not exposed` for the surfaces that
/// cast but get no sun); windows and doors are cut out of their base surfaces; Site:Location,
/// RunPeriod, Timestep and Building's north axis give Model::sun.
/// @throws InputError {display_name, "line N, Class \"Name\" field \"Field\""} (IDF) or
///         {display_name, JSON path} (epJSON).
Model read_energyplus(const std::filesystem::path& file, const std::string& display_name,
                      const LoadOptions& options);

/// read_energyplus on text in memory; `epjson` picks the syntax.
Model parse_energyplus(const std::string& text, const std::string& display_name, bool epjson,
                       const LoadOptions& options = {});

/// True when `file`'s name ends in `.idf` or `.epJSON` (any case).
bool is_energyplus_file_name(const std::filesystem::path& file);

/// An EnergyPlus version identifier ("9.6", "24.1.0") as major * 100 + minor (9.6 -> 906); 0 for
/// text that is no version (blank, not one to three whole numbers, a major beyond 999).
int energyplus_version_code(std::string_view text);

}  // namespace shadow::scene_readers
