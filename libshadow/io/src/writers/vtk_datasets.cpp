// SPDX-License-Identifier: GPL-3.0-or-later
#include "writers/vtk_datasets.hpp"

#include "core/lights.hpp"
#include "runtime/parallel.hpp"
#include "geometry/unit_vector.hpp"
#include "lighting/fragment_irradiance.hpp"
#include "writers/face_orientation.hpp"
#include "writers/names.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkFieldData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkType.h>
#include <vtkTypeInt32Array.h>
#include <vtkTypeInt64Array.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <vector>

namespace shadow::detail {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Cells per item when a dataset is filled on several threads.
constexpr std::size_t kCellsPerItem = 4096;

/// Runs fill(begin, end) over [0, count) in ranges of kCellsPerItem on `threads` threads (each
/// cell written by one range only, so the result does not depend on the thread count).
template <typename Fill>
void for_cell_ranges(std::size_t count, unsigned threads, const Fill& fill) {
  const std::size_t items = (count + kCellsPerItem - 1) / kCellsPerItem;
  if (threads <= 1 || items <= 1) {
    fill(std::size_t{0}, count);
    return;
  }
  runtime::parallel_for(items, threads, [&](unsigned, std::size_t item) {
    fill(item * kCellsPerItem, std::min(count, (item + 1) * kCellsPerItem));
  });
}

/// Polygons given as (vertex count, vertex at) packed into Float64 points and one cell array.
/// Points are not shared between cells: the fragments of neighbouring faces rarely share
/// vertices exactly, and merging would cost a hash map as large as the output. The offsets are
/// summed first; the points and connectivity are then filled on `threads` threads.
template <typename CountFn, typename VertexFn>
void fill_polygons(vtkPolyData* poly, std::size_t cell_count, CountFn count, VertexFn vertex,
                   unsigned threads = 1) {
  vtkNew<vtkIdTypeArray> offsets;
  offsets->SetNumberOfValues(static_cast<vtkIdType>(cell_count) + 1);
  vtkIdType* offset = offsets->GetPointer(0);
  vtkIdType point_count = 0;
  for (std::size_t c = 0; c < cell_count; ++c) {
    offset[c] = point_count;
    point_count += static_cast<vtkIdType>(count(c));
  }
  offset[cell_count] = point_count;

  vtkNew<vtkDoubleArray> coords;
  coords->SetNumberOfComponents(3);
  coords->SetNumberOfTuples(point_count);
  vtkNew<vtkIdTypeArray> connectivity;
  connectivity->SetNumberOfValues(point_count);
  double* xyz = coords->GetPointer(0);
  vtkIdType* ids = connectivity->GetPointer(0);
  for_cell_ranges(cell_count, threads, [&](std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c) {
      vtkIdType next = offset[c];
      const std::size_t n = static_cast<std::size_t>(offset[c + 1] - offset[c]);
      for (std::size_t i = 0; i < n; ++i, ++next) {
        const glm::dvec3& p = vertex(c, i);
        xyz[3 * next + 0] = p.x;
        xyz[3 * next + 1] = p.y;
        xyz[3 * next + 2] = p.z;
        ids[next] = next;
      }
    }
  });

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetData(coords);
  vtkNew<vtkCellArray> polys;
  polys->SetData(offsets, connectivity);
  poly->SetPoints(points);
  poly->SetPolys(polys);
}

template <typename Array>
vtkSmartPointer<Array> make_array(const char* name, std::size_t tuples, int components = 1) {
  auto array = vtkSmartPointer<Array>::New();
  array->SetName(name);
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(static_cast<vtkIdType>(tuples));
  return array;
}

/// Bounding box of every face vertex (an empty scene gets the unit box at the origin).
struct Box {
  glm::dvec3 centre{0.0};
  double diagonal = 1.0;
};

