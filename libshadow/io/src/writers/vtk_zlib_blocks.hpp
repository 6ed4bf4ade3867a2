// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: the zlib blocks of a .vtp file compressed on every thread before VTK writes it.
//
// vtkXMLWriter cuts each array of the appended data into blocks of BlockSize bytes and hands
// them to its compressor one after the other, on the calling thread: for a million faces that
// was most of the time spent writing faces.vtp. Each block is compressed on its own (its own
// zlib stream), so they can be compressed in any order. PrecompressedZLib knows which blocks
// the writer will ask for (the arrays' own memory, and for string arrays and cell offsets the
// bytes the writer builds from them), compresses them all on every thread first, and then,
// asked by the writer, hands back the block it already has. VTK still writes everything else
// (the XML, the headers, the offsets), so the file is the one VTK writes, byte for byte.
//
// Any block it did not foresee (or whose bytes differ from what it foresaw) is compressed there
// and then by vtkZLibDataCompressor itself, as before: a wrong guess costs time, never bytes.
#pragma once

#include <vtkZLibDataCompressor.h>

#include <cstddef>
#include <unordered_map>
#include <vector>

class vtkAbstractArray;
class vtkPolyData;

namespace shadow::detail {

/// What a PrecompressedZLib did (for tests and measurements).
struct ZLibBlockStats {
  std::size_t prepared = 0;  ///< blocks compressed beforehand on the threads
  std::size_t served = 0;    ///< blocks the writer asked for and got from those
  std::size_t direct = 0;    ///< blocks compressed when asked (not foreseen, or a repeat)
};

/// A vtkZLibDataCompressor (its class name, level and results) whose blocks can be compressed
/// beforehand on several threads. Without prepare() it is vtkZLibDataCompressor.
class PrecompressedZLib : public vtkZLibDataCompressor {
 public:
  // No vtkTypeMacro: the writer names the compressor in the file ("vtkZLibDataCompressor"),
  // and that name must stay.
  static PrecompressedZLib* New();

  /// Compresses, on `threads` threads, every block that a vtkXMLPolyDataWriter writing `data`
  /// with this compressor, `block_size` and 64-bit ids will ask for. `data` must stay alive and
  /// unchanged until the writer is done. Throws std::bad_alloc when zlib runs out of memory.
  void prepare(vtkPolyData* data, std::size_t block_size, unsigned threads);

  const ZLibBlockStats& stats() const { return stats_; }

  PrecompressedZLib(const PrecompressedZLib&) = delete;
  PrecompressedZLib& operator=(const PrecompressedZLib&) = delete;

 protected:
  PrecompressedZLib() = default;
  ~PrecompressedZLib() override = default;

  size_t CompressBuffer(unsigned char const* uncompressed, size_t uncompressed_size,
                        unsigned char* compressed, size_t space) override;

 private:
  /// One block as the writer will hand it over, and its zlib stream once compressed.
  struct Block {
    const unsigned char* bytes = nullptr;
    std::size_t size = 0;
    std::vector<unsigned char> zlib;  ///< empty: not compressed beforehand
    bool served = false;
  };
  void add_in_place(vtkAbstractArray* array, std::size_t block_size);
  void add_copied(std::vector<unsigned char> bytes, std::size_t block_size);

  /// Blocks of arrays the writer reads in place, found by their address.
  std::unordered_map<const unsigned char*, std::size_t> in_place_;
  /// Blocks the writer copies into a buffer of its own first (strings, cell offsets), in the
  /// order it writes them; `next_copied_` is the next one expected.
  std::vector<std::size_t> copied_;
  std::size_t next_copied_ = 0;
  std::vector<Block> blocks_;
  /// The bytes of the copied blocks, built here as the writer builds them.
  std::vector<std::vector<unsigned char>> buffers_;
  ZLibBlockStats stats_;
};

}  // namespace shadow::detail
