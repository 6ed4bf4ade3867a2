// SPDX-License-Identifier: GPL-3.0-or-later
#include "writers/vtp_writer.hpp"

#include "writers/vtk_errors.hpp"
#include "writers/vtk_zlib_blocks.hpp"

#include <shadow/output.hpp>

#include <vtkCommand.h>
#include <vtkErrorCode.h>
#include <vtkExecutive.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataWriter.h>

#include <cerrno>
#include <cstring>
#include <string>

namespace shadow::detail {

static_assert(VtpWriteOptions{}.window_bytes == PrecompressedZLib::kWindowBytes);

void write_polydata(vtkPolyData* data, const std::filesystem::path& path,
                    const std::filesystem::path& shown_as, const VtpWriteOptions& options) {
  vtkNew<vtkXMLPolyDataWriter> writer;
  // The writer reports the cause (when it knows one); its executive then adds a generic
  // "returned failure" dump that says nothing useful: keep it off stderr, and out of the message.
  vtkNew<VtkErrorCapture> errors;
  vtkNew<VtkErrorCapture> pipeline_errors;
  writer->AddObserver(vtkCommand::ErrorEvent, errors);
  writer->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, pipeline_errors);
  writer->SetFileName(path.string().c_str());
  writer->SetInputData(data);
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff();  // raw binary: base64 would add a third to the size
  writer->SetCompressorTypeToZLib();
  writer->SetCompressionLevel(kVtpZlibLevel);
  writer->SetHeaderTypeToUInt64();  // blocks over 4 GiB stay addressable
  writer->SetIdTypeToInt64();
  // A zlib compressor of the same class name and level, its blocks made by libdeflate (on every
  // thread as the writer comes to them); a failed block never reaches the writer
  // (vtk_zlib_blocks.hpp).
  vtkNew<PrecompressedZLib> compressor;
  vtkNew<VtkErrorCapture> compressor_errors;  // zlib's failures, told by the writer's error
  compressor->AddObserver(vtkCommand::ErrorEvent, compressor_errors);
  compressor->SetCompressionLevel(writer->GetCompressor()->GetCompressionLevel());
  writer->SetCompressor(compressor);
  if (options.threads > 1)
    compressor->prepare(data, static_cast<std::size_t>(writer->GetBlockSize()), options.threads, options.window_bytes);
  compressor->fail_for_test(options.fail_at_block);

  errno = 0;
  const int ok = writer->Write();
  const unsigned long code = writer->GetErrorCode();
  if (options.stats != nullptr) *options.stats = compressor->stats();
  compressor->rethrow_failure();  // out of memory: std::bad_alloc, the file unfinished
  if (ok == 1 && code == vtkErrorCode::NoError) return;

  const int saved_errno = errno;
  std::string reason = errors->reason();
  if (reason.empty()) reason = compressor_errors->reason();
  // VTK quotes the file it opened: that is the temporary name, which means nothing to users.
  const std::string quoted_path = " \"" + path.string() + "\"";
  if (const std::size_t at = reason.find(quoted_path); at != std::string::npos)
    reason.erase(at, quoted_path.size());
  if (reason.empty() && code != vtkErrorCode::NoError)
    reason = vtkErrorCode::GetStringFromErrorCode(code);
  // VTK's codes below its own range are errno values, so the system's reason may be there already.
  const std::string system_reason = saved_errno != 0 ? std::strerror(saved_errno) : "";
  if (!system_reason.empty() && reason.find(system_reason) == std::string::npos)
    reason += (reason.empty() ? "" : ": ") + system_reason;
  if (reason.empty()) reason = "VTK could not write the file";
  throw OutputError((shown_as.empty() ? path : shown_as).string() + ": " + reason);
}

}  // namespace shadow::detail
