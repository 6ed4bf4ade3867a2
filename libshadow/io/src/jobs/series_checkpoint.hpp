// SPDX-License-Identifier: GPL-3.0-or-later
// The columns of a sun series in transit and at rest: what an MPI rank sends to rank 0, and what
// OUTDIR/series.checkpoint keeps of a long run so that `--resume` computes only what is missing
// (docs/cluster.md). Doubles travel and rest as their raw bits, so the gathered or resumed
// series is the uninterrupted one's, bit for bit.
#pragma once

#include <shadow/series.hpp>
#include <shadow/shadows.hpp>
#include <shadow/sun_hours.hpp>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace shadow::jobs {

/// The columns of some instants of a series: what compute_series gave for them.
struct SeriesColumns {
  std::vector<std::uint64_t> instants;  ///< indices into the series' lights
  std::size_t rows = 0;                 ///< SeriesResult::faces.size()
  /// Instant-major (k * rows + row), for instants[k].
  std::vector<double> lit_area, lit_fraction, lit_area_error_bound;
  std::vector<unsigned char> faces_light;
  shadow::ShadowStats stats;  ///< of these instants
};

/// The columns of `part`, computed by compute_series on the lights of `instants` (in order).
SeriesColumns columns_of(const shadow::SeriesResult& part, const std::vector<std::uint64_t>& instants);

/// Puts `columns` into `full` (every instant's table) and adds their stats.
/// @throws std::runtime_error when they do not fit (another shape: a bug, or a corrupt record)
void place_columns(const SeriesColumns& columns, shadow::SeriesResult& full);

/// Raw bytes of `columns` (little-endian bits, as the machine holds them) and back.
std::string encode_columns(const SeriesColumns& columns);
/// @throws std::runtime_error on a malformed or truncated message
SeriesColumns decode_columns(const std::string& bytes);

/// The sun-hours map in transit (a rank's faces) and the merge of the parts in face order.
std::string encode_map(const shadow::SunHoursMap& map);
shadow::SunHoursMap decode_map(const std::string& bytes);
/// Parts computed on consecutive blocks of the ascending face list: their concatenation, each
/// part's region ids shifted by the earlier parts' SunHoursMap::regions (what one call on all
/// faces numbers them).
shadow::SunHoursMap merge_maps(const std::vector<shadow::SunHoursMap>& parts);

/// What the columns depend on, as a 64-bit digest: libshadow's version, the arithmetic, every
/// face's vertices (bits), mesh and receiver flag, every instant's light direction and time, and
/// the tile threshold of the arithmetic (tile_casters, or fast_tile_casters with --fast) when it
/// is not the default: fast tiles change lit areas within their bounds, and tiles change the
/// stats' candidate counts. Output-only options (--every, --fragments, --sun-hours-map) and the
/// threads are left out: a resumed run may change them.
std::uint64_t series_digest(const shadow::Scene& scene, const shadow::SunSeries& suns, const shadow::SeriesOptions& options);

/// OUTDIR/series.checkpoint: a header (format, digest, shape, the run's start time) and then one
/// record per completed round of instants, appended and flushed to disk as the run goes. Each
/// record carries its length and a checksum, so a record torn by a kill is recognised and
/// dropped on resume (with everything after it).
class Checkpoint {
 public:
  static std::filesystem::path file(const std::filesystem::path& outdir) { return outdir / "series.checkpoint"; }

  /// A new, empty checkpoint at `path` (written under a temporary name and renamed into place).
  /// @throws shadow::OutputError
  static Checkpoint create(const std::filesystem::path& path, std::uint64_t digest, std::size_t rows,
                           std::size_t instants, const std::string& started_utc);

  /// What an existing checkpoint holds, read back for --resume.
  struct Contents {
    std::vector<SeriesColumns> records;
    std::string started_utc;
    std::uint64_t valid_bytes = 0;  ///< length of the header and the records that passed their checks
    bool torn = false;              ///< bytes after the last good record (a write cut short)
  };
  /// Reads `path` and checks it against this run.
  /// @throws shadow::InputError naming the file when it is not a checkpoint, or was written for
  /// another scene, other options or another version (digest or shape differ)
  static Contents read(const std::filesystem::path& path, std::uint64_t digest, std::size_t rows, std::size_t instants);
  /// The same, handing each good record to `record` as it is read (Contents::records stays
  /// empty): one record in memory at a time. An InputError or OutputError that `record` throws
  /// passes through.
  static Contents read(const std::filesystem::path& path, std::uint64_t digest, std::size_t rows, std::size_t instants,
                       const std::function<void(const SeriesColumns&)>& record);

  /// Opens the checkpoint at `path` to append after its first `valid_bytes` (cutting a torn tail).
  /// @throws shadow::OutputError
  static Checkpoint reopen(const std::filesystem::path& path, std::uint64_t valid_bytes);

  Checkpoint(Checkpoint&& other) noexcept;
  Checkpoint& operator=(Checkpoint&&) = delete;
  Checkpoint(const Checkpoint&) = delete;
  ~Checkpoint();

  /// Appends one record and flushes it to disk (fsync). @throws shadow::OutputError
  void append(const SeriesColumns& columns);

  /// Closes and removes the file (the run is complete: its outputs are in place).
  void remove();

 private:
  Checkpoint(std::filesystem::path path, std::FILE* file) : path_(std::move(path)), file_(file) {}
  std::filesystem::path path_;
  std::FILE* file_ = nullptr;
};

}  // namespace shadow::jobs
