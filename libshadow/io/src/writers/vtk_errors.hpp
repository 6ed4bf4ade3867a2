// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: VTK's error messages captured instead of printed, so that a failure becomes one
// OutputError line.
#pragma once

#include <vtkCommand.h>

#include <string>

namespace shadow::detail {

/// Observes vtkCommand::ErrorEvent on VTK objects and keeps the first message, so that it does
/// not go to stderr: `object->AddObserver(vtkCommand::ErrorEvent, capture)`.
class VtkErrorCapture : public vtkCommand {
 public:
  static VtkErrorCapture* New() { return new VtkErrorCapture; }
  void Execute(vtkObject* caller, unsigned long event, void* call_data) override;

  /// The first message as VTK sent it ("ClassName (0x...): reason\n"); empty when none came.
  const std::string& message() const { return message_; }
  /// The first message without VTK's "ClassName (0x...): " prefix and trailing newline.
  std::string reason() const;

 private:
  std::string message_;
};

}  // namespace shadow::detail
