// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: how every writer of io puts its files in place. Each file is written under a
// temporary name beside it (`.NAME.tmp-PID`) and renamed into place by commit(), in staging
// order (report.json staged last, so placed last); whatever is not in place when the stager goes
// out of scope is removed, so an error never leaves a half-written file that looks complete.
#pragma once

#include <shadow/output.hpp>  // OutputError

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <ostream>
#include <string>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

namespace shadow::detail {

/// Output files written under temporary names. Whatever is not yet in place when this goes
/// out of scope (an error, an exception) is removed, so no half-written file stays behind.
class StagedFiles {
 public:
  explicit StagedFiles(std::filesystem::path dir) : dir_(std::move(dir)) {}
  StagedFiles(const StagedFiles&) = delete;
  StagedFiles& operator=(const StagedFiles&) = delete;
  ~StagedFiles() {
    for (const Entry& e : entries_) {
      std::error_code ignored;
      if (!e.placed) std::filesystem::remove(e.temp, ignored);
    }
  }

  /// A file to write: `temp` (hidden, unique to this process) becomes `final_path` on commit.
  struct Target {
    std::filesystem::path temp;
    std::filesystem::path final_path;
  };

  Target stage(const std::string& name) {
    Entry e;
    e.final_path = dir_ / name;
    // A name in a subfolder (series/sun_00000.vtp) gets its temporary beside it.
    e.temp = e.final_path.parent_path() / ("." + e.final_path.filename().string() + ".tmp-" + std::to_string(static_cast<long>(::getpid())));
    // Whatever is at that name now is not ours (a leftover of an earlier process with our pid, or
    // a planted symbolic link that the writers would follow): remove the entry itself first.
    std::error_code ignored;
    std::filesystem::remove(e.temp, ignored);
    entries_.push_back(e);
    return {e.temp, e.final_path};
  }

  /// Renames every staged file into place, in staging order.
  std::vector<std::filesystem::path> commit() {
    std::vector<std::filesystem::path> placed;
    for (Entry& e : entries_) {
      std::error_code ec;
      std::filesystem::rename(e.temp, e.final_path, ec);
      if (ec) {
        throw OutputError(e.final_path.string() + ": cannot move the finished file into place: " +
                          ec.message());
      }
      e.placed = true;
      placed.push_back(e.final_path);
    }
    return placed;
  }

 private:
  struct Entry {
    std::filesystem::path temp;
    std::filesystem::path final_path;
    bool placed = false;
  };
  std::filesystem::path dir_;
  std::vector<Entry> entries_;
};

/// Writes `target.temp` through `write` with a checked close: a stream error (a full disk, a
/// quota, a file size limit) while writing or flushing becomes an OutputError naming the final
/// file, which is what the user asked for, with the system's reason.
inline void write_staged_stream(const StagedFiles::Target& target, const std::function<void(std::ostream&)>& write) {
  errno = 0;
  std::ofstream out(target.temp, std::ios::binary | std::ios::trunc);
  if (out) write(out);
  if (out) out.close();  // the last buffer reaches the file here: its failure counts too
  if (!out) {
    const int saved_errno = errno;
    throw OutputError(target.final_path.string() + ": " +
                      (saved_errno != 0 ? std::strerror(saved_errno) : "could not write the file"));
  }
}

/// Creates `outdir` and its parents; an existing directory is fine.
inline void make_output_directory(const std::filesystem::path& outdir) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(outdir, ec);
  if (std::filesystem::exists(status)) {
    if (!std::filesystem::is_directory(status))
      throw OutputError(outdir.string() + ": exists and is not a directory");
    return;
  }
  std::filesystem::create_directories(outdir, ec);
  if (ec) {
    throw OutputError(outdir.string() + ": cannot create the output directory: " + ec.message());
  }
}

/// Removes a report.json of an earlier run before anything new is written, so that an
/// interrupted run never leaves old results that look complete next to new files.
inline void remove_stale_report(const std::filesystem::path& report) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::symlink_status(report, ec);
  if (!std::filesystem::exists(status)) return;
  if (std::filesystem::is_directory(status))
    throw OutputError(report.string() + ": is a directory; cannot replace it with the report");
  std::filesystem::remove(report, ec);
  if (ec) throw OutputError(report.string() + ": cannot remove the old report: " + ec.message());
}

/// The name remove_stale_report_aside() gives the report it moves aside: `.report.json.old-PID`.
inline std::filesystem::path report_aside(const std::filesystem::path& report) {
  return report.parent_path() /
         ("." + report.filename().string() + ".old-" + std::to_string(static_cast<long>(::getpid())));
}

/// remove_stale_report with its slow part in the background: the report is renamed aside at
/// once (report_aside(): from here on no report is there, as after remove_stale_report), and the
/// renamed file is removed on the thread returned, which the caller joins. Removing a large
/// report frees its pages in the kernel and, where the earlier run's writes are still on their
/// way to the disk, waits for them: a million faces' 560 MB took 0.05-0.2 s in which the rest
/// of the run waited. Where the rename fails, or no thread starts, the report is removed here
/// (the thread returned is then not joinable). A run killed before the thread is done leaves the
/// hidden file, which a later run into the directory removes (its process is gone).
inline std::thread remove_stale_report_aside(const std::filesystem::path& report) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::symlink_status(report, ec);
  if (!std::filesystem::exists(status) || std::filesystem::is_directory(status)) {
    remove_stale_report(report);  // (nothing there; or a directory: its error)
    return {};
  }
  const std::filesystem::path aside = report_aside(report);
  std::filesystem::remove(aside, ec);  // a leftover of an earlier process with our pid
  std::filesystem::rename(report, aside, ec);
  if (ec) {
    remove_stale_report(report);
    return {};
  }
  try {
    return std::thread([aside] {
      std::error_code ignored;
      std::filesystem::remove(aside, ignored);
    });
  } catch (const std::exception&) {  // no thread (or no memory for its copy of the name)
    std::filesystem::remove(aside, ec);
    return {};
  }
}

}  // namespace shadow::detail
