// SPDX-License-Identifier: GPL-3.0-or-later
#include "writers/vtk_errors.hpp"

namespace shadow::detail {

void VtkErrorCapture::Execute(vtkObject*, unsigned long, void* call_data) {
  if (call_data != nullptr && message_.empty()) message_ = static_cast<const char*>(call_data);
}

std::string VtkErrorCapture::reason() const {
  // VTK's messages end with a newline and start with "ClassName (0x...): ".
  std::string reason = message_;
  while (!reason.empty() && (reason.back() == '\n' || reason.back() == ' ')) reason.pop_back();
  const std::size_t colon = reason.find("): ");
  if (colon != std::string::npos) reason.erase(0, colon + 3);
  return reason;
}

}  // namespace shadow::detail
