// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: writing a VTK dataset as a .vtp file.
#pragma once

#include <filesystem>

class vtkPolyData;

namespace shadow::detail {

/// Writes `data` as a binary, appended, zlib-compressed .vtp file.
/// @throws OutputError naming `shown_as` (default: `path`) and VTK's reason.
void write_polydata(vtkPolyData* data, const std::filesystem::path& path,
                    const std::filesystem::path& shown_as = {});

}  // namespace shadow::detail