/// On `threads` threads, in blocks of faces (a million faces' vertices took some 30 ms on one):
/// minima and maxima are exact, so the box is the same on any count.
Box scene_box(const Scene& scene, unsigned threads) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr std::size_t kBlock = 16384;
  const std::size_t blocks = (scene.faces.size() + kBlock - 1) / kBlock;
  std::vector<glm::dvec3> block_lo(blocks, glm::dvec3(kInf)), block_hi(blocks, glm::dvec3(-kInf));
  runtime::parallel_for_blocks(scene.faces.size(), kBlock, threads,
                               [&](unsigned, std::size_t b, std::size_t begin, std::size_t end) {
                                 glm::dvec3 lo(kInf), hi(-kInf);
                                 for (std::size_t f = begin; f < end; ++f)
                                   for (const glm::dvec3& v : scene.faces[f].vertices) {
                                     lo = glm::min(lo, v);
                                     hi = glm::max(hi, v);
                                   }
                                 block_lo[b] = lo;
                                 block_hi[b] = hi;
                               });
  glm::dvec3 lo(kInf), hi(-kInf);
  for (std::size_t b = 0; b < blocks; ++b) {
    lo = glm::min(lo, block_lo[b]);
    hi = glm::max(hi, block_hi[b]);
  }
  Box box;
  if (!(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z)) return box;
  box.centre = 0.5 * (lo + hi);
  const double diagonal = glm::length(hi - lo);
  // A single point (or a flat speck) would put the sun on the scene: keep a visible distance.
  if (std::isfinite(diagonal) && diagonal > 0.0) box.diagonal = diagonal;
  return box;
}

// v / |v|, or zero when v has no usable direction (validation rejects such lights anyway).
using geometry::unit_or_zero;

}  // namespace

vtkSmartPointer<vtkPolyData> make_fragments_polydata(const Scene& scene, const ShadowResult& result) {
  const std::vector<Fragment>& fragments = result.fragments;
  const std::size_t n = fragments.size();
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  fill_polygons(
      poly, n, [&](std::size_t c) { return fragments[c].polygon.size(); },
      [&](std::size_t c, std::size_t i) -> const glm::dvec3& { return fragments[c].polygon[i]; });

  auto face_id = make_array<vtkTypeInt64Array>("face_id", n);
  auto light_id = make_array<vtkTypeInt32Array>("light_id", n);
  auto lit = make_array<vtkTypeInt32Array>("lit", n);
  auto area = make_array<vtkDoubleArray>("area", n);
  auto fragment_id = make_array<vtkTypeInt64Array>("fragment_id", n);
  for (std::size_t c = 0; c < n; ++c) {
    const Fragment& f = fragments[c];
    const auto cell = static_cast<vtkIdType>(c);
    face_id->SetValue(cell, static_cast<vtkTypeInt64>(f.face_id));
    light_id->SetValue(cell, static_cast<vtkTypeInt32>(f.light_id));
    lit->SetValue(cell, f.lit ? 1 : 0);
    area->SetValue(cell, f.area);
    fragment_id->SetValue(cell, static_cast<vtkTypeInt64>(f.fragment_id));
  }
  vtkCellData* cd = poly->GetCellData();
  cd->AddArray(face_id);
  cd->AddArray(light_id);
  cd->AddArray(lit);
  cd->AddArray(area);
  cd->AddArray(fragment_id);
  // Extended lights' regions (0 fully lit, 1 penumbra, 2 umbra; -1 for a point light's cells),
  // only when the scene has an extended light: other files stay as they were.
  bool extended = false;
  for (const Light& light : scene.lights) extended |= light.is_extended();
  if (extended) {
    auto region = make_array<vtkTypeInt32Array>("region", n);
    for (std::size_t c = 0; c < n; ++c)
      region->SetValue(static_cast<vtkIdType>(c), static_cast<vtkTypeInt32>(fragments[c].region));
    cd->AddArray(region);
  }

  // Points are not shared between cells, so each point takes the irradiance of its own cell's
  // light (lighting/fragment_irradiance.hpp).
  std::size_t point_count = 0;
  for (const Fragment& f : fragments) point_count += f.polygon.size();
  auto irradiance = make_array<vtkDoubleArray>("irradiance", point_count);
  double* values = irradiance->GetPointer(0);
  for (const Fragment& f : fragments) {
    fragment_irradiance(scene, f, values);
    values += f.polygon.size();
  }
  // Extended lights (docs/area-light-visibility.md): the irradiance through the visible part of
  // the light, and the visible fraction `visibility` (0..1) at each point; a point light's
  // points get 1 where lit and 0 in shadow. Scenes without extended lights write neither change.
  std::vector<std::size_t> extended_ids;
  for (std::size_t l = 0; l < scene.lights.size(); ++l)
    if (scene.lights[l].is_extended()) extended_ids.push_back(l);
  bool any_visibility = false;
  for (const Fragment& f : fragments) any_visibility = any_visibility || !f.visibility.empty();
  vtkSmartPointer<vtkDoubleArray> visibility;
  if (!extended_ids.empty() && any_visibility) {
    // The engine computed the irradiance with the visibility (Fragment::irradiance): kept, not
    // recomputed here.
    double* e = irradiance->GetPointer(0);
    for (const Fragment& f : fragments) {
      if (f.irradiance.size() == f.polygon.size()) std::copy(f.irradiance.begin(), f.irradiance.end(), e);
      e += f.polygon.size();
    }
    visibility = make_array<vtkDoubleArray>("visibility", point_count);
    double* v = visibility->GetPointer(0);
    for (const Fragment& f : fragments)
      for (std::size_t i = 0; i < f.polygon.size(); ++i)
        *v++ = i < f.visibility.size() ? f.visibility[i] : (f.lit ? 1.0 : 0.0);
  }
  poly->GetPointData()->AddArray(irradiance);
  if (visibility) poly->GetPointData()->AddArray(visibility);
  // ParaView colours by the active scalars when a file is opened: lit/shadowed is the view
  // people want first.
  cd->SetActiveScalars("lit");
  return poly;
}

