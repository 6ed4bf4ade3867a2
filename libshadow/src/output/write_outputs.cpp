// SPDX-License-Identifier: GPL-3.0-or-later
#include "output/vtk_files.hpp"

#include <shadow/output.hpp>

#include <vtkPolyData.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>
#include <system_error>
#include <utility>

#ifdef _WIN32
#include <process.h>
#else
#include <unistd.h>
#endif

namespace shadow {
namespace {

namespace fs = std::filesystem;

long process_id() {
#ifdef _WIN32
  return static_cast<long>(_getpid());
#else
  return static_cast<long>(getpid());
#endif
}

/// Output files written under temporary names. Whatever is not yet in place when this goes
/// out of scope (an error, an exception) is removed, so no half-written file stays behind.
class StagedFiles {
 public:
  explicit StagedFiles(fs::path dir) : dir_(std::move(dir)) {}
  StagedFiles(const StagedFiles&) = delete;
  StagedFiles& operator=(const StagedFiles&) = delete;
  ~StagedFiles() {
    for (const Entry& e : entries_) {
      std::error_code ignored;
      if (!e.placed) fs::remove(e.temp, ignored);
    }
  }

  /// A file to write: `temp` (hidden, unique to this process) becomes `final_path` on commit.
  struct Target {
    fs::path temp;
    fs::path final_path;
  };

  Target stage(const std::string& name) {
    Entry e;
    e.final_path = dir_ / name;
    e.temp = dir_ / ("." + name + ".tmp-" + std::to_string(process_id()));
    entries_.push_back(e);
    return {e.temp, e.final_path};
  }

  /// Renames every staged file into place, in staging order.
  std::vector<fs::path> commit() {
    std::vector<fs::path> placed;
    for (Entry& e : entries_) {
      std::error_code ec;
      fs::rename(e.temp, e.final_path, ec);
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
    fs::path temp;
    fs::path final_path;
    bool placed = false;
  };
  fs::path dir_;
  std::vector<Entry> entries_;
};

/// Creates `outdir` and its parents; an existing directory is fine.
void make_output_directory(const fs::path& outdir) {
  std::error_code ec;
  const fs::file_status status = fs::status(outdir, ec);
  if (fs::exists(status)) {
    if (!fs::is_directory(status))
      throw OutputError(outdir.string() + ": exists and is not a directory");
    return;
  }
  fs::create_directories(outdir, ec);
  if (ec) {
    throw OutputError(outdir.string() + ": cannot create the output directory: " + ec.message());
  }
}

/// Removes a report.json of an earlier run before anything new is written, so that an
/// interrupted run never leaves old results that look complete next to new files.
void remove_stale_report(const fs::path& report) {
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(report, ec);
  if (!fs::exists(status)) return;
  if (fs::is_directory(status))
    throw OutputError(report.string() + ": is a directory; cannot replace it with the report");
  fs::remove(report, ec);
  if (ec) throw OutputError(report.string() + ": cannot remove the old report: " + ec.message());
}

void write_report_file(const fs::path& path, const fs::path& shown_as, const Scene& scene,
                       const ShadowResult& result) {
  errno = 0;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (out) write_report_json(out, scene, result);
  if (out) out.close();
  if (!out) {
    const int saved_errno = errno;
    throw OutputError(shown_as.string() + ": " +
                      (saved_errno != 0 ? std::strerror(saved_errno) : "could not write the file"));
  }
}

}  // namespace

std::vector<fs::path> write_outputs(const fs::path& outdir, const Scene& scene,
                                    const ShadowResult& result) {
  make_output_directory(outdir);
  remove_stale_report(outdir / "report.json");

  // Each dataset is built just before it is written and freed right after: only one of them
  // is in memory at a time. Errors name the final file, which is what the user asked for.
  StagedFiles staged(outdir);
  // Fragments first: by far the largest file, so a full disk shows up before the others.
  const auto fragments = staged.stage("fragments.vtp");
  detail::write_polydata(detail::make_fragments_polydata(scene, result), fragments.temp,
                         fragments.final_path);
  const auto faces = staged.stage("faces.vtp");
  detail::write_polydata(detail::make_faces_polydata(scene, result), faces.temp, faces.final_path);
  const auto plane_shadows = staged.stage("plane_shadows.vtp");
  detail::write_polydata(detail::make_plane_shadows_polydata(result), plane_shadows.temp,
                         plane_shadows.final_path);
  const auto lights = staged.stage("lights.vtp");
  detail::write_polydata(detail::make_lights_polydata(scene), lights.temp, lights.final_path);
  const auto vtm = staged.stage("scene.vtm");
  detail::write_vtm(
      {{"faces", "faces.vtp"},
       {"fragments", "fragments.vtp"},
       {"plane_shadows", "plane_shadows.vtp"},
       {"lights", "lights.vtp"}},
      vtm.temp, vtm.final_path);
  const auto report = staged.stage("report.json");  // staged last, so placed last
  write_report_file(report.temp, report.final_path, scene, result);
  return staged.commit();
}

}  // namespace shadow
