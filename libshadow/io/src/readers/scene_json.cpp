// SPDX-License-Identifier: GPL-3.0-or-later
// Reading scene files (contract: meshes, lights, planes, receivers).
//
// Every error names the scene file and the JSON path of the offending value
// (`lights[1].to_light`), or the line and column for malformed JSON, or the OBJ file and line.
// The JSON is read in two passes: first the whole document is checked (cheap), then the mesh
// files are read (possibly slow), so a typo in a light is reported before a large OBJ is loaded.
#include "readers/scene_json_reader.hpp"

#include "core/lights.hpp"
#include "core/polygon_holes.hpp"
#include "readers/json_document.hpp"
#include "readers/model_dispatch.hpp"
#include "readers/obj_reader.hpp"
#include "validation/planarity.hpp"

#include <shadow/input_file.hpp>
#include <shadow/scene_io.hpp>
#include <shadow/sun.hpp>

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace shadow {
namespace scene_json {

// ---- small helpers for messages ----------------------------------------------------------------


namespace {

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

}  // namespace

std::string suggestion(const std::string& given, const std::vector<std::string>& known) {
  std::size_t best = 3;  // only suggest for typos (at most 2 edits)
  const std::string* match = nullptr;
  for (const std::string& k : known) {
    const std::size_t d = edit_distance(given, k);
    if (d < best && d < k.size()) {
      best = d;
      match = &k;
    }
  }
  return match == nullptr ? std::string() : " (did you mean " + quote(*match) + "?)";
}

std::string model_name(scene_readers::ModelFormat format) {
  switch (format) {
    case scene_readers::ModelFormat::cityjson: return "cityjson";
    case scene_readers::ModelFormat::energyplus: return "energyplus";
    case scene_readers::ModelFormat::none: break;
  }
  return "";
}

Scene SceneReader::read(const std::string& text) {
  const Json document = scene_readers::parse_json_document<Json>(text, file_);
  if (!document.is_object())
    fail("", "a scene must be a JSON object with \"meshes\" and \"lights\", got " + describe(document));

  check_keys(document, "", {"meshes", "lights", "planes", "receivers", "materials", "camera", "sun",
                            "sun_hours_map", "energyplus_shading", "ground"});
  const Json& meshes = require(document, "", "meshes", "the scene's meshes");
  // With a `sun` block the suns are the lights: `lights` may be left out (or be empty).
  const Json* sun = find(document, "sun");
  // Materials first: meshes name them. A scene with an emitting material (radiosity) has a
  // source without lights: `lights` may be left out (or be empty) too.
  if (const Json* materials = find(document, "materials")) read_materials(*materials);
  bool emits = false;
  for (const Material& m : scene_.materials) emits = emits || m.emittance > 0.0;
  const bool lights_optional = sun != nullptr || emits || !options_.require_lights;
  const Json* lights = lights_optional ? find(document, "lights")
                                       : &require(document, "", "lights", "the scene's lights");
  pending_ = read_meshes(meshes);
  if (lights != nullptr) read_lights(*lights, /*may_be_empty=*/lights_optional);
  if (sun != nullptr) {
    // The suns' lights come after the scene's own; expanding is cheap next to loading meshes.
    scene_.source = scene_file_;
    const SunPeriod period = read_sun(*sun);
    if (std::optional<std::string> doubt = local_time_doubt(period, find(*sun, "utc_offset") || find(*sun, "time_zone")))
      scene_.warnings.push_back({{file_, "sun"}, *doubt});
    add_sun_lights(scene_, period, options_.threads);
  }
  if (const Json* planes = find(document, "planes")) read_planes(*planes);
  if (const Json* receivers = find(document, "receivers")) read_receivers(*receivers);
  if (const Json* camera = find(document, "camera")) read_camera(*camera);
  if (const Json* map = find(document, "sun_hours_map")) read_mesh_list(*map, "sun_hours_map", sun_hours_map_names_);
  const Json* ground = find(document, "ground");
  if (ground != nullptr) read_mesh_list(*ground, "ground", ground_names_);
  if (const Json* ep = find(document, "energyplus_shading")) {
    if (!ep->is_boolean()) fail("energyplus_shading", "expected true or false, got " + describe(*ep));
    scene_.energyplus_shading = ep->get<bool>();
  }

  for (std::size_t i = 0; i < pending_.size(); ++i) {
    const std::size_t first = scene_.meshes.size();
    load_faces(std::move(pending_[i]));
    scene_meshes_of_.emplace_back(first, scene_.meshes.size());
  }
  // A level of detail that no model file has (one that some lack is their warning only).
  if (!lod_absent_.empty() && lod_absent_.size() == lod_files_)
    fail(lod_absent_.front().first, "no city object of " + (lod_files_ == 1 ? std::string("its model") : "any model") +
                                        " has geometry of LoD " + options_.cityjson_lod + " (" +
                                        lod_absent_.front().second + ")");
  // A scene that writes energyplus-shading.csv (asked for, or holding an EnergyPlus model) takes
  // each step's sun where EnergyPlus takes it, unless its sun block says otherwise.
  if (sun != nullptr && scene_.sun && scene_.sun->times.empty() && !scene_.sun->energyplus_times &&
      find(*sun, "energyplus_times") == nullptr) {
    bool energyplus = false;
    for (const Mesh& mesh : scene_.meshes) energyplus = energyplus || mesh.model == "energyplus";
    if (scene_.energyplus_shading.value_or(energyplus)) {
      SunPeriod period = *scene_.sun;
      period.energyplus_times = true;
      replace_sun_lights(scene_, period, options_.threads);
    }
  }
  apply_model_receivers();
  apply_mesh_list(sun_hours_map_names_, scene_.sun_hours_map);
  if (ground != nullptr) {
    scene_.ground.emplace();
    apply_mesh_list(ground_names_, *scene_.ground);
  }
  if (scene_.origin) place_origin();
  scene_.source = scene_file_;
  return std::move(scene_);
}

void SceneReader::check_keys(const Json& object, const std::string& path,
                const std::vector<std::string>& known) const {
  for (const auto& [key, value] : object.items()) {
    if (!key.empty() && (key[0] == '_' || key[0] == '$')) continue;
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    fail(path, "unknown key " + quote(key) + suggestion(key, known));
  }
}

std::string SceneReader::get_name(const Json& object, const std::string& path, const char* what) const {
  const Json& name = require(object, path, "name", what);
  if (!name.is_string()) fail(member(path, "name"), "expected a string, got " + describe(name));
  const std::string& s = name.get_ref<const std::string&>();
  if (s.empty()) fail(member(path, "name"), "the name is empty");
  return s;
}

double SceneReader::get_number(const Json& value, const std::string& path) const {
  if (!value.is_number()) fail(path, "expected a number, got " + describe(value));
  const double x = value.get<double>();
  if (!std::isfinite(x)) fail(path, "number is not finite");
  return x;
}

glm::dvec3 SceneReader::get_vec3(const Json& value, const std::string& path) const {
  if (!value.is_array()) fail(path, "expected an array of 3 numbers [x, y, z], got " + describe(value));
  if (value.size() != 3)
    fail(path, "expected 3 numbers [x, y, z], got " + std::to_string(value.size()) +
                   (value.size() == 1 ? " element" : " elements"));
  glm::dvec3 v;
  for (std::size_t i = 0; i < 3; ++i) v[static_cast<int>(i)] = get_number(value[i], element(path, i));
  return v;
}

glm::dvec3 SceneReader::get_color(const Json& value, const std::string& path) const {
  if (value.is_array() && value.size() != 3)
    fail(path, "expected 3 numbers [r, g, b], got " + std::to_string(value.size()) +
                   (value.size() == 1 ? " element" : " elements"));
  const glm::dvec3 color = get_vec3(value, path);
  for (int c = 0; c < 3; ++c)
    if (color[c] < 0.0 || color[c] > 1.0)
      fail(element(path, static_cast<std::size_t>(c)),
           "color components must be in [0, 1], got " + format_number(color[c]));
  return color;
}

/// `reflectance` (one number or [r, g, b], each in [0, 1)) and `emittance` (W/m^2, >= 0).
void SceneReader::read_radiosity_terms(const Json& m, const std::string& path, Material& material) const {
  if (const Json* value = find(m, "reflectance")) {
    const std::string place = member(path, "reflectance");
    auto check = [&](double r, const std::string& where) {
      if (!(r >= 0.0 && r < 1.0))
        fail(where, "reflectance must be in [0, 1) (1 would reflect all and never converge), got " +
                        format_number(r));
    };
    if (value->is_array()) {
      if (value->size() != 3)
        fail(place, "expected one number or 3 numbers [r, g, b], got " + std::to_string(value->size()) +
                        (value->size() == 1 ? " element" : " elements"));
      const glm::dvec3 rgb = get_vec3(*value, place);
      for (int c = 0; c < 3; ++c) check(rgb[c], element(place, static_cast<std::size_t>(c)));
      material.reflectance_rgb = rgb;
      material.reflectance = (rgb.x + rgb.y + rgb.z) / 3.0;
    } else {
      const double r = get_number(*value, place);
      check(r, place);
      material.reflectance = r;
      material.reflectance_rgb = glm::dvec3(r);
    }
  }
  if (const Json* value = find(m, "emittance")) {
    const std::string place = member(path, "emittance");
    const double e = get_number(*value, place);
    if (!(e >= 0.0)) fail(place, "emittance must be >= 0 (W/m^2), got " + format_number(e));
    material.emittance = e;
  }
}

void SceneReader::read_materials(const Json& materials) {
  require_array(materials, "materials");
  std::map<std::string, std::size_t> seen;
  for (std::size_t i = 0; i < materials.size(); ++i) {
    const std::string path = element("materials", i);
    const Json& m = materials[i];
    require_object(m, path, "a material");
    check_keys(m, path, {"name", "k_a", "k_d", "k_s", "shininess", "color", "specular_color", "reflectance",
                         "emittance"});
    Material material;
    material.name = get_name(m, path, "each material needs a unique name");
    if (const auto [it, inserted] = seen.emplace(material.name, i); !inserted)
      fail(member(path, "name"), "material name " + quote(material.name) + " is already used by " +
                                     element("materials", it->second));
    const std::pair<const char*, double*> coefficients[] = {
        {"k_a", &material.k_a}, {"k_d", &material.k_d}, {"k_s", &material.k_s},
        {"shininess", &material.shininess}};
    for (const auto& [key, target] : coefficients) {
      if (const Json* value = find(m, key)) {
        *target = get_number(*value, member(path, key));
        if (*target < 0)
          fail(member(path, key), std::string(key) + " must be >= 0, got " + format_number(*target));
      }
    }
    if (const Json* color = find(m, "color")) material.color = get_color(*color, member(path, "color"));
    if (const Json* color = find(m, "specular_color"))
      material.specular_color = get_color(*color, member(path, "specular_color"));
    read_radiosity_terms(m, path, material);
    scene_.materials.push_back(std::move(material));
  }
}

void SceneReader::read_camera(const Json& c) {
  if (!c.is_object()) fail("camera", "expected an object {\"eye\", \"target\", \"up\", \"fov\"}");
  for (const auto& [key, value] : c.items()) {
    (void)value;
    if (key.empty() || key[0] == '_' || key[0] == '$') continue;
    if (key != "eye" && key != "target" && key != "up" && key != "fov")
      fail("camera", "unknown key " + quote(key) + " (known: \"eye\", \"target\", \"up\", \"fov\")");
  }
  Camera camera;
  auto vec3 = [&](const char* key, std::optional<glm::dvec3>& out) {
    const Json* v = find(c, key);
    if (v == nullptr) return;
    const std::string path = member("camera", key);
    if (!v->is_array() || v->size() != 3) fail(path, "expected 3 numbers [x, y, z]");
    glm::dvec3 xyz;
    for (std::size_t i = 0; i < 3; ++i) {
      const Json& x = (*v)[i];
      if (!x.is_number() || !std::isfinite(x.get<double>())) fail(element(path, i), "expected a finite number");
      xyz[static_cast<int>(i)] = x.get<double>();
    }
    out = xyz;
  };
  vec3("eye", camera.eye);
  vec3("target", camera.target);
  vec3("up", camera.up);
  if (const Json* fov = find(c, "fov")) {
    if (!fov->is_number() || !(fov->get<double>() >= 1.0 && fov->get<double>() <= 170.0))
      fail("camera.fov", "expected a vertical view angle in degrees, in [1, 170]");
    camera.fov_degrees = fov->get<double>();
  }
  scene_.camera = camera;
}

void SceneReader::read_planes(const Json& planes) {
  require_array(planes, "planes");
  std::map<std::string, std::size_t> seen;
  for (std::size_t i = 0; i < planes.size(); ++i) {
    const std::string path = element("planes", i);
    const Json& p = planes[i];
    require_object(p, path, "a plane");
    check_keys(p, path, {"name", "point", "normal", "window"});
    Plane plane;
    plane.name = get_name(p, path, "each plane needs a unique name");
    if (const auto [it, inserted] = seen.emplace(plane.name, i); !inserted)
      fail(member(path, "name"), "plane name " + quote(plane.name) + " is already used by " +
                                     element("planes", it->second));
    plane.point = get_vec3(require(p, path, "point", "a point on the plane"), member(path, "point"));
    plane.normal = get_vec3(require(p, path, "normal", "the plane's normal"), member(path, "normal"));
    if (plane.normal == glm::dvec3(0.0)) fail(member(path, "normal"), "normal has zero length");
    if (const Json* window = find(p, "window")) {
      plane.window = get_number(*window, member(path, "window"));
      if (!(plane.window > 0))
        fail(member(path, "window"), "window (half side of the square computed) must be > 0, got " +
                                         format_number(plane.window));
    }
    scene_.planes.push_back(std::move(plane));
  }
}

void SceneReader::read_receivers(const Json& receivers) {
  require_array(receivers, "receivers");
  for (PendingMesh& mesh : pending_) mesh.receiver = false;
  for (std::size_t i = 0; i < receivers.size(); ++i) {
    const std::string path = element("receivers", i);
    const Json& r = receivers[i];
    if (!r.is_string()) fail(path, "expected a mesh name, got " + describe(r));
    const std::string& name = r.get_ref<const std::string&>();
    const auto it = std::find(mesh_names_.begin(), mesh_names_.end(), name);
    if (it != mesh_names_.end()) {
      pending_[static_cast<std::size_t>(it - mesh_names_.begin())].receiver = true;
      continue;
    }
    check_model_mesh_name(name, path);
    model_receivers_.push_back({path, name});
  }
}

void SceneReader::check_model_mesh_name(const std::string& name, const std::string& path) const {
  if (name.rfind("type:", 0) == 0) return;
  const std::size_t slash = name.find('/');
  const auto parent = slash == std::string::npos ? mesh_names_.end()
                                                 : std::find(mesh_names_.begin(), mesh_names_.end(), name.substr(0, slash));
  if (parent == mesh_names_.end() || pending_[static_cast<std::size_t>(parent - mesh_names_.begin())].file.empty())
    fail(path, "no mesh is named " + quote(name) + suggestion(name, mesh_names_));
}

std::vector<std::size_t> SceneReader::model_meshes(const std::string& name, const std::string& path) const {
  const auto it = std::find_if(scene_.meshes.begin(), scene_.meshes.end(), [&](const Mesh& m) { return m.name == name; });
  if (it != scene_.meshes.end()) return {static_cast<std::size_t>(it - scene_.meshes.begin())};
  if (name.rfind("type:", 0) == 0) return select_meshes(scene_, name, {file_, path});
  fail(path, "no mesh is named " + quote(name) + " (the model " + quote(name.substr(0, name.find('/'))) +
                 " has no mesh " + quote(name.substr(name.find('/') + 1)) + ")");
}

void SceneReader::apply_model_receivers() {
  for (const auto& receiver : model_receivers_)
    for (std::size_t m : model_meshes(receiver.second, receiver.first)) scene_.meshes[m].receiver = true;
}

void SceneReader::read_mesh_list(const Json& list, const char* key,
                                 std::vector<std::pair<std::string, std::string>>& names) {
  require_array(list, key);
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string path = element(key, i);
    const Json& m = list[i];
    if (!m.is_string()) fail(path, "expected a mesh name, got " + describe(m));
    const std::string& name = m.get_ref<const std::string&>();
    if (std::find(mesh_names_.begin(), mesh_names_.end(), name) == mesh_names_.end()) check_model_mesh_name(name, path);
    names.push_back({path, name});
  }
}

void SceneReader::apply_mesh_list(const std::vector<std::pair<std::string, std::string>>& names,
                                  std::vector<std::size_t>& meshes) const {
  for (const auto& [path, name] : names) {
    std::vector<std::size_t> chosen;
    const auto it = std::find(mesh_names_.begin(), mesh_names_.end(), name);
    if (it != mesh_names_.end()) {
      const auto [first, end] = scene_meshes_of_[static_cast<std::size_t>(it - mesh_names_.begin())];
      for (std::size_t m = first; m < end; ++m) chosen.push_back(m);
    } else {
      chosen = model_meshes(name, path);
    }
    for (std::size_t m : chosen)
      if (std::find(meshes.begin(), meshes.end(), m) == meshes.end()) meshes.push_back(m);
  }
}

}  // namespace scene_json

