// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: writing a VTK dataset as a .vtp file.
#pragma once

#include <cstddef>
#include <filesystem>

class vtkPolyData;

namespace shadow::detail {

struct ZLibBlockStats;

/// The deflate level of every .vtp: 1, the fastest. Against zlib's level 5 (VTK's default), a
/// million faces' faces.vtp was written in about half the time and 14% larger; readers inflate
/// either alike (docs/benchmarks.md, "zlib's fastest level"). libdeflate makes the blocks at
/// this level (vtk_zlib_blocks.hpp).
inline constexpr int kVtpZlibLevel = 1;

/// How write_polydata compresses.
struct VtpWriteOptions {
  /// Threads compressing the zlib blocks; 1: on the calling thread, as VTK does.
  unsigned threads = 1;
  /// Blocks compressed at once, in bytes before compression (PrecompressedZLib::kWindowBytes).
  std::size_t window_bytes = std::size_t{32} << 20;
  /// For tests: this block (from 0, in the writer's order) fails as if zlib ran out of memory.
  std::size_t fail_at_block = static_cast<std::size_t>(-1);
  /// If given, how the blocks went.
  ZLibBlockStats* stats = nullptr;
};

/// Writes `data` as a binary, appended, zlib-compressed .vtp file (vtkXMLPolyDataWriter; the
/// zlib blocks made by libdeflate at kVtpZlibLevel, vtk_zlib_blocks.hpp). With
/// `options.threads` above 1 the blocks are compressed on that many threads, a window at a
/// time: the same bytes, sooner.
/// @throws OutputError naming `shown_as` (default: `path`) and VTK's reason; std::bad_alloc
/// when the compressor (libdeflate or zlib) runs out of memory (the file at `path` is then unfinished: the caller removes it).
void write_polydata(vtkPolyData* data, const std::filesystem::path& path,
                    const std::filesystem::path& shown_as = {}, const VtpWriteOptions& options = {});

}  // namespace shadow::detail
