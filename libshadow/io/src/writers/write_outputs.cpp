// SPDX-License-Identifier: GPL-3.0-or-later
#include "runtime/parallel.hpp"
#include "writers/series_outputs.hpp"
#include "writers/series_stream.hpp"
#include "writers/staged_files.hpp"
#include "writers/vtk_datasets.hpp"
#include "writers/vtm_writer.hpp"
#include "writers/vtp_writer.hpp"

#include <shadow/error.hpp>
#include <shadow/series_files.hpp>
#include <shadow/output.hpp>
#include <shadow/sun_hours.hpp>

#include <vtkPolyData.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <algorithm>
#include <cstdio>
#include <exception>
#include <fstream>
#include <functional>
#include <iterator>
#include <vector>
#include <string>
#include <system_error>
#include <thread>
#include <utility>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace shadow {

OutputError::OutputError(const std::string& message) : std::runtime_error(escape_control(message)) {}
namespace {

namespace fs = std::filesystem;
using detail::StagedFiles;
using detail::write_staged_stream;
using detail::make_output_directory;
using detail::remove_stale_report;

/// The files write_series() stages at OUTDIR's top level besides faces.vtp and report.json.
const char* const kSeriesOutputNames[] = {"sunlit.csv", "energyplus-shading.csv", "energyplus-objects.idf", "series.pvd",
                                          "fragments.pvd", "sun_hours_by_object.csv"};

using detail::is_series_instant_name;

long process_id() { return static_cast<long>(getpid()); }

/// The files write() stages; their temporaries are `.NAME.tmp-PID`.
const char* const kOutputNames[] = {"fragments.vtp", "faces.vtp", "plane_shadows.vtp", "lights.vtp",
                                    "scene.vtm", "report.json", "sun_hours.vtp", "sun_hours_levels.vtp"};

/// Removes `.NAME.tmp-PID` files of our outputs whose process no longer exists: a run killed
/// with SIGKILL cannot clean up after itself. Files of live processes are left alone.
void remove_stale_temporaries(const fs::path& outdir, bool series_folder = false) {
  std::error_code ec;
  for (fs::directory_iterator it(outdir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    std::vector<std::string> outputs(std::begin(kOutputNames), std::end(kOutputNames));
    outputs.insert(outputs.end(), std::begin(kSeriesOutputNames), std::end(kSeriesOutputNames));
    if (series_folder) {
      outputs.clear();
      const std::size_t tmp = name.find(".tmp-");
      if (name.size() > 1 && name[0] == '.' && tmp != std::string::npos && is_series_instant_name(name.substr(1, tmp - 1)))
        outputs.push_back(name.substr(1, tmp - 1));
    }
    for (const std::string& output : outputs) {
      // `.NAME.tmp-PID`, or the report an earlier run moved aside (remove_stale_report_aside).
      std::string prefix = "." + output + ".tmp-";
      if (name.rfind(prefix, 0) != 0 && output == "report.json") prefix = "." + output + ".old-";
      if (name.rfind(prefix, 0) != 0) continue;
      const std::string digits = name.substr(prefix.size());
      if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) break;
      char* stop = nullptr;
      const long pid = std::strtol(digits.c_str(), &stop, 10);
      if (pid <= 0) break;
      // kill(pid, 0) checks existence without sending anything; ESRCH: no such process.
      if (pid != process_id() && kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) {
        std::error_code ignored;
        fs::remove(it->path(), ignored);
      }
      break;
    }
  }
}

void write_report_file(const StagedFiles::Target& target, const Scene& scene, const ShadowResult& result,
                       const RunInfo* run) {
  write_staged_stream(target, [&](std::ostream& out) {
    if (run != nullptr) write_report_json(out, scene, result, *run);
    else write_report_json(out, scene, result);
  });
}

/// An exclusive flock on OUTDIR/.shadow.lock, released (and the file removed) on destruction.
class DirectoryLock {
 public:
  explicit DirectoryLock(const fs::path& outdir) : path_(outdir / ".shadow.lock") {
    // The file is removed on release, so the inode locked may have been unlinked by its holder
    // between our open and our flock: then try again on the new file.
    for (int attempt = 0; attempt < 100; ++attempt) {
      fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);  // never through a planted link
      if (fd_ < 0)
        throw OutputError(path_.string() + ": cannot create the lock file: " + std::strerror(errno));
      if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
        const int error = errno;
        ::close(fd_);
        fd_ = -1;
        if (error == EWOULDBLOCK)
          throw OutputError(outdir.string() + ": another shadow process is writing to this directory (" +
                            path_.filename().string() + " is locked); wait for it or choose another output");
        throw OutputError(path_.string() + ": cannot lock: " + std::strerror(error));
      }
      struct stat held {}, now {};
      if (::fstat(fd_, &held) == 0 && ::stat(path_.c_str(), &now) == 0 && held.st_ino == now.st_ino &&
          held.st_dev == now.st_dev)
        return;
      ::close(fd_);
      fd_ = -1;
    }
    throw OutputError(path_.string() + ": cannot lock: the lock file keeps changing");
  }
  ~DirectoryLock() {
    if (fd_ < 0) return;
    ::unlink(path_.c_str());  // while still locked: no one else can hold this inode now
    ::close(fd_);
  }
  DirectoryLock(const DirectoryLock&) = delete;
  DirectoryLock& operator=(const DirectoryLock&) = delete;

 private:
  fs::path path_;
  int fd_ = -1;
};

}  // namespace

