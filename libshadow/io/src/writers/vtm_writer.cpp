// SPDX-License-Identifier: GPL-3.0-or-later
#include "writers/vtm_writer.hpp"

#include <shadow/output.hpp>

#include <cerrno>
#include <cstring>
#include <fstream>

namespace shadow::detail {

std::string xml_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

void write_vtm(const std::vector<VtmBlock>& blocks, const std::filesystem::path& path,
               const std::filesystem::path& shown_as) {
  // The layout vtkXMLMultiBlockDataWriter of VTK 9.1 produces, with files next to the .vtm
  // rather than in a subdirectory, so the .vtp files are usable on their own too.
  std::string xml =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"vtkMultiBlockDataSet\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n"
      "  <vtkMultiBlockDataSet>\n";
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    xml += "    <DataSet index=\"" + std::to_string(i) + "\" name=\"" + xml_escape(blocks[i].name) +
           "\" file=\"" + xml_escape(blocks[i].file) + "\"/>\n";
  }
  xml += "  </vtkMultiBlockDataSet>\n</VTKFile>\n";

  errno = 0;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (out) out.write(xml.data(), static_cast<std::streamsize>(xml.size()));
  if (out) out.close();
  if (!out) {
    const int saved_errno = errno;
    throw OutputError((shown_as.empty() ? path : shown_as).string() + ": " +
                      (saved_errno != 0 ? std::strerror(saved_errno) : "could not write the file"));
  }
}

}  // namespace shadow::detail
