// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: the ParaView multiblock file (.vtm) that groups the .vtp files. Plain XML written
// directly: no VTK needed.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace shadow::detail {

/// A block of the ParaView multiblock file: its name and its file relative to the .vtm.
struct VtmBlock {
  std::string name;
  std::string file;
};

/// XML attribute text with & < > " escaped (block names, file names in .vtm and .pvd files).
std::string xml_escape(const std::string& text);

/// Writes a .vtm multiblock file in the form vtkXMLMultiBlockDataWriter (VTK 9.1) writes.
/// @throws OutputError naming `shown_as` (default: `path`) and the system's reason.
void write_vtm(const std::vector<VtmBlock>& blocks, const std::filesystem::path& path,
               const std::filesystem::path& shown_as = {});

}  // namespace shadow::detail