struct OutputDirectory::Impl {
  fs::path outdir;
  std::unique_ptr<DirectoryLock> lock;
  std::thread removing_report;  ///< removes the old report moved aside (remove_stale_report_aside)
  Impl() = default;
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl() {  // (before the lock is released: members go in reverse order)
    if (removing_report.joinable()) removing_report.join();
  }
};

OutputDirectory::OutputDirectory(const fs::path& outdir) : impl_(std::make_unique<Impl>()) {
  impl_->outdir = outdir;
  make_output_directory(outdir);
  impl_->lock = std::make_unique<DirectoryLock>(outdir);
  remove_stale_temporaries(outdir);
  if (fs::is_directory(outdir / "series")) remove_stale_temporaries(outdir / "series", true);
  // First, before any computing: a run killed from here on leaves no report.json, so nothing
  // in the directory looks like a complete result. (Moved aside at once, removed meanwhile.)
  impl_->removing_report = detail::remove_stale_report_aside(outdir / "report.json");
}

OutputDirectory::~OutputDirectory() = default;

const fs::path& OutputDirectory::path() const noexcept { return impl_->outdir; }

std::vector<fs::path> OutputDirectory::write(const Scene& scene, const ShadowResult& result,
                                             const RunInfo* run) {
  const fs::path& outdir = impl_->outdir;
  make_output_directory(outdir);  // it may have been removed while computing
  remove_stale_report(outdir / "report.json");
  // A sun series' files from an earlier `shadow series` into this OUTDIR would sit beside this
  // run's complete-looking set (an old energyplus-shading.csv ready to import): remove them.
  std::error_code ignored;
  for (const char* old : kSeriesOutputNames) fs::remove(outdir / old, ignored);
  fs::remove(outdir / "sun_hours.vtp", ignored);
  fs::remove(outdir / "sun_hours_levels.vtp", ignored);

  // Each dataset is built just before it is written and freed right after: only one of them
  // is in memory at a time. Errors name the final file, which is what the user asked for.
  StagedFiles staged(outdir);
  // Points relative to Scene::origin when it has one (report.json states it).
  auto shifted = [&scene](vtkSmartPointer<vtkPolyData> poly) {
    detail::shift_to_origin(poly, scene);
    return poly;
  };
  // Fragments first: by far the largest file, so a full disk shows up before the others.
  const auto fragments = staged.stage("fragments.vtp");
  const auto faces = staged.stage("faces.vtp");
  const auto plane_shadows = staged.stage("plane_shadows.vtp");
  const auto lights = staged.stage("lights.vtp");
  const auto vtm = staged.stage("scene.vtm");
  const auto report = staged.stage("report.json");  // staged last, so placed last
  // The zlib blocks of each .vtp made on every thread (the same bytes on any count:
  // vtk_zlib_blocks.hpp).
  const unsigned threads = runtime::resolve_threads(run != nullptr ? run->options.threads : 0);
  auto write_vtk = [&] {
    const detail::VtpWriteOptions vtp{threads};
    detail::write_polydata(shifted(detail::make_fragments_polydata(scene, result)), fragments.temp,
                           fragments.final_path, vtp);
    detail::write_polydata(shifted(detail::make_faces_polydata(scene, result, threads)), faces.temp, faces.final_path, vtp);
    detail::write_polydata(shifted(detail::make_plane_shadows_polydata(result)), plane_shadows.temp,
                           plane_shadows.final_path, vtp);
    detail::write_polydata(shifted(detail::make_lights_polydata(scene, threads)), lights.temp, lights.final_path, vtp);
    detail::write_vtm(
        {{"faces", "faces.vtp"},
         {"fragments", "fragments.vtp"},
         {"plane_shadows", "plane_shadows.vtp"},
         {"lights", "lights.vtp"}},
        vtm.temp, vtm.final_path);
  };
  // The VTK files on this thread, report.json (no VTK) on a thread of its own meanwhile: each
  // leaves the cores idle now and then (the kernel's copy of 560 MB of text for a million faces,
  // the .vtp's serial parts), which the other fills. VTK stays on the calling thread: its errors
  // are captured there only (vtk_errors), and with VTK on a thread of its own a zlib allocation
  // failure while compressing went uncaptured and crashed instead of exiting 6 (ctest
  // cli_out_of_memory). The blocks compressed on the other threads call libdeflate alone, no
  // VTK; out of memory there, or in the report, is std::bad_alloc. The report's failure is
  // rethrown here after the VTK files' own (which comes first: the one the user sees).
  std::exception_ptr report_error;
  std::thread reporting;
  if (threads > 1) {
    try {
      reporting = std::thread([&] {
        try {
          write_report_file(report, scene, result, run);
        } catch (...) {
          report_error = std::current_exception();
        }
      });
    } catch (const std::system_error&) {
      // No thread to be had (a process limit): the report after the VTK files, below.
    }
  }
  struct JoinOnExit {
    std::thread& thread;
    ~JoinOnExit() {
      if (thread.joinable()) thread.join();
    }
  } join_reporting{reporting};
  write_vtk();
  if (reporting.joinable()) reporting.join();
  else write_report_file(report, scene, result, run);
  if (report_error) std::rethrow_exception(report_error);
  return staged.commit();
}

