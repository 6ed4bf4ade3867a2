// SPDX-License-Identifier: GPL-3.0-or-later
/// @file sun_hours.hpp
/// @brief The exact sun-hours map: the overlay of every instant's lit region on chosen faces.
///
/// For each receiving face, the lit region of every instant (an exact polygon set in the face's
/// chart, as the exact engine computes it) is overlaid in one exact arrangement; each cell of
/// the overlay carries the sum of the weights (hours) of the instants under which it is lit.
/// Cells of equal hours that share an edge are merged, and regions with holes are split into
/// simple polygons as fragments are. Sampling tools draw this map on point grids; here the
/// boundaries are exact. See docs/sun-hours-map.md.
#pragma once

#include <shadow/scene.hpp>
#include <shadow/shadows.hpp>

#include <glm/vec3.hpp>

#include <cstddef>
#include <filesystem>
#include <functional>
#include <vector>

namespace shadow {

/// One instant of a sun path: a directional light and the hours it stands for.
struct SunHoursInstant {
  Light light;         ///< a directional light (point lights are accepted too)
  double hours = 1.0;  ///< the weight: hours of sun this instant stands for (finite, >= 0)
};

/// One simple polygon of a face, lit under the same instants everywhere inside.
struct SunHoursCell {
  std::size_t face_id = 0;
  /// Sum of the `hours` of the instants under which the cell is lit, summed exactly and
  /// rounded once (so equal sets of instants give bit-equal hours).
  double sun_hours = 0.0;
  /// Numbers the connected regions of equal hours of the whole map; the simple pieces of one
  /// region (a region with holes is split) share it.
  std::size_t region_id = 0;
  std::vector<glm::dvec3> polygon;  ///< with the face's orientation, points rounded once
  double area = 0.0;                ///< exact area of this cell, rounded once
};

/// Sun hours on one receiving face.
struct SunHoursFace {
  std::size_t face_id = 0;
  double area = 0.0;  ///< the face's area
  /// Exact integral of sun hours over the face (sum over cells of sun_hours x area, equal to
  /// the sum over instants of hours x lit area), rounded once; unit: hours x area.
  double hour_area = 0.0;
  /// Area of cells left out because rounding them to doubles made them degenerate (slivers a
  /// few ulps wide; see Fragment and FaceLighting::dropped_area).
  double dropped_area = 0.0;
  std::size_t instants_lit = 0;  ///< instants under which some part of the face is lit
};

/// The map over every chosen face.
struct SunHoursMap {
  std::vector<SunHoursCell> cells;  ///< ordered by face_id, then region_id
  std::vector<SunHoursFace> faces;  ///< one per chosen face, by face_id
  double total_hours = 0.0;         ///< the sum of the instants' hours
  /// Region ids used: every cell's region_id is below it (a region whose cells were all too
  /// thin to write still takes its id). A map of more faces computed in parts is their
  /// concatenation in face order, each part's region ids shifted by the earlier parts' `regions`.
  std::size_t regions = 0;
};

/// Options of compute_sun_hours_map.
struct SunHoursOptions {
  /// Worker threads (faces are computed in parallel); 0: every hardware thread; at most 1024.
  unsigned threads = 0;
  /// Called now and then from one thread at a time; `total` is the number of faces times the
  /// number of instants (lit regions), then the faces' overlays count once more each.
  std::function<void(const Progress&)> progress;
  /// Merge touching cells of equal hours into one region (fewer cells). When false every face
  /// of the arrangement is its own region.
  bool merge_equal = true;
};

/// The exact sun-hours map on `faces` (face ids, any order, duplicates ignored) of the engine's
/// scene under `instants`, reusing the engine's prepared faces. Degenerate faces get no cells.
/// @throws InputError for a face id out of range, an unusable light (zero or non-finite
/// direction, ...) or hours that are negative or not finite, naming `instants[i]`.
SunHoursMap compute_sun_hours_map(const ShadowEngine& engine, const std::vector<std::size_t>& faces,
                                  const std::vector<SunHoursInstant>& instants, const SunHoursOptions& options = {});

/// The faces of the scene's `sun_hours_map` meshes (Scene::sun_hours_map), ascending.
/// @throws InputError for a mesh index out of range (possible only in scenes built in code).
std::vector<std::size_t> sun_hours_map_faces(const Scene& scene);

/// The faces of the meshes named in `mesh_names` (the CLI's `--sun-hours-map MESH[,MESH]`):
/// mesh names, or `type:<T>` for every mesh of CityJSON object type T (select_meshes()).
/// @throws InputError naming `what` (e.g. "--sun-hours-map") for a name that is no mesh's, or a
/// type no mesh has (listing the types present).
std::vector<std::size_t> sun_hours_map_faces(const Scene& scene, const std::vector<std::string>& mesh_names,
                                             const std::string& what = "--sun-hours-map");

/// The scene's sun instants above the horizon (Scene::sun_instants with a light), each weighing
/// hours_per_instant() of the period (shadow/series.hpp): its step, or for explicit `times` the
/// median gap between them, the same rule as the series' sun hours.
/// Empty when the scene has no `sun` block.
std::vector<SunHoursInstant> sun_hours_instants(const Scene& scene);

}  // namespace shadow
