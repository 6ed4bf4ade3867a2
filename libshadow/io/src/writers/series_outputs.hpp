// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: the datasets and the report of a sun series (OutputDirectory::write_series).
#pragma once

#include <shadow/output.hpp>
#include <shadow/series.hpp>

#include <vtkSmartPointer.h>

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

class vtkPolyData;

namespace shadow::detail {

/// A sun series' per-instant file name in OUTDIR/series/: `sun_NNNNN.vtp` or `fragments_NNNNN.vtp`.
bool is_series_instant_name(const std::string& name);

/// Every face (geometry, face_id, mesh, receiver, area), the base of the series datasets.
vtkSmartPointer<vtkPolyData> make_series_base(const Scene& scene);

/// The faces at one instant: the base with cell arrays `lit_fraction`, `lit_area`,
/// `faces_light` (and `lit_area_error_bound` for the fast path); NaN on faces not computed.
vtkSmartPointer<vtkPolyData> make_series_instant(vtkPolyData* base, const SeriesResult& series,
                                                 std::size_t instant);
/// The same for one column (`shape`: the rows and the arithmetic; its cells are not read).
vtkSmartPointer<vtkPolyData> make_series_instant(vtkPolyData* base, const SeriesResult& shape,
                                                 const SeriesColumn& column);

/// faces.vtp of a series: the base with `sun_hours` (and `sun_hours_error_bound`, fast path).
vtkSmartPointer<vtkPolyData> make_series_faces(vtkPolyData* base, const SeriesResult& series,
                                               const std::vector<double>& sun_hours,
                                               const std::vector<double>& sun_hours_bound);

/// A ParaView collection (.pvd): one DataSet per (time value, file).
/// @throws OutputError naming `shown_as`
void write_pvd(const std::vector<std::pair<double, std::string>>& steps, const std::filesystem::path& path,
               const std::filesystem::path& shown_as);

/// report.json of a series.
void write_series_report_json(std::ostream& out, const Scene& scene, const SunSeries& suns,
                              const SeriesResult& series, const SurfaceSeries& surfaces,
                              const ObjectSunHours& objects,
                              const std::vector<double>& sun_hours, const std::vector<double>& sun_hours_bound,
                              const EnergyPlusSchedule& energyplus, std::size_t every, const RunInfo* run);

}  // namespace shadow::detail