std::vector<fs::path> OutputDirectory::write_series(const Scene& scene, const SunSeries& suns,
                                                    const SeriesResult& series, std::size_t every,
                                                    const RunInfo* run) {
  SeriesFiles files;
  files.every = every;
  return write_series(scene, suns, series, files, run);
}

std::vector<fs::path> OutputDirectory::write_series(const Scene& scene, const SunSeries& suns,
                                                    const SeriesResult& series, const SeriesFiles& files,
                                                    const RunInfo* run) {
  // The whole table through the stream that a series job feeds as its instants complete: one
  // writer, so the files are the same whichever way the series came.
  SeriesFileStream stream = stream_series(scene, suns, series, files);
  for (std::size_t i = 0; i < series.instants; ++i) stream.add(i, SeriesColumn::of(series, i));
  return stream.finish(run);
}

SeriesFileStream OutputDirectory::stream_series(const Scene& scene, const SunSeries& suns, const SeriesResult& shape,
                                                const SeriesFiles& files) {
  return SeriesFileStream(std::make_unique<detail::SeriesStream>(impl_->outdir, scene, suns, shape, files));
}

SeriesFileStream::SeriesFileStream(std::unique_ptr<detail::SeriesStream> impl) : impl_(std::move(impl)) {}
SeriesFileStream::SeriesFileStream(SeriesFileStream&&) noexcept = default;
SeriesFileStream& SeriesFileStream::operator=(SeriesFileStream&&) noexcept = default;
SeriesFileStream::~SeriesFileStream() = default;

void SeriesFileStream::add(std::size_t instant, const SeriesColumn& column) { impl_->add(instant, column); }
void SeriesFileStream::add_stats(const ShadowStats& stats) { impl_->add_stats(stats); }
std::size_t SeriesFileStream::written() const { return impl_->written(); }
std::vector<fs::path> SeriesFileStream::finish(const RunInfo* run) { return impl_->finish(run); }
const SurfaceSeries& SeriesFileStream::surfaces() const { return impl_->surfaces(); }

std::vector<fs::path> write_outputs(const fs::path& outdir, const Scene& scene,
                                    const ShadowResult& result) {
  return OutputDirectory(outdir).write(scene, result);
}

std::vector<fs::path> write_outputs(const fs::path& outdir, const Scene& scene,
                                    const ShadowResult& result, const RunInfo& run) {
  return OutputDirectory(outdir).write(scene, result, &run);
}

void write_sun_hours_vtp(const fs::path& path, const SunHoursMap& map) {
  write_sun_hours_vtp(path, map, Scene{});
}

namespace {

void write_map_vtp(const fs::path& path, const SunHoursMap& map, const Scene& scene, bool levels) {
  fs::path dir = path.parent_path();
  if (dir.empty()) dir = ".";
  make_output_directory(dir);
  StagedFiles staged(dir);
  const auto target = staged.stage(path.filename().string());
  vtkSmartPointer<vtkPolyData> poly = detail::make_sun_hours_polydata(map, levels);
  detail::shift_to_origin(poly, scene);  // like every other dataset of the run (Scene::origin)
  detail::write_polydata(poly, target.temp, target.final_path);
  staged.commit();
}

}  // namespace

void write_sun_hours_vtp(const fs::path& path, const SunHoursMap& map, const Scene& scene) {
  write_map_vtp(path, map, scene, false);
}

void write_sun_hours_levels_vtp(const fs::path& path, const SunHoursMap& map, const Scene& scene) {
  write_map_vtp(path, map, scene, true);
}

void write_file_staged(const fs::path& path, const std::function<void(std::ostream&)>& write) {
  fs::path dir = path.parent_path();
  if (dir.empty()) dir = ".";
  StagedFiles staged(dir);
  write_staged_stream(staged.stage(path.filename().string()), write);
  staged.commit();
}

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

}  // namespace shadow
