// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: the zlib blocks of a .vtp file, made by libdeflate on every thread while VTK writes it.
//
// vtkXMLWriter cuts each array of the appended data into blocks of BlockSize bytes and hands
// them to its compressor one after the other, on the calling thread: for a million faces that
// was most of the time spent writing faces.vtp. Each block is compressed on its own (its own
// zlib stream), so they can be compressed in any order. PrecompressedZLib knows which blocks
// the writer will ask for (the arrays' own memory, and for string arrays and cell offsets the
// bytes the writer builds from them) and in which order. Asked for a block it has not
// compressed yet, it compresses that block and those after it, a window of about
// `window_bytes`, on every thread (libdeflate alone: no VTK off the calling thread), then hands
// them over one by one as the writer asks. VTK still writes everything else (the XML, the
// headers, the offsets); at most a window's compressed blocks are held at a time.
//
// Every block is a zlib stream made by libdeflate, whose level 1 deflates a million faces'
// arrays in about 0.4 of zlib's time at level 1, a little smaller (docs/benchmarks.md,
// "Twenty-seventh look"), but for a block whose stream would be longer than zlib's bound (which
// the writer makes room for): zlib's own then. The file names vtkZLibDataCompressor, and every
// zlib reader (VTK's, ParaView's, Python's zlib) inflates it as it would VTK's own: only the
// compressed bytes differ from those VTK would write, never the arrays they hold. Any block it
// did not foresee (or whose bytes differ from what it foresaw) is compressed there and then, in
// the same way: the file's bytes do not depend on the thread count.
#pragma once

#include <vtkZLibDataCompressor.h>

#include <cstddef>
#include <exception>
#include <memory>
#include <unordered_map>
#include <vector>

class vtkAbstractArray;
class vtkPolyData;
struct libdeflate_compressor;

namespace shadow::detail {

/// What a PrecompressedZLib did (for tests and measurements).
struct ZLibBlockStats {
  std::size_t foreseen = 0;  ///< blocks expected from the dataset
  std::size_t served = 0;    ///< blocks the writer asked for and got from the threads
  std::size_t direct = 0;    ///< blocks compressed when asked (not foreseen, or a repeat)
  std::size_t windows = 0;   ///< rounds of compression on the threads
};

/// A vtkZLibDataCompressor (its class name and level, zlib streams) whose blocks libdeflate
/// makes: in windows on several threads after prepare(), else one by one as the writer asks.
class PrecompressedZLib : public vtkZLibDataCompressor {
 public:
  // No vtkTypeMacro: the writer names the compressor in the file ("vtkZLibDataCompressor"),
  // and that name must stay.
  static PrecompressedZLib* New();

  /// The window of blocks compressed at once unless told otherwise: 32 MiB before compression.
  static constexpr std::size_t kWindowBytes = std::size_t{32} << 20;

  /// Lists, in the writer's order, every block that a vtkXMLPolyDataWriter writing `data` with
  /// this compressor, `block_size` and 64-bit ids will ask for, to be compressed on `threads`
  /// threads about `window_bytes` at a time. `data` must stay alive and unchanged until the
  /// writer is done.
  void prepare(vtkPolyData* data, std::size_t block_size, unsigned threads,
               std::size_t window_bytes = kWindowBytes);

  /// Rethrows what failed while compressing, if anything (std::bad_alloc when libdeflate or zlib
  /// ran out of memory, on the threads or on the writer's): the writer itself never sees an exception,
  /// nor a failed block (VTK 9.1 would dereference the null array it then gets). From a failure
  /// on, every block is one placeholder byte, so the writer ends soon; its file must go.
  void rethrow_failure() const;

  /// For tests: the `call`-th block the writer asks for (from 0) fails as if zlib ran out of
  /// memory, whether it is compressed on the threads or when asked.
  void fail_for_test(std::size_t call) { fail_at_call_ = call; }

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
    std::vector<unsigned char> zlib;
    bool compressed = false;  ///< tried on the threads (`zlib` empty if it did not fit)
    bool served = false;
  };
  void add_in_place(vtkAbstractArray* array, std::size_t block_size);
  void add_copied(std::vector<unsigned char> bytes, std::size_t block_size);
  /// The block the writer hands over, if foreseen: found by address, or the next copied one.
  Block* find(const unsigned char* bytes, std::size_t size);
  /// Compresses block `first` and those after it not yet compressed, a window, on the threads.
  /// `fail_first`: its first block fails as out of memory (fail_for_test).
  void compress_window(std::size_t first, bool fail_first);
  /// A failed block: the failure kept for rethrow_failure(), a placeholder byte for the writer.
  size_t failed(std::exception_ptr failure, unsigned char* compressed);
  /// libdeflate's compressor of `slot` (0: the writer's thread; 1 + w: worker w) at this
  /// compressor's level, made on first use. @throws std::bad_alloc when libdeflate has no memory.
  libdeflate_compressor* deflater(std::size_t slot);
  struct DeflateDeleter {
    void operator()(libdeflate_compressor* compressor) const;
  };

  /// Blocks of arrays the writer reads in place, found by their address.
  std::unordered_map<const unsigned char*, std::size_t> in_place_;
  /// Blocks the writer copies into a buffer of its own first (strings, cell offsets), in the
  /// order it writes them; `next_copied_` is the next one expected.
  std::vector<std::size_t> copied_;
  std::size_t next_copied_ = 0;
  std::vector<Block> blocks_;  ///< in the writer's order
  /// The bytes of the copied blocks, built here as the writer builds them.
  std::vector<std::vector<unsigned char>> buffers_;
  unsigned threads_ = 1;
  std::size_t window_bytes_ = kWindowBytes;
  bool enabled_ = false;  ///< off: every block compressed when asked
  std::vector<std::unique_ptr<libdeflate_compressor, DeflateDeleter>> deflaters_;  ///< by slot
  int deflater_level_ = -1;  ///< the level deflaters_ were made at
  std::vector<unsigned char> direct_;  ///< a block compressed when asked, before it is copied
  std::exception_ptr failure_;
  std::size_t calls_ = 0;
  std::size_t fail_at_call_ = static_cast<std::size_t>(-1);
  ZLibBlockStats stats_;
};

}  // namespace shadow::detail
