// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: writing a VTK dataset as a .vtp file.
#pragma once

#include <filesystem>

class vtkPolyData;

namespace shadow::detail {

struct ZLibBlockStats;

/// Writes `data` as a binary, appended, zlib-compressed .vtp file (vtkXMLPolyDataWriter). With
/// `threads` above 1 the zlib blocks are compressed on that many threads first
/// (vtk_zlib_blocks.hpp): the same bytes, sooner. `stats`, if given, says how the blocks went.
/// @throws OutputError naming `shown_as` (default: `path`) and VTK's reason; std::bad_alloc
/// when compressing runs out of memory.
void write_polydata(vtkPolyData* data, const std::filesystem::path& path,
                    const std::filesystem::path& shown_as = {}, unsigned threads = 1,
                    ZLibBlockStats* stats = nullptr);

}  // namespace shadow::detail
