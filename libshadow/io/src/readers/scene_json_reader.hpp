// SPDX-License-Identifier: GPL-3.0-or-later
// The scene file reader's class (scene_json.cpp), shared by the files of its steps: the document,
// materials, planes, receivers and sun-hours map (scene_json.cpp), the meshes and their faces
// (scene_json_meshes.cpp), the lights and the sun (scene_json_lights.cpp). Internal to scene/.
#pragma once

#include "common/format.hpp"
#include "readers/json_document.hpp"
#include "readers/model_dispatch.hpp"

#include <shadow/scene.hpp>
#include <shadow/scene_io.hpp>

#include <glm/mat4x4.hpp>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace shadow::scene_json {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using scene_readers::describe;
using scene_readers::element;
using scene_readers::member;
using scene_readers::quote;

/// A number as messages write it (common/format.hpp: the shortest form that reads back exactly).
using detail::format_number;

/// " (did you mean \"position\"?)" for a near miss, else "".
std::string suggestion(const std::string& given, const std::vector<std::string>& known);

/// Mesh::model for a model's format.
std::string model_name(scene_readers::ModelFormat format);

/// A warning for a sun period whose local standard time is more than 3.5 hours from the sun's at
/// its longitude (a forgotten or mistyped zone shifts every instant); `offset_given`: the block
/// had "utc_offset" or "time_zone". None for explicit times or a plausible zone.
std::optional<std::string> local_time_doubt(const SunPeriod& period, bool offset_given);

// ---- the scene reader --------------------------------------------------------------------------

/// An inline polygon: its vertices, and the optional name, kind and holes of the object form.
struct InlinePolygon {
  std::vector<glm::dvec3> vertices;
  std::vector<std::vector<glm::dvec3>> holes;
  std::string name, kind;
};

/// A mesh as found in the JSON; its faces are read in the second pass.
struct PendingMesh {
  std::string path;  // "meshes[i]"
  std::string name;
  std::string file;  // empty for inline polygons
  std::vector<InlinePolygon> polygons;
  std::string material;  // name of a scene material, empty for the default
  bool receiver = true;
  bool orient_outward = false;
  bool y_up = false;  // up_axis "y": (x, y, z) -> (x, -z, y) before the transform
  std::optional<glm::dmat4> transform;
};

class SceneReader {
 public:
  SceneReader(const fs::path& scene_file, const LoadOptions& options)
      : scene_file_(scene_file), file_(scene_file.string()), max_file_bytes_(options.max_file_bytes), options_(options) {}

  Scene read(const std::string& text);

 private:
  [[noreturn]] void fail(const std::string& path, const std::string& problem) const {
    throw InputError({file_, path}, problem);
  }

  static const Json* find(const Json& object, const char* key) {
    const auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
  }

  const Json& require(const Json& object, const std::string& path, const char* key,
                      const char* what) const {
    const Json* value = find(object, key);
    if (value == nullptr) fail(path, std::string("missing \"") + key + "\" (" + what + ")");
    return *value;
  }

  /// Unknown keys are errors (they are usually typos); keys starting with `_` or `$` are
  /// comments or schema references and always allowed.
  void check_keys(const Json& object, const std::string& path,
                  const std::vector<std::string>& known) const;

  void require_object(const Json& value, const std::string& path, const char* what) const {
    if (!value.is_object()) fail(path, std::string("expected ") + what + " (a JSON object), got " + describe(value));
  }

  void require_array(const Json& value, const std::string& path) const {
    if (!value.is_array()) fail(path, "expected an array, got " + describe(value));
  }

  std::string get_name(const Json& object, const std::string& path, const char* what) const;

  double get_number(const Json& value, const std::string& path) const;

  glm::dvec3 get_vec3(const Json& value, const std::string& path) const;

  // -- meshes --

  std::vector<PendingMesh> read_meshes(const Json& meshes);

  /// `transform`, `up_axis` and `orient` of a mesh.
  void read_placement(const Json& m, const std::string& path, PendingMesh& p) const;

  /// A 4x4 row-major affine matrix, or {"translate", "rotate", "scale"} applied scale first,
  /// then rotate, then translate.
  glm::dmat4 read_transform(const Json& t, const std::string& path) const;

