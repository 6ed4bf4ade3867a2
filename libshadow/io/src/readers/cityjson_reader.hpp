// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: the CityJSON reader (1.1 and 2.0), called by the scene loader's model dispatch.
#pragma once

#include "readers/model.hpp"

#include <shadow/scene_io.hpp>

#include <filesystem>
#include <string>

namespace shadow::scene_readers {

/// Reads the geometry of a CityJSON file (docs/cityjson.md): one mesh per city object with
/// geometry, named by its id; faces named `<id>/<surface index>` (or `<id>/<semantic>-<index>`)
/// with their semantic surface type as Face::kind; inner rings cut out exactly. Sets
/// Model::origin to the file's `transform.translate`.
/// @throws InputError naming the file and the JSON path.
Model read_cityjson(const std::filesystem::path& path, const std::string& display_name,
                    const LoadOptions& options);

}  // namespace shadow::scene_readers