vtkSmartPointer<vtkPolyData> make_plane_shadows_polydata(const ShadowResult& result) {
  // One cell per polygon of every plane shadow, in plane then light order.
  std::vector<std::pair<const PlaneShadow*, std::size_t>> cells;
  for (const PlaneShadow& shadow : result.plane_shadows)
    for (std::size_t c = 0; c < shadow.polygons.size(); ++c) cells.emplace_back(&shadow, c);
  const std::size_t n = cells.size();
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  fill_polygons(
      poly, n, [&](std::size_t c) { return cells[c].first->polygons[cells[c].second].size(); },
      [&](std::size_t c, std::size_t i) -> const glm::dvec3& { return cells[c].first->polygons[cells[c].second][i]; });
  auto plane_id = make_array<vtkTypeInt32Array>("plane_id", n);
  auto light_id = make_array<vtkTypeInt32Array>("light_id", n);
  auto region_id = make_array<vtkTypeInt64Array>("region_id", n);
  auto area = make_array<vtkDoubleArray>("area", n);
  for (std::size_t c = 0; c < n; ++c) {
    const PlaneShadow& s = *cells[c].first;
    const auto cell = static_cast<vtkIdType>(c);
    plane_id->SetValue(cell, static_cast<vtkTypeInt32>(s.plane_id));
    light_id->SetValue(cell, static_cast<vtkTypeInt32>(s.light_id));
    region_id->SetValue(cell, static_cast<vtkTypeInt64>(s.region_id[cells[c].second]));
    area->SetValue(cell, s.polygon_area[cells[c].second]);
  }
  vtkCellData* cd = poly->GetCellData();
  cd->AddArray(plane_id);
  cd->AddArray(light_id);
  cd->AddArray(region_id);
  cd->AddArray(area);
  cd->SetActiveScalars("light_id");
  return poly;
}