  /// Inline polygons: arrays of vertices, or objects {"vertices", "name", "kind", "holes"}.
  std::vector<InlinePolygon> read_inline_polygons(const Json& polygons, const std::string& path) const;

  std::vector<glm::dvec3> read_ring(const Json& polygon, const std::string& polygon_path) const;

  /// Second pass: the faces of a mesh, numbered after those of the meshes before it. A mesh
  /// whose file is a model (CityJSON, EnergyPlus) becomes one scene mesh per model mesh, named
  /// `<mesh>/<model mesh>`.
  void load_faces(PendingMesh pending);

  /// A model asked for an origin for the VTK outputs (it sits at projected coordinates); after
  /// placement the scene may not be far away any more: whole metres below the placed scene when
  /// it is still 1e4 or more from (0, 0, 0), else none.
  void place_origin();

  /// A mirroring placement (negative determinant, or up_axis with a mirroring transform) turns
  /// every face's front to its back: the faces of the mesh are reversed so that they keep facing
  /// where the model meant them to face.
  void finish_mesh(const PendingMesh& pending, std::size_t first_mesh);

  // -- materials --

  /// A colour: 3 numbers in [0, 1].
  glm::dvec3 get_color(const Json& value, const std::string& path) const;

  void read_radiosity_terms(const Json& m, const std::string& path, Material& material) const;
  void read_materials(const Json& materials);

  // -- lights --

  void read_lights(const Json& lights, bool may_be_empty);

  // -- sun --

  /// The `sun` block (docs/scene-format.md): a site and a period or times. Types are checked
  /// here, ranges by check_sun_period (same file, place `sun.<key>`).
  SunPeriod read_sun(const Json& sun) const;

  // -- planes and receivers --

  // -- camera --

  /// The view of `shadow render`; the messages are the ones that tool gave when it read the key.
  void read_camera(const Json& c);

  void read_planes(const Json& planes);

  void read_receivers(const Json& receivers);

  /// A name that is no scene mesh's may still be one a model file brings (checked once the model
  /// is read): `<mesh>/<model mesh>` (one building of a model file) or `type:<T>` (every city
  /// object of a CityJSON type). Anything else is an error now, before any mesh file is read.
  void check_model_mesh_name(const std::string& name, const std::string& path) const;

  /// The scene meshes a name checked by check_model_mesh_name selects, now that the models are
  /// read (`mesh/<id>`: that mesh; `type:<T>`: every mesh of the type, select_meshes).
  std::vector<std::size_t> model_meshes(const std::string& name, const std::string& path) const;

  /// Receivers that name meshes of a model (`city/B`, `type:Building`): those meshes receive,
  /// the model's others do not (unless the model's own name is listed too).
  void apply_model_receivers();

  /// A list of mesh names under `key` (`sun_hours_map`, `ground`), spelled as `receivers` are.
  /// Names are checked now; they become scene meshes once the mesh files are read
  /// (apply_mesh_list), stored as (JSON path, name) in `names`.
  void read_mesh_list(const Json& list, const char* key, std::vector<std::pair<std::string, std::string>>& names);

  /// The scene meshes of `names` (read_mesh_list) appended to `meshes` in the order given, each
  /// once: a mesh of the scene file stands for every scene mesh it became (all of a model
  /// file's meshes).
  void apply_mesh_list(const std::vector<std::pair<std::string, std::string>>& names, std::vector<std::size_t>& meshes) const;

  fs::path scene_file_;
  std::string file_;
  std::uintmax_t max_file_bytes_;
  LoadOptions options_;
  Scene scene_;
  std::vector<std::string> mesh_names_;
  std::vector<PendingMesh> pending_;
  std::vector<std::pair<std::string, std::string>> model_receivers_;  // (JSON path, mesh name)
  std::vector<std::pair<std::string, std::string>> sun_hours_map_names_;  // (JSON path, mesh name)
  std::vector<std::pair<std::string, std::string>> ground_names_;  // (JSON path, mesh name)
  std::vector<std::pair<std::size_t, std::size_t>> scene_meshes_of_;  // per scene-file mesh: [first, end) of scene_.meshes
  std::size_t lod_files_ = 0;  // CityJSON files read with LoadOptions::cityjson_lod
  std::vector<std::pair<std::string, std::string>> lod_absent_;  // (JSON path, "file" has levels) without that LoD
};

}  // namespace shadow::scene_json