using scene_json::model_name;
using scene_json::SceneReader;
namespace fs = std::filesystem;

Scene parse_scene(const std::string& json_text, const fs::path& scene_file, const LoadOptions& options) {
  Scene scene;
  try {
    scene = SceneReader(scene_file, options).read(json_text);
  } catch (const nlohmann::json::exception& e) {
    // Not expected (values are type-checked before use); still an input error, never a crash.
    throw InputError({scene_file.string(), ""}, scene_readers::json_exception_reason(e.what()));
  }
  validate_scene(scene, options);
  return scene;
}

Scene load_scene(const fs::path& scene_file, const LoadOptions& options) {
  std::string text = read_input_file(scene_file, scene_file.string(), options.max_file_bytes);
  const scene_readers::ModelFormat format = scene_readers::model_format(scene_file, text);
  if (format == scene_readers::ModelFormat::none) return parse_scene(text, scene_file, options);
  // A whole model as the scene: its meshes and faces, its sun if it implies one, no lights.
  text.clear();
  scene_readers::Model model = scene_readers::read_model(format, scene_file, scene_file.string(), options);
  Scene scene;
  scene.source = scene_file;
  scene.meshes = std::move(model.meshes);
  scene.faces = std::move(model.faces);
  scene.warnings = std::move(model.warnings);
  scene.skipped_faces = std::move(model.skipped);
  scene.origin = model.origin;
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    Mesh& mesh = scene.meshes[m];
    if (mesh.file.empty()) mesh.file = scene_file.string();
    mesh.model = model_name(format);
    for (std::size_t f = mesh.first_face; f < mesh.first_face + mesh.face_count && f < scene.faces.size(); ++f)
      scene.faces[f].mesh = m;
  }
  if (!model.absent_lod_levels.empty())
    throw InputError({scene_file.string(), "CityObjects"}, "no city object has geometry of LoD " + options.cityjson_lod +
                                                               " (the file's: " + model.absent_lod_levels + ")");
  if (scene.faces.empty())
    throw InputError({scene_file.string(), ""}, "the model has no geometry that libshadow reads (see docs/cityjson.md "
                                                "and docs/energyplus.md for what is read)");
  // The sun the model implies (EnergyPlus Site:Location and RunPeriod) lights it.
  if (model.sun) add_sun_lights(scene, *model.sun, options.threads);
  validate_scene(scene, options);
  return scene;
}

}  // namespace shadow