vtkSmartPointer<vtkPolyData> make_faces_polydata(const Scene& scene, const ShadowResult& result, unsigned threads) {
  const std::size_t n = scene.faces.size();
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  fill_polygons(
      poly, n, [&](std::size_t c) { return scene.faces[c].vertices.size(); },
      [&](std::size_t c, std::size_t i) -> const glm::dvec3& {
        return scene.faces[c].vertices[i];
      },
      threads);

  auto face_id = make_array<vtkTypeInt64Array>("face_id", n);
  auto mesh_id = make_array<vtkTypeInt32Array>("mesh_id", n);
  auto mesh = vtkSmartPointer<vtkStringArray>::New();
  mesh->SetName("mesh");
  mesh->SetNumberOfValues(static_cast<vtkIdType>(n));
  auto receiver = make_array<vtkTypeInt32Array>("receiver", n);
  auto area = make_array<vtkDoubleArray>("area", n);
  area->Fill(kNaN);
  auto name = vtkSmartPointer<vtkStringArray>::New();
  name->SetName("name");
  name->SetNumberOfValues(static_cast<vtkIdType>(n));
  auto kind = vtkSmartPointer<vtkStringArray>::New();
  kind->SetName("kind");
  kind->SetNumberOfValues(static_cast<vtkIdType>(n));
  auto source = vtkSmartPointer<vtkStringArray>::New();
  source->SetName("source");
  source->SetNumberOfValues(static_cast<vtkIdType>(n));
  auto normal = make_array<vtkDoubleArray>("normal", n, 3);
  auto azimuth = make_array<vtkDoubleArray>("azimuth", n);
  auto tilt = make_array<vtkDoubleArray>("tilt", n);
  const double north_axis = north_axis_of(scene);
  // Each face's values written through the arrays' memory, faces in ranges on every thread.
  vtkStdString* face_names = n > 0 ? name->GetPointer(0) : nullptr;
  vtkStdString* kinds = n > 0 ? kind->GetPointer(0) : nullptr;
  vtkStdString* sources = n > 0 ? source->GetPointer(0) : nullptr;
  vtkStdString* meshes = n > 0 ? mesh->GetPointer(0) : nullptr;
  double* normals = normal->GetPointer(0);
  double* azimuths = azimuth->GetPointer(0);
  double* tilts = tilt->GetPointer(0);
  vtkTypeInt64* face_ids = face_id->GetPointer(0);
  vtkTypeInt32* mesh_ids = mesh_id->GetPointer(0);
  vtkTypeInt32* receivers = receiver->GetPointer(0);
  for_cell_ranges(n, threads, [&](std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c) {
      const Face& face = scene.faces[c];
      const bool known_mesh = face.mesh < scene.meshes.size();
      const FaceOrientation o = face_orientation(face, north_axis);
      face_names[c] = face.name;
      kinds[c] = face.kind;
      sources[c] = face.source.to_string();
      normals[3 * c + 0] = o.normal.x;
      normals[3 * c + 1] = o.normal.y;
      normals[3 * c + 2] = o.normal.z;
      azimuths[c] = o.azimuth;
      tilts[c] = o.tilt;
      face_ids[c] = static_cast<vtkTypeInt64>(c);
      mesh_ids[c] = static_cast<vtkTypeInt32>(face.mesh);
      meshes[c] = known_mesh ? scene.meshes[face.mesh].name : std::string();
      receivers[c] = known_mesh && scene.meshes[face.mesh].receiver ? 1 : 0;
    }
  });
  for (vtkAbstractArray* array : {static_cast<vtkAbstractArray*>(name), static_cast<vtkAbstractArray*>(kind),
                                  static_cast<vtkAbstractArray*>(source), static_cast<vtkAbstractArray*>(mesh)})
    array->DataChanged();  // written through their memory: as SetValue would have told them

  // One lit_fraction_/lit_area_ pair per light with results, NaN where the pair was not computed.
  const std::vector<std::size_t> light_ids = lights_with_results(result);
  const std::vector<std::string> names = light_array_names(scene, light_ids);
  std::unordered_map<std::size_t, std::size_t> column_of;
  std::vector<vtkSmartPointer<vtkDoubleArray>> fractions;
  std::vector<vtkSmartPointer<vtkDoubleArray>> lit_areas;
  for (std::size_t k = 0; k < light_ids.size(); ++k) {
    column_of[light_ids[k]] = k;
    fractions.push_back(make_array<vtkDoubleArray>(("lit_fraction_" + names[k]).c_str(), n));
    lit_areas.push_back(make_array<vtkDoubleArray>(("lit_area_" + names[k]).c_str(), n));
    fractions.back()->Fill(kNaN);
    lit_areas.back()->Fill(kNaN);
  }
  for (const FaceLighting& entry : result.lighting) {
    if (entry.face_id >= n) continue;  // a result for another scene: nothing to attach it to
    const auto cell = static_cast<vtkIdType>(entry.face_id);
    const std::size_t k = column_of.at(entry.light_id);
    area->SetValue(cell, entry.area);
    fractions[k]->SetValue(cell, entry.lit_fraction);
    lit_areas[k]->SetValue(cell, entry.lit_area);
  }

  vtkCellData* cd = poly->GetCellData();
  cd->AddArray(face_id);
  cd->AddArray(mesh_id);
  cd->AddArray(mesh);
  cd->AddArray(receiver);
  cd->AddArray(area);
  cd->AddArray(name);
  cd->AddArray(kind);
  cd->AddArray(source);
  cd->AddArray(normal);
  cd->AddArray(azimuth);
  cd->AddArray(tilt);
  for (std::size_t k = 0; k < light_ids.size(); ++k) {
    cd->AddArray(fractions[k]);
    cd->AddArray(lit_areas[k]);
  }
  if (!fractions.empty()) cd->SetActiveScalars(fractions.front()->GetName());
  return poly;
}

