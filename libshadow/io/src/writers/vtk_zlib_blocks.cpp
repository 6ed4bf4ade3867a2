// SPDX-License-Identifier: GPL-3.0-or-later
#include "writers/vtk_zlib_blocks.hpp"

#include "runtime/first_touch.hpp"
#include "runtime/parallel.hpp"

#include <vtkAbstractArray.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkType.h>

#include <libdeflate.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <exception>
#include <new>
#include <utility>

namespace shadow::detail {
namespace {

/// The string array's values as vtkXMLWriter puts them in its blocks: each value's bytes and a
/// terminating zero, one after the other (a value may run on into the next block). Made on
/// `threads` threads, by blocks of values (a million faces' four string arrays were a tenth of a
/// second of one thread): each block's size, then each block's bytes at its place.
std::vector<unsigned char> packed_strings(vtkStringArray* strings, unsigned threads) {
  const std::size_t count = static_cast<std::size_t>(std::max<vtkIdType>(strings->GetNumberOfValues(), 0));
  const vtkStdString* values = count > 0 ? strings->GetPointer(0) : nullptr;
  constexpr std::size_t kBlock = 16384;
  std::vector<std::size_t> start((count + kBlock - 1) / kBlock + 1, 0);
  runtime::parallel_for_blocks(count, kBlock, threads, [&](unsigned, std::size_t b, std::size_t begin, std::size_t end) {
    std::size_t size = 0;
    for (std::size_t i = begin; i < end; ++i) size += values[i].size() + 1;
    start[b + 1] = size;
  });
  for (std::size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
  std::vector<unsigned char> bytes;
  runtime::resize_touched(bytes, start.back(), threads);  // (zeros: every value's terminator)
  runtime::parallel_for_blocks(count, kBlock, threads, [&](unsigned, std::size_t b, std::size_t begin, std::size_t end) {
    unsigned char* out = bytes.data() + start[b];
    for (std::size_t i = begin; i < end; ++i) {
      std::memcpy(out, values[i].data(), values[i].size());
      out += values[i].size() + 1;
    }
  });
  return bytes;
}

/// The file's "offsets" of a cell array: where each cell ends in the connectivity (the cell
/// array's own offsets without their leading zero), as 64-bit integers.
std::vector<unsigned char> end_offsets(vtkCellArray* cells) {
  const vtkIdType cell_count = cells->GetNumberOfCells();
  vtkDataArray* offsets = cells->GetOffsetsArray();
  std::vector<unsigned char> bytes(static_cast<std::size_t>(cell_count) * sizeof(std::int64_t));
  if (offsets->HasStandardMemoryLayout() && offsets->GetDataTypeSize() == sizeof(std::int64_t) &&
      (offsets->GetDataType() == VTK_ID_TYPE || offsets->GetDataType() == VTK_TYPE_INT64)) {
    std::memcpy(bytes.data(), static_cast<const unsigned char*>(offsets->GetVoidPointer(0)) + sizeof(std::int64_t),
                bytes.size());
    return bytes;
  }
  for (vtkIdType c = 0; c < cell_count; ++c) {
    const auto end = static_cast<std::int64_t>(offsets->GetTuple1(c + 1));
    std::memcpy(bytes.data() + static_cast<std::size_t>(c) * sizeof end, &end, sizeof end);
  }
  return bytes;
}

/// `size` bytes as one zlib stream made by `compressor` into `out`, sized to it: 0 bytes where
/// it failed. Always in room of libdeflate's own bound, on the threads and on the writer's
/// thread alike: libdeflate before 1.19 keeps a few bytes of its output buffer free, so straight
/// into the writer's tighter room a stream could fail on one thread count and not another, and
/// the file would depend on it.
void deflate_into(libdeflate_compressor* compressor, const unsigned char* bytes, std::size_t size,
                  std::vector<unsigned char>& out) {
  out.resize(libdeflate_zlib_compress_bound(compressor, size));
  out.resize(libdeflate_zlib_compress(compressor, bytes, size, out.data(), out.size()));
}

}  // namespace

void PrecompressedZLib::DeflateDeleter::operator()(libdeflate_compressor* compressor) const {
  libdeflate_free_compressor(compressor);
}

libdeflate_compressor* PrecompressedZLib::deflater(std::size_t slot) {
  if (deflater_level_ != GetCompressionLevel()) {  // (a level changed: every compressor made again)
    deflaters_.clear();
    deflater_level_ = GetCompressionLevel();
  }
  if (deflaters_.size() <= slot) deflaters_.resize(slot + 1);
  auto& made = deflaters_[slot];
  if (!made) made.reset(libdeflate_alloc_compressor(deflater_level_));
  if (!made) throw std::bad_alloc();  // libdeflate's only failure: no memory
  return made.get();
}

PrecompressedZLib* PrecompressedZLib::New() {
  auto* compressor = new PrecompressedZLib;
  compressor->InitializeObjectBase();
  return compressor;
}

void PrecompressedZLib::add_in_place(vtkAbstractArray* array, std::size_t block_size) {
  // The writer reads arrays with the standard layout (an array of structures) in place, block
  // by block; anything else (bit arrays, other layouts) it copies, and compresses itself here.
  auto* data = vtkDataArray::SafeDownCast(array);
  if (data == nullptr || data->GetDataType() == VTK_BIT || !data->HasStandardMemoryLayout()) return;
  const std::size_t word = static_cast<std::size_t>(data->GetDataTypeSize());
  const std::size_t words = static_cast<std::size_t>(data->GetNumberOfTuples()) *
                            static_cast<std::size_t>(data->GetNumberOfComponents());
  const std::size_t block_words = word == 0 ? 0 : block_size / word;
  if (block_words == 0 || words == 0) return;
  const auto* bytes = static_cast<const unsigned char*>(data->GetVoidPointer(0));
  for (std::size_t at = 0; at < words; at += block_words) {
    Block block;
    block.bytes = bytes + at * word;
    block.size = std::min(block_words, words - at) * word;
    in_place_.emplace(block.bytes, blocks_.size());
    blocks_.push_back(std::move(block));
  }
}

void PrecompressedZLib::add_copied(std::vector<unsigned char> bytes, std::size_t block_size) {
  if (bytes.empty() || block_size == 0) return;
  buffers_.push_back(std::move(bytes));
  const std::vector<unsigned char>& kept = buffers_.back();  // moved: its bytes stay where they are
  for (std::size_t at = 0; at < kept.size(); at += block_size) {
    Block block;
    block.bytes = kept.data() + at;
    block.size = std::min(block_size, kept.size() - at);
    copied_.push_back(blocks_.size());
    blocks_.push_back(std::move(block));
  }
}

void PrecompressedZLib::prepare(vtkPolyData* data, std::size_t block_size, unsigned threads,
                                std::size_t window_bytes) {
  in_place_.clear();
  copied_.clear();
  next_copied_ = 0;
  blocks_.clear();
  buffers_.clear();
  stats_ = {};
  threads_ = std::max(1u, threads);
  window_bytes_ = std::max<std::size_t>(1, window_bytes);

  // The arrays in the order the writer writes them: field data, then the piece's point data,
  // cell data, points and the four cell arrays (connectivity, offsets).
  auto add_arrays = [&](vtkFieldData* arrays) {
    if (arrays == nullptr) return;
    for (int i = 0; i < arrays->GetNumberOfArrays(); ++i) {
      vtkAbstractArray* array = arrays->GetAbstractArray(i);
      if (auto* strings = vtkStringArray::SafeDownCast(array))
        add_copied(packed_strings(strings, threads_), block_size);
      else
        add_in_place(array, block_size);
    }
  };
  add_arrays(data->GetFieldData());
  add_arrays(data->GetPointData());
  add_arrays(data->GetCellData());
  if (data->GetPoints() != nullptr) add_in_place(data->GetPoints()->GetData(), block_size);
  for (vtkCellArray* cells : {data->GetVerts(), data->GetLines(), data->GetStrips(), data->GetPolys()}) {
    if (cells == nullptr || cells->GetNumberOfCells() == 0) continue;
    add_in_place(cells->GetConnectivityArray(), block_size);
    add_copied(end_offsets(cells), block_size - block_size % sizeof(std::int64_t));
  }
  stats_.foreseen = blocks_.size();
  enabled_ = !blocks_.empty();
}

void PrecompressedZLib::rethrow_failure() const {
  if (failure_) std::rethrow_exception(failure_);
}

PrecompressedZLib::Block* PrecompressedZLib::find(const unsigned char* bytes, std::size_t size) {
  if (auto found = in_place_.find(bytes); found != in_place_.end()) {
    Block& block = blocks_[found->second];
    return block.size == size && !block.served ? &block : nullptr;
  }
  if (next_copied_ < copied_.size()) {
    Block& expected = blocks_[copied_[next_copied_]];
    if (expected.size == size && !expected.served && std::memcmp(expected.bytes, bytes, size) == 0) {
      ++next_copied_;
      return &expected;
    }
  }
  return nullptr;
}

void PrecompressedZLib::compress_window(std::size_t first, bool fail_first) {
  // This block and the next ones not yet compressed, in the writer's order, up to the window.
  std::vector<std::size_t> window;
  std::size_t bytes = 0;
  for (std::size_t b = first; b < blocks_.size() && (window.empty() || bytes < window_bytes_); ++b) {
    if (blocks_[b].compressed || blocks_[b].served) continue;
    window.push_back(b);
    bytes += blocks_[b].size;
  }
  // A compressor per worker, made here (not on the workers: the list is not theirs to grow).
  for (unsigned w = 0; w < threads_; ++w) deflater(1 + w);
  runtime::parallel_for(window.size(), threads_, [&](unsigned worker, std::size_t k) {
    Block& block = blocks_[window[k]];
    if (fail_first && k == 0) throw std::bad_alloc();
    deflate_into(deflaters_[1 + worker].get(), block.bytes, block.size, block.zlib);
    block.zlib.shrink_to_fit();
  });
  for (const std::size_t b : window) blocks_[b].compressed = true;
  ++stats_.windows;
}

size_t PrecompressedZLib::failed(std::exception_ptr failure, unsigned char* compressed) {
  if (!failure_) failure_ = std::move(failure);
  enabled_ = false;
  in_place_.clear();
  copied_.clear();
  blocks_.clear();  // what was compressed ahead goes back now
  compressed[0] = 0;
  return 1;
}

size_t PrecompressedZLib::CompressBuffer(unsigned char const* uncompressed, size_t uncompressed_size,
                                         unsigned char* compressed, size_t space) {
  const bool fail = calls_++ == fail_at_call_;
  if (failure_) return failed(nullptr, compressed);  // the file is lost already: end it soon
  Block* block = enabled_ ? find(uncompressed, uncompressed_size) : nullptr;
  if (block != nullptr && !block->compressed) {
    try {
      compress_window(static_cast<std::size_t>(block - blocks_.data()), fail);
    } catch (...) {
      return failed(std::current_exception(), compressed);
    }
  } else if (fail) {
    return failed(std::make_exception_ptr(std::bad_alloc()), compressed);
  }
  if (enabled_ && block != nullptr && !block->zlib.empty() && block->zlib.size() <= space) {
    std::memcpy(compressed, block->zlib.data(), block->zlib.size());
    const std::size_t size = block->zlib.size();
    block->served = true;
    std::vector<unsigned char>().swap(block->zlib);  // written: its memory goes back now
    ++stats_.served;
    return size;
  }
  ++stats_.direct;
  // Here and now, on the writer's thread, the threads' bytes (deflate_into).
  try {
    deflate_into(deflater(0), uncompressed, uncompressed_size, direct_);
  } catch (...) {
    return failed(std::current_exception(), compressed);
  }
  std::size_t size = direct_.size();
  if (size > 0 && size <= space) {
    std::memcpy(compressed, direct_.data(), size);
    return size;
  }
  // libdeflate's stream is longer than zlib's bound, which the writer made room for (a block
  // served from the threads is not then either): zlib's own. vtkZLibDataCompressor fails only
  // when zlib runs out of memory.
  size = vtkZLibDataCompressor::CompressBuffer(uncompressed, uncompressed_size, compressed, space);
  if (size == 0) return failed(std::make_exception_ptr(std::bad_alloc()), compressed);
  return size;
}

}  // namespace shadow::detail
