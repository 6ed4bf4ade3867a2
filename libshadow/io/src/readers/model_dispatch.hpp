// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: which model format a file is (by extension, else by content), and reading it.
#pragma once

#include "readers/model.hpp"

#include <shadow/scene_io.hpp>

#include <filesystem>
#include <string>
#include <string_view>

namespace shadow::scene_readers {

enum class ModelFormat {
  none,        ///< not a model: a scene JSON or an OBJ file
  cityjson,    ///< CityJSON (`.city.json`, or JSON whose top-level "type" is "CityJSON")
  energyplus,  ///< EnergyPlus IDF (`.idf`, or a line opening `Version,`, `Zone,`, ...) or epJSON
               ///< (`.epJSON`, or JSON with a top-level "Version" and EnergyPlus geometry objects)
};

/// The model format of `file`. `.idf`, `.epjson` and `.city.json` (any case) decide by name;
/// `.obj` is never a model; any other name is decided by the content (`text`: the whole file).
/// JSON is parsed for its top-level keys, never judged by a prefix: a CityJSON file may name
/// its "type" after megabytes of city objects.
ModelFormat model_format(const std::filesystem::path& file, std::string_view text);

/// True when `text` is JSON by its first character (`{` or `[` after blanks and a byte order mark).
bool is_json_text(std::string_view text);

/// Reads a model of the given format (not `none`) with its reader.
/// @throws InputError
Model read_model(ModelFormat format, const std::filesystem::path& path, const std::string& display_name,
                 const LoadOptions& options);

}  // namespace shadow::scene_readers