vtkSmartPointer<vtkPolyData> make_lights_polydata(const Scene& scene, unsigned threads) {
  const std::size_t n = scene.lights.size();
  const Box box = scene_box(scene, threads);

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(n));
  vtkNew<vtkCellArray> verts;
  auto light_id = make_array<vtkTypeInt32Array>("light_id", n);
  auto type = make_array<vtkTypeInt32Array>("type", n);
  auto to_light = make_array<vtkDoubleArray>("to_light", n, 3);
  auto direction = make_array<vtkDoubleArray>("direction", n, 3);
  auto name = vtkSmartPointer<vtkStringArray>::New();
  name->SetName("name");
  name->SetNumberOfValues(static_cast<vtkIdType>(n));
  auto intensity = make_array<vtkDoubleArray>("intensity", n);
  auto color = make_array<vtkDoubleArray>("color", n, 3);

  for (std::size_t i = 0; i < n; ++i) {
    const Light& light = scene.lights[i];
    const auto id = static_cast<vtkIdType>(i);
    glm::dvec3 position;
    glm::dvec3 toward;
    if (light.type == LightType::Directional) {
      // The sun has no position: put its glyph one scene diagonal away, in its direction.
      toward = unit_or_zero(light.to_light);
      position = box.centre + toward * box.diagonal;
    } else {
      // An area light stands at its centroid (the point that stands for it: core/lights.hpp).
      position = light.type == LightType::Area ? shadow::detail::centre_light(light).position : light.position;
      toward = unit_or_zero(position - box.centre);
    }
    points->SetPoint(id, position.x, position.y, position.z);
    verts->InsertNextCell(1, &id);
    light_id->SetValue(id, static_cast<vtkTypeInt32>(i));
    // 0 directional, 1 point, 2 area, 3 disk
    type->SetValue(id, light.type == LightType::Directional ? 0
                       : light.type == LightType::Area  ? 2
                       : light.type == LightType::Disk  ? 3
                                                        : 1);
    to_light->SetTuple3(id, toward.x, toward.y, toward.z);
    direction->SetTuple3(id, -toward.x, -toward.y, -toward.z);
    name->SetValue(id, light.name);
    intensity->SetValue(id, light.intensity);
    color->SetTuple3(id, light.color.r, light.color.g, light.color.b);
  }

  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetVerts(verts);
  vtkPointData* pd = poly->GetPointData();
  pd->AddArray(light_id);
  pd->AddArray(type);
  pd->AddArray(to_light);
  pd->AddArray(direction);
  pd->AddArray(name);
  pd->AddArray(intensity);
  pd->AddArray(color);
  pd->SetActiveVectors("direction");
  return poly;
}

