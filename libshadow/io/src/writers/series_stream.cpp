// SPDX-License-Identifier: GPL-3.0-or-later
// The files of a sun series, written as its instants arrive (series_stream.hpp).
#include "writers/series_stream.hpp"

#include "writers/series_outputs.hpp"
#include "writers/vtk_datasets.hpp"
#include "writers/vtp_writer.hpp"

#include <shadow/series_files.hpp>

#include <vtkPolyData.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <system_error>

namespace shadow::detail {
namespace {

namespace fs = std::filesystem;

/// Opens `target.temp` for writing. @throws OutputError naming the final file
void open_staged(std::ofstream& out, const StagedFiles::Target& target) {
  errno = 0;
  out.open(target.temp, std::ios::binary | std::ios::trunc);
  if (!out) {
    const int saved = errno;
    throw OutputError(target.final_path.string() + ": " + (saved != 0 ? std::strerror(saved) : "could not write the file"));
  }
}

}  // namespace

/// A column that came before its turn: a copy, instant-major (stride 1).
struct SeriesStream::Owned {
  std::vector<double> lit_area, lit_fraction, lit_area_error_bound;
  std::vector<unsigned char> faces_light;
  [[nodiscard]] SeriesColumn view() const {
    return {lit_area.data(), lit_fraction.data(), faces_light.data(), lit_area_error_bound.data(), 1};
  }
};

SeriesStream::SeriesStream(const fs::path& outdir, const Scene& scene, const SunSeries& suns, const SeriesResult& shape,
                           const OutputDirectory::SeriesFiles& files)
    : outdir_(outdir), scene_(scene), suns_(suns), files_(files), staged_(outdir) {
  shape_.faces = shape.faces;
  shape_.area = shape.area;
  shape_.instants = shape.instants;
  shape_.arithmetic = shape.arithmetic;
  shape_.stats = shape.stats;
  make_output_directory(outdir_);
  remove_stale_report(outdir_ / "report.json");
  const std::size_t rows = shape_.faces.size();
  row_of_.assign(scene.faces.size(), SIZE_MAX);
  for (std::size_t r = 0; r < rows; ++r)
    if (shape_.faces[r] < row_of_.size()) row_of_[shape_.faces[r]] = r;
  fraction_sum_.assign(rows, 0.0);
  bound_sum_.assign(rows, 0.0);
  lit_sum_.assign(rows, 0.0);
  // The named surfaces and their areas, as surface_series() makes them (faces in their order).
  surfaces_.instants = shape_.instants;
  surfaces_.surfaces = named_surfaces(scene, true);
  surfaces_.area.assign(surfaces_.surfaces.size(), 0.0);
  for (std::size_t s = 0; s < surfaces_.surfaces.size(); ++s)
    for (const std::size_t f : surfaces_.surfaces[s].faces)
      if (f < row_of_.size() && row_of_[f] != SIZE_MAX) surfaces_.area[s] += shape_.area[row_of_[f]];
  surface_sum_.assign(surfaces_.surfaces.size(), 0.0);
  fractions_.assign(surfaces_.surfaces.size(), 0.0);

  // Staged in the order write_series has always placed them: the CSVs, the per-instant
  // datasets as they come, the collections, faces.vtp, report.json.
  sunlit_target_ = staged_.stage("sunlit.csv");
  open_staged(sunlit_, sunlit_target_);
  write_sunlit_header(sunlit_, surfaces_.surfaces);
  if (files_.energyplus_shading.value_or(energyplus_shading_wanted(scene)))
    energyplus_schedule_ = energyplus_schedule(scene);
  else
    energyplus_schedule_.reason =
        files_.energyplus_shading || scene.energyplus_shading
            ? "not asked for (energyplus_shading false)"
            : "not asked for: the scene has no EnergyPlus model (shadow series --energyplus-shading, or "
              "the scene key \"energyplus_shading\": true, writes it)";
  if (energyplus_schedule_.written) {
    energyplus_target_ = staged_.stage("energyplus-shading.csv");
    open_staged(energyplus_, energyplus_target_);
    energyplus_rows_.emplace(scene, suns, shape_.instants, surfaces_.surfaces.size(), energyplus_schedule_);
    energyplus_rows_->header(energyplus_, surfaces_.surfaces);
  }
  // How to use the CSV: the objects that make EnergyPlus import it, beside it.
  if (energyplus_schedule_.written && !files_.energyplus_objects.empty()) {
    const auto objects = staged_.stage("energyplus-objects.idf");
    write_staged_stream(objects, [&](std::ostream& out) { out << files_.energyplus_objects; });
  }
  by_object_target_ = staged_.stage("sun_hours_by_object.csv");  // written by finish()
  // The instants' datasets share the base's points: shifting it (Scene::origin) shifts them all.
  base_ = make_series_base(scene);
  shift_to_origin(base_, scene);
  if (files_.every > 0) make_output_directory(outdir_ / "series");
}

SeriesStream::~SeriesStream() = default;

void SeriesStream::add(std::size_t instant, const SeriesColumn& column) {
  if (instant >= shape_.instants || instant < next_ || waiting_.count(instant) != 0)
    throw std::logic_error("series stream: instant " + std::to_string(instant) + " out of range or given twice");
  if (instant != next_) {
    // Early: a copy waits for the instants before it (ranks, or a resumed checkpoint's holes).
    auto owned = std::make_unique<Owned>();
    const std::size_t rows = shape_.faces.size();
    owned->lit_area.resize(rows);
    owned->lit_fraction.resize(rows);
    owned->lit_area_error_bound.resize(rows);
    owned->faces_light.resize(rows);
    for (std::size_t r = 0; r < rows; ++r) {
      const std::size_t at = r * column.stride;
      owned->lit_area[r] = column.lit_area[at];
      owned->lit_fraction[r] = column.lit_fraction[at];
      owned->lit_area_error_bound[r] = column.lit_area_error_bound[at];
      owned->faces_light[r] = column.faces_light[at];
    }
    waiting_.emplace(instant, std::move(owned));
    return;
  }
  emit(instant, column);
  for (auto it = waiting_.begin(); it != waiting_.end() && it->first == next_; it = waiting_.erase(it))
    emit(it->first, it->second->view());
}

void SeriesStream::emit(std::size_t i, const SeriesColumn& column) {
  const std::size_t rows = shape_.faces.size(), stride = column.stride;
  // Running sums in instant order: the whole-table functions add in the same order.
  for (std::size_t r = 0; r < rows; ++r) {
    fraction_sum_[r] += column.lit_fraction[r * stride];
    bound_sum_[r] += column.lit_area_error_bound[r * stride];
    lit_sum_[r] += column.lit_area[r * stride];
  }
  // Each surface's lit fraction at this instant, as surface_series() computes it.
  for (std::size_t s = 0; s < surfaces_.surfaces.size(); ++s) {
    const std::vector<std::size_t>& faces = surfaces_.surfaces[s].faces;
    double fraction = 0.0;
    if (faces.size() == 1 && faces[0] < row_of_.size() && row_of_[faces[0]] != SIZE_MAX) {
      fraction = column.lit_fraction[row_of_[faces[0]] * stride];  // a single face: its own exact fraction
    } else if (surfaces_.area[s] > 0.0) {
      double lit = 0.0;
      for (const std::size_t f : faces)
        if (f < row_of_.size() && row_of_[f] != SIZE_MAX) lit += column.lit_area[row_of_[f] * stride];
      fraction = std::min(1.0, lit / surfaces_.area[s]);
    }
    fractions_[s] = fraction;
    surface_sum_[s] += fraction;
  }
  write_sunlit_row(sunlit_, suns_, i, fractions_);
  check_stream(sunlit_, sunlit_target_);
  if (energyplus_rows_) {
    energyplus_rows_->instant(energyplus_, i, fractions_);
    check_stream(energyplus_, energyplus_target_);
  }
  if (files_.every > 0 && i % files_.every == 0) {
    char name[64];  // room for any size_t
    std::snprintf(name, sizeof name, "series/sun_%05zu.vtp", i);
    const auto target = staged_.stage(name);
    write_polydata(make_series_instant(base_, shape_, column), target.temp, target.final_path);
    // ParaView's time: hours since the first instant (UTC seconds would lose its slider's digits).
    const double t = i < suns_.times.size() ? static_cast<double>(suns_.times[i] - suns_.times.front()) / 3600.0
                                            : static_cast<double>(i);
    steps_.emplace_back(t, name);
    instant_files_.push_back(fs::path(name).filename().string());
    if (files_.fragments) {
      // One instant's polygons at a time: a year of them would not fit in memory.
      const ShadowResult result = files_.fragments(i);
      std::snprintf(name, sizeof name, "series/fragments_%05zu.vtp", i);
      const auto fragments = staged_.stage(name);
      vtkSmartPointer<vtkPolyData> poly = make_fragments_polydata(scene_, result);
      shift_to_origin(poly, scene_);
      write_polydata(poly, fragments.temp, fragments.final_path);
      fragment_steps_.emplace_back(t, name);
      instant_files_.push_back(fs::path(name).filename().string());
    }
  }
  ++next_;
}

void SeriesStream::check_stream(std::ofstream& out, const StagedFiles::Target& target) {
  if (out) return;
  const int saved = errno;
  throw OutputError(target.final_path.string() + ": " + (saved != 0 ? std::strerror(saved) : "could not write the file"));
}

void SeriesStream::close_stream(std::ofstream& out, const StagedFiles::Target& target) {
  errno = 0;
  if (out) out.close();  // the last buffer reaches the file here: its failure counts too
  check_stream(out, target);
}

std::vector<fs::path> SeriesStream::finish(const RunInfo* run) {
  if (next_ != shape_.instants || !waiting_.empty())
    throw std::logic_error("series stream: " + std::to_string(next_) + " of " + std::to_string(shape_.instants) +
                           " instants written");
  close_stream(sunlit_, sunlit_target_);
  if (energyplus_rows_) {
    energyplus_schedule_ = energyplus_rows_->finish(energyplus_);
    close_stream(energyplus_, energyplus_target_);
  }
  const fs::path& outdir = outdir_;
  std::error_code ignored;
  if (!energyplus_schedule_.written || files_.energyplus_objects.empty())
    fs::remove(outdir / "energyplus-objects.idf", ignored);
  // The sums as a table of one instant: sun_hours() and the others then add each row's sum to
  // 0.0 (which leaves it as it is) and finish as they do on the whole table, bit for bit.
  SeriesResult sums = shape_;
  sums.instants = 1;
  sums.lit_fraction = fraction_sum_;
  sums.lit_area_error_bound = bound_sum_;
  sums.lit_area = lit_sum_;
  sums.faces_light.assign(shape_.faces.size(), 0);
  const double hours_per_instant = suns_.hours_per_instant;
  const std::vector<double> hours = sun_hours(sums, hours_per_instant);
  const std::vector<double> bound = sun_hours_error_bound(sums, hours_per_instant);
  const ObjectSunHours objects = object_sun_hours(scene_, sums, hours_per_instant);
  surfaces_.sun_hours.resize(surface_sum_.size());
  for (std::size_t s = 0; s < surface_sum_.size(); ++s) surfaces_.sun_hours[s] = surface_sum_[s] * hours_per_instant;

  // Sun hours per building (CityJSON object, parts rolled up), EnergyPlus zone or mesh.
  write_staged_stream(by_object_target_, [&](std::ostream& out) { write_sun_hours_by_object_csv(out, objects); });
  if (!energyplus_schedule_.written) {
    // Not this run's (report.json says why): an older one must not pass for it.
    fs::remove(outdir / "energyplus-shading.csv", ignored);
  }
  const std::size_t every = files_.every;
  if (every > 0) {
    const auto pvd = staged_.stage("series.pvd");
    write_pvd(steps_, pvd.temp, pvd.final_path);
    if (files_.fragments) {
      const auto fragments_pvd = staged_.stage("fragments.pvd");
      write_pvd(fragment_steps_, fragments_pvd.temp, fragments_pvd.final_path);
    }
  }
  const auto faces = staged_.stage("faces.vtp");
  write_polydata(make_series_faces(base_, shape_, hours, bound), faces.temp, faces.final_path);
  const auto report = staged_.stage("report.json");  // staged last, so placed last
  write_staged_stream(report, [&](std::ostream& out) {
    write_series_report_json(out, scene_, suns_, shape_, surfaces_, objects, hours, bound, energyplus_schedule_, every,
                             run);
  });
  // Files of an earlier series that this one does not have would look like part of it.
  std::error_code ec;
  for (fs::directory_iterator it(outdir / "series", ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (is_series_instant_name(name) && std::find(instant_files_.begin(), instant_files_.end(), name) == instant_files_.end())
      fs::remove(it->path(), ignored);
  }
  if (every == 0) fs::remove(outdir / "series.pvd", ignored);
  if (every == 0 || !files_.fragments) fs::remove(outdir / "fragments.pvd", ignored);
  return staged_.commit();
}

}  // namespace shadow::detail