vtkSmartPointer<vtkPolyData> make_sun_hours_polydata(const SunHoursMap& map, bool levels) {
  const std::vector<SunHoursCell>& cells = levels ? map.level_cells : map.cells;
  const std::size_t n = cells.size();
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  fill_polygons(
      poly, n, [&](std::size_t c) { return cells[c].polygon.size(); },
      [&](std::size_t c, std::size_t i) -> const glm::dvec3& { return cells[c].polygon[i]; });
  const char* value_name = levels ? "level" : "sun_hours";
  auto sun_hours = make_array<vtkDoubleArray>(value_name, n);
  auto face_id = make_array<vtkTypeInt64Array>("face_id", n);
  auto region_id = make_array<vtkTypeInt64Array>("region_id", n);
  auto area = make_array<vtkDoubleArray>("area", n);
  for (std::size_t c = 0; c < n; ++c) {
    const auto cell = static_cast<vtkIdType>(c);
    sun_hours->SetValue(cell, cells[c].sun_hours);
    face_id->SetValue(cell, static_cast<vtkTypeInt64>(cells[c].face_id));
    region_id->SetValue(cell, static_cast<vtkTypeInt64>(cells[c].region_id));
    area->SetValue(cell, cells[c].area);
  }
  vtkCellData* cd = poly->GetCellData();
  cd->AddArray(sun_hours);
  cd->AddArray(face_id);
  cd->AddArray(region_id);
  cd->AddArray(area);
  cd->SetActiveScalars(value_name);  // what ParaView colours by when the file is opened
  // The period's total, so that a legend can span 0..total even where no cell gets every hour.
  auto total = make_array<vtkDoubleArray>("total_hours", 1);
  total->SetValue(0, map.total_hours);
  poly->GetFieldData()->AddArray(total);
  if (levels) {
    // The levels and the exact area reaching each: the planning answer without summing cells.
    const std::vector<double> at_least = sun_hours_level_areas(map);
    auto level_values = make_array<vtkDoubleArray>("levels", map.levels.size());
    auto level_areas = make_array<vtkDoubleArray>("level_areas", map.levels.size());
    for (std::size_t k = 0; k < map.levels.size(); ++k) {
      level_values->SetValue(static_cast<vtkIdType>(k), map.levels[k]);
      level_areas->SetValue(static_cast<vtkIdType>(k), at_least[k]);
    }
    auto whole = make_array<vtkDoubleArray>("area", 1);
    whole->SetValue(0, sun_hours_map_area(map));
    poly->GetFieldData()->AddArray(level_values);
    poly->GetFieldData()->AddArray(level_areas);
    poly->GetFieldData()->AddArray(whole);
  }
  return poly;
}

void shift_to_origin(vtkPolyData* poly, const Scene& scene) {
  if (!scene.origin || poly == nullptr) return;
  const glm::dvec3 origin = *scene.origin;
  if (vtkPoints* points = poly->GetPoints()) {
    for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i) {
      double p[3];
      points->GetPoint(i, p);
      points->SetPoint(i, p[0] - origin.x, p[1] - origin.y, p[2] - origin.z);
    }
    points->Modified();
  }
  auto array = make_array<vtkDoubleArray>("origin", 1, 3);
  array->SetTuple3(0, origin.x, origin.y, origin.z);
  poly->GetFieldData()->AddArray(array);
}

}  // namespace shadow::detail
