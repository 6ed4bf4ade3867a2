// SPDX-License-Identifier: GPL-3.0-or-later
// Reading scene files (contract: meshes, lights, planes, receivers).
//
// Every error names the scene file and the JSON path of the offending value
// (`lights[1].to_light`), or the line and column for malformed JSON, or the OBJ file and line.
// The JSON is read in two passes: first the whole document is checked (cheap), then the mesh
// files are read (possibly slow), so a typo in a light is reported before a large OBJ is loaded.
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


namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using scene_readers::describe;
using scene_readers::element;
using scene_readers::member;
using scene_readers::quote;

// ---- small helpers for messages ----------------------------------------------------------------

std::string format_number(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", x);
  return buffer;
}

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

/// " (did you mean \"position\"?)" for a near miss, else "".
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

/// Mesh::model for a model's format.
std::string model_name(scene_readers::ModelFormat format) {
  switch (format) {
    case scene_readers::ModelFormat::cityjson: return "cityjson";
    case scene_readers::ModelFormat::energyplus: return "energyplus";
    case scene_readers::ModelFormat::none: break;
  }
  return "";
}

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

/// cos and sin of an angle in degrees, exact for multiples of 90 (a quarter turn then keeps
/// coordinates exact).
std::pair<double, double> cos_sin_degrees(double degrees) {
  const double turns = degrees / 90.0;
  if (turns == std::floor(turns) && std::fabs(turns) < 1e15) {
    const long long q = ((static_cast<long long>(turns) % 4) + 4) % 4;
    static constexpr double c[4] = {1, 0, -1, 0}, s[4] = {0, 1, 0, -1};
    return {c[q], s[q]};
  }
  const double r = degrees * 3.14159265358979323846 / 180.0;
  return {std::cos(r), std::sin(r)};
}

/// The rotation by `degrees` about the unit `axis` (Rodrigues), right-handed.
glm::dmat4 rotation(const glm::dvec3& axis, double degrees) {
  const auto [c, s] = cos_sin_degrees(degrees);
  const double x = axis.x, y = axis.y, z = axis.z, t = 1 - c;
  glm::dmat4 m(1.0);  // glm is column-major: m[column][row]
  m[0][0] = t * x * x + c;     m[1][0] = t * x * y - s * z; m[2][0] = t * x * z + s * y;
  m[0][1] = t * x * y + s * z; m[1][1] = t * y * y + c;     m[2][1] = t * y * z - s * x;
  m[0][2] = t * x * z - s * y; m[1][2] = t * y * z + s * x; m[2][2] = t * z * z + c;
  return m;
}

/// The vertex after the mesh's placement: up axis first, then the transform.
glm::dvec3 place(const PendingMesh& mesh, glm::dvec3 v) {
  if (mesh.y_up) v = glm::dvec3(v.x, -v.z, v.y);
  if (mesh.transform) {
    const glm::dmat4& m = *mesh.transform;
    // Row by row, the translation added last: exact when the matrix is a pure translation.
    v = glm::dvec3(m[0][0] * v.x + m[1][0] * v.y + m[2][0] * v.z + m[3][0],
                   m[0][1] * v.x + m[1][1] * v.y + m[2][1] * v.z + m[3][1],
                   m[0][2] * v.x + m[1][2] * v.y + m[2][2] * v.z + m[3][2]);
  }
  return v;
}

class SceneReader {
 public:
  SceneReader(const fs::path& scene_file, const LoadOptions& options)
      : scene_file_(scene_file), file_(scene_file.string()), max_file_bytes_(options.max_file_bytes), options_(options) {}

  Scene read(const std::string& text) {
    const Json document = scene_readers::parse_json_document<Json>(text, file_);
    if (!document.is_object())
      fail("", "a scene must be a JSON object with \"meshes\" and \"lights\", got " + describe(document));

    check_keys(document, "", {"meshes", "lights", "planes", "receivers", "materials", "camera", "sun",
                              "sun_hours_map", "energyplus_shading"});
    const Json& meshes = require(document, "", "meshes", "the scene's meshes");
    // With a `sun` block the suns are the lights: `lights` may be left out (or be empty).
    const Json* sun = find(document, "sun");
    // Materials first: meshes name them. A scene with an emitting material (radiosity) has a
    // source without lights: `lights` may be left out (or be empty) too.
    if (const Json* materials = find(document, "materials")) read_materials(*materials);
    bool emits = false;
    for (const Material& m : scene_.materials) emits = emits || m.emittance > 0.0;
    const Json* lights = sun != nullptr || emits ? find(document, "lights")
                                                 : &require(document, "", "lights", "the scene's lights");
    pending_ = read_meshes(meshes);
    if (lights != nullptr) read_lights(*lights, /*may_be_empty=*/sun != nullptr || emits);
    if (sun != nullptr) {
      // The suns' lights come after the scene's own; expanding is cheap next to loading meshes.
      scene_.source = scene_file_;
      add_sun_lights(scene_, read_sun(*sun));
    }
    if (const Json* planes = find(document, "planes")) read_planes(*planes);
    if (const Json* receivers = find(document, "receivers")) read_receivers(*receivers);
    if (const Json* camera = find(document, "camera")) read_camera(*camera);
    if (const Json* map = find(document, "sun_hours_map")) read_sun_hours_map(*map);
    if (const Json* ep = find(document, "energyplus_shading")) {
      if (!ep->is_boolean()) fail("energyplus_shading", "expected true or false, got " + describe(*ep));
      scene_.energyplus_shading = ep->get<bool>();
    }

    for (std::size_t i = 0; i < pending_.size(); ++i) {
      const std::size_t first = scene_.meshes.size();
      load_faces(std::move(pending_[i]));
      scene_meshes_of_.emplace_back(first, scene_.meshes.size());
    }
    apply_model_receivers();
    apply_sun_hours_map();
    if (scene_.origin) place_origin();
    scene_.source = scene_file_;
    return std::move(scene_);
  }

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
                  const std::vector<std::string>& known) const {
    for (const auto& [key, value] : object.items()) {
      if (!key.empty() && (key[0] == '_' || key[0] == '$')) continue;
      if (std::find(known.begin(), known.end(), key) != known.end()) continue;
      fail(path, "unknown key " + quote(key) + suggestion(key, known));
    }
  }

  void require_object(const Json& value, const std::string& path, const char* what) const {
    if (!value.is_object()) fail(path, std::string("expected ") + what + " (a JSON object), got " + describe(value));
  }

  void require_array(const Json& value, const std::string& path) const {
    if (!value.is_array()) fail(path, "expected an array, got " + describe(value));
  }

  std::string get_name(const Json& object, const std::string& path, const char* what) const {
    const Json& name = require(object, path, "name", what);
    if (!name.is_string()) fail(member(path, "name"), "expected a string, got " + describe(name));
    const std::string& s = name.get_ref<const std::string&>();
    if (s.empty()) fail(member(path, "name"), "the name is empty");
    return s;
  }

  double get_number(const Json& value, const std::string& path) const {
    if (!value.is_number()) fail(path, "expected a number, got " + describe(value));
    const double x = value.get<double>();
    if (!std::isfinite(x)) fail(path, "number is not finite");
    return x;
  }

  glm::dvec3 get_vec3(const Json& value, const std::string& path) const {
    if (!value.is_array()) fail(path, "expected an array of 3 numbers [x, y, z], got " + describe(value));
    if (value.size() != 3)
      fail(path, "expected 3 numbers [x, y, z], got " + std::to_string(value.size()) +
                     (value.size() == 1 ? " element" : " elements"));
    glm::dvec3 v;
    for (std::size_t i = 0; i < 3; ++i) v[static_cast<int>(i)] = get_number(value[i], element(path, i));
    return v;
  }

  // -- meshes --

  std::vector<PendingMesh> read_meshes(const Json& meshes) {
    require_array(meshes, "meshes");
    if (meshes.empty()) fail("meshes", "the scene has no meshes; at least one is needed");
    std::vector<PendingMesh> pending;
    std::map<std::string, std::size_t> seen;
    for (std::size_t i = 0; i < meshes.size(); ++i) {
      const std::string path = element("meshes", i);
      const Json& m = meshes[i];
      require_object(m, path, "a mesh");
      check_keys(m, path, {"name", "file", "polygons", "material", "transform", "up_axis", "orient"});
      const std::string name = get_name(m, path, "each mesh needs a unique name");
      if (const auto [it, inserted] = seen.emplace(name, i); !inserted)
        fail(member(path, "name"), "mesh name " + quote(name) + " is already used by " +
                                       element("meshes", it->second));
      mesh_names_.push_back(name);

      const Json* file = find(m, "file");
      const Json* polygons = find(m, "polygons");
      if (file != nullptr && polygons != nullptr)
        fail(path, "give either \"file\" or \"polygons\", not both");
      if (file == nullptr && polygons == nullptr)
        fail(path, "missing \"file\" (an OBJ file) or \"polygons\" (inline faces)");
      PendingMesh p;
      p.path = path;
      p.name = name;
      read_placement(m, path, p);
      if (const Json* material = find(m, "material")) {
        const std::string material_path = member(path, "material");
        if (!material->is_string())
          fail(material_path, "expected a material name, got " + describe(*material));
        p.material = material->get<std::string>();
        std::vector<std::string> names;
        for (const Material& known : scene_.materials) names.push_back(known.name);
        if (std::find(names.begin(), names.end(), p.material) == names.end())
          fail(material_path, "no material is named " + quote(p.material) +
                                  (names.empty() ? std::string(" (the scene has no \"materials\")")
                                                 : suggestion(p.material, names)));
      }
      if (file != nullptr) {
        if (!file->is_string()) fail(member(path, "file"), "expected a file name, got " + describe(*file));
        p.file = file->get<std::string>();
        if (p.file.empty()) fail(member(path, "file"), "the file name is empty");
      } else {
        p.polygons = read_inline_polygons(*polygons, member(path, "polygons"));
      }
      pending.push_back(std::move(p));
    }
    return pending;
  }

  /// `transform`, `up_axis` and `orient` of a mesh.
  void read_placement(const Json& m, const std::string& path, PendingMesh& p) const {
    if (const Json* up = find(m, "up_axis")) {
      const std::string up_path = member(path, "up_axis");
      if (!up->is_string() || (*up != "z" && *up != "y"))
        fail(up_path, "expected \"z\" (the default: +z is up) or \"y\" (+y is up, as most OBJ and glTF "
                      "exports write it), got " + describe(*up));
      p.y_up = *up == "y";
    }
    if (const Json* orient = find(m, "orient")) {
      const std::string orient_path = member(path, "orient");
      if (!orient->is_string() || (*orient != "outward" && *orient != "as-is"))
        fail(orient_path, "expected \"outward\" (turn closed parts outward) or \"as-is\", got " + describe(*orient));
      p.orient_outward = *orient == "outward";
    }
    if (const Json* t = find(m, "transform")) p.transform = read_transform(*t, member(path, "transform"));
  }

  /// A 4x4 row-major affine matrix, or {"translate", "rotate", "scale"} applied scale first,
  /// then rotate, then translate.
  glm::dmat4 read_transform(const Json& t, const std::string& path) const {
    glm::dmat4 m(1.0);
    if (t.is_array()) {
      if (t.size() != 4) fail(path, "expected a 4x4 matrix (4 rows of 4 numbers, row-major), got " +
                                        std::to_string(t.size()) + " rows");
      for (std::size_t r = 0; r < 4; ++r) {
        const std::string row_path = element(path, r);
        if (!t[r].is_array() || t[r].size() != 4) fail(row_path, "expected a row of 4 numbers, got " + describe(t[r]));
        for (std::size_t c = 0; c < 4; ++c)
          m[static_cast<int>(c)][static_cast<int>(r)] = get_number(t[r][c], element(row_path, c));
      }
      if (m[0][3] != 0 || m[1][3] != 0 || m[2][3] != 0 || m[3][3] != 1)
        fail(element(path, 3), "the last row must be [0, 0, 0, 1] (an affine transform)");
    } else if (t.is_object()) {
      check_keys(t, path, {"translate", "rotate", "scale"});
      glm::dmat4 scale(1.0), rotate(1.0);
      if (const Json* s = find(t, "scale")) {
        const std::string s_path = member(path, "scale");
        const glm::dvec3 k = s->is_number() ? glm::dvec3(get_number(*s, s_path)) : get_vec3(*s, s_path);
        scale[0][0] = k.x;
        scale[1][1] = k.y;
        scale[2][2] = k.z;
      }
      if (const Json* r = find(t, "rotate")) {
        const std::string r_path = member(path, "rotate");
        if (r->is_object()) {
          check_keys(*r, r_path, {"axis", "degrees"});
          const glm::dvec3 axis = get_vec3(require(*r, r_path, "axis", "the rotation axis"), member(r_path, "axis"));
          const double length = std::sqrt(axis.x * axis.x + axis.y * axis.y + axis.z * axis.z);
          if (!(length > 0) || !std::isfinite(length)) fail(member(r_path, "axis"), "axis has zero length");
          const double degrees = get_number(require(*r, r_path, "degrees", "the angle, counter-clockwise seen "
                                                                            "from the axis' tip"),
                                            member(r_path, "degrees"));
          rotate = rotation(axis / length, degrees);
        } else {
          // [rx, ry, rz] in degrees: about x, then y, then z (fixed axes).
          const glm::dvec3 angles = get_vec3(*r, r_path);
          rotate = rotation({0, 0, 1}, angles.z) * rotation({0, 1, 0}, angles.y) * rotation({1, 0, 0}, angles.x);
        }
      }
      glm::dmat4 translate(1.0);
      if (const Json* d = find(t, "translate")) {
        const glm::dvec3 v = get_vec3(*d, member(path, "translate"));
        translate[3] = glm::dvec4(v, 1.0);
      }
      m = translate * rotate * scale;
    } else {
      fail(path, "expected a 4x4 matrix or {\"translate\", \"rotate\", \"scale\"}, got " + describe(t));
    }
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[2][1] * m[1][2]) -
                       m[1][0] * (m[0][1] * m[2][2] - m[2][1] * m[0][2]) +
                       m[2][0] * (m[0][1] * m[1][2] - m[1][1] * m[0][2]);
    if (!(det != 0) || !std::isfinite(det)) fail(path, "the transform is singular (it flattens the mesh)");
    return m;
  }

  /// Inline polygons: arrays of vertices, or objects {"vertices", "name", "kind", "holes"}.
  std::vector<InlinePolygon> read_inline_polygons(const Json& polygons, const std::string& path) const {
    require_array(polygons, path);
    std::vector<InlinePolygon> out;
    out.reserve(polygons.size());
    for (std::size_t j = 0; j < polygons.size(); ++j) {
      const std::string polygon_path = element(path, j);
      const Json& polygon = polygons[j];
      InlinePolygon p;
      if (polygon.is_object()) {
        check_keys(polygon, polygon_path, {"vertices", "name", "kind", "holes"});
        const Json& vertices = require(polygon, polygon_path, "vertices", "the polygon's [x, y, z] vertices");
        p.vertices = read_ring(vertices, member(polygon_path, "vertices"));
        for (const char* key : {"name", "kind"})
          if (const Json* v = find(polygon, key)) {
            if (!v->is_string()) fail(member(polygon_path, key), "expected a string, got " + describe(*v));
            (std::string(key) == "name" ? p.name : p.kind) = v->get<std::string>();
          }
        if (const Json* holes = find(polygon, "holes")) {
          const std::string holes_path = member(polygon_path, "holes");
          require_array(*holes, holes_path);
          for (std::size_t h = 0; h < holes->size(); ++h)
            p.holes.push_back(read_ring((*holes)[h], element(holes_path, h)));
        }
      } else {
        p.vertices = read_ring(polygon, polygon_path);
      }
      out.push_back(std::move(p));
    }
    return out;
  }

  std::vector<glm::dvec3> read_ring(const Json& polygon, const std::string& polygon_path) const {
    if (!polygon.is_array())
      fail(polygon_path, "expected a polygon (an array of [x, y, z] vertices, or an object with \"vertices\"), got " +
                             describe(polygon));
    if (!polygon.empty() && polygon[0].is_number())
      fail(polygon_path, "expected a polygon (an array of [x, y, z] vertices), got an array of numbers "
                         "(\"polygons\" is an array of polygons: [[[x, y, z], ...], ...])");
    if (polygon.size() < 3)
      fail(polygon_path, "polygon has " + std::to_string(polygon.size()) +
                             (polygon.size() == 1 ? " vertex" : " vertices") + "; at least 3 are needed");
    std::vector<glm::dvec3> face;
    face.reserve(polygon.size());
    for (std::size_t k = 0; k < polygon.size(); ++k) face.push_back(get_vec3(polygon[k], element(polygon_path, k)));
    return face;
  }

  /// Second pass: the faces of a mesh, numbered after those of the meshes before it. A mesh
  /// whose file is a model (CityJSON, EnergyPlus) becomes one scene mesh per model mesh, named
  /// `<mesh>/<model mesh>`.
  void load_faces(PendingMesh pending) {
    const std::size_t first_mesh = scene_.meshes.size();
    auto new_mesh = [&](const std::string& name) -> Mesh& {
      Mesh mesh;
      mesh.name = name;
      mesh.file = pending.file;
      mesh.material = pending.material;
      mesh.receiver = pending.receiver;
      mesh.orient_outward = pending.orient_outward;
      mesh.first_face = scene_.faces.size();
      scene_.meshes.push_back(std::move(mesh));
      return scene_.meshes.back();
    };
    auto add_face = [&](std::vector<glm::dvec3> vertices, SourceLocation source, std::string name, std::string kind) {
      for (glm::dvec3& v : vertices) v = place(pending, v);
      Face face;
      face.vertices = std::move(vertices);
      face.mesh = scene_.meshes.size() - 1;
      face.source = std::move(source);
      face.name = std::move(name);
      face.kind = std::move(kind);
      scene_.faces.push_back(std::move(face));
    };
    std::string display;
    if (!pending.file.empty()) {
      const fs::path file = scene_file_.parent_path() / fs::path(pending.file);
      // Errors name the mesh file as the user would find it: relative to the scene's directory.
      display = file.lexically_normal().string();
      std::string text;
      try {
        text = read_input_file(file, display, max_file_bytes_);
      } catch (const InputError& e) {
        // The file could not be opened: say which mesh of the scene wanted it.
        std::string problem = e.problem();
        const std::string prefix = "cannot open";
        if (problem.rfind(prefix, 0) == 0) problem.insert(prefix.size(), " " + quote(display));
        else problem = quote(display) + ": " + problem;
        fail(member(pending.path, "file"), problem);
      }
      const scene_readers::ModelFormat format = scene_readers::model_format(file, text);
      if (format != scene_readers::ModelFormat::none) {
        text.clear();
        scene_readers::Model model = scene_readers::read_model(format, file, display, options_);
        for (Warning& w : model.warnings) scene_.warnings.push_back(std::move(w));
        for (SkippedFace& skipped : model.skipped) {  // surfaces the reader left out (skip_invalid)
          skipped.mesh = pending.name + "/" + skipped.mesh;
          scene_.skipped_faces.push_back(std::move(skipped));
        }
        if (model.origin && !scene_.origin) scene_.origin = model.origin;
        if (model.sun && scene_.sun && model.sun->north_axis != scene_.sun->north_axis)
          // The scene's `sun` block places the suns; the model's axes may be turned from north
          // (EnergyPlus's Building North Axis), which the block must then repeat.
          scene_.warnings.push_back(
              {{file_, member(pending.path, "file")},
               "the model " + quote(display) + " has a north axis of " + format_number(model.sun->north_axis) +
                   " degrees but the scene's sun block has north_axis " + format_number(scene_.sun->north_axis) +
                   ": its suns would come from the wrong directions; set \"north_axis\": " +
                   format_number(model.sun->north_axis) + " in the sun block (or run the model file itself)"});
        if (model.meshes.empty())
          scene_.warnings.push_back({{file_, pending.path}, "mesh " + quote(pending.name) + " has no faces (the model " +
                                                                quote(display) + " has no geometry that is read)"});
        for (const Mesh& part : model.meshes) {
          // The model says which of its meshes receive (EnergyPlus: not its shading groups or its
          // unexposed surfaces); `receivers` naming `<mesh>/<model mesh>` still makes one receive.
          Mesh& mesh = new_mesh(pending.name + "/" + part.name);
          mesh.receiver = pending.receiver && part.receiver;
          mesh.model = model_name(format);
          // What the model says the mesh is; a CityJSON part's parent is named like the meshes.
          mesh.object_type = part.object_type;
          if (!part.parent.empty()) {
            mesh.parent = pending.name + "/" + part.parent;
            mesh.parent_type = part.parent_type;
          }
          for (std::size_t f = part.first_face; f < part.first_face + part.face_count; ++f) {
            Face& face = model.faces.at(f);
            add_face(std::move(face.vertices), std::move(face.source), std::move(face.name), std::move(face.kind));
          }
          scene_.meshes.back().face_count = scene_.faces.size() - scene_.meshes.back().first_face;
        }
        finish_mesh(pending, first_mesh);
        return;
      }
      if (scene_readers::is_json_text(text))
        // Read as OBJ it would give no face and a silently empty result.
        fail(member(pending.path, "file"),
             quote(display) + " is JSON but neither CityJSON (a top-level \"type\": \"CityJSON\") nor EnergyPlus "
                              "epJSON (a top-level \"Version\" and geometry such as \"BuildingSurface:Detailed\"): a "
                              "mesh file is Wavefront OBJ, CityJSON or EnergyPlus IDF/epJSON");
      std::vector<std::size_t> lines;
      std::vector<std::string> groups;
      std::vector<std::vector<glm::dvec3>> polygons = detail::parse_obj_with_lines(text, display, &lines, &groups);
      text.clear();
      if (polygons.empty())
        // An empty result would pass for a computed one: a mesh file with no face is an error.
        fail(member(pending.path, "file"), quote(display) + " has no faces: no f statements (read as Wavefront OBJ; "
                                                              "a CityJSON or EnergyPlus model is recognised by its content)");
      new_mesh(pending.name);
      for (std::size_t j = 0; j < polygons.size(); ++j)
        add_face(std::move(polygons[j]), {display, "line " + std::to_string(lines[j])}, groups[j], "");
    } else {
      new_mesh(pending.name);
      if (pending.polygons.empty())
        scene_.warnings.push_back({{file_, pending.path}, "mesh " + quote(pending.name) + " has no faces"});
      for (std::size_t j = 0; j < pending.polygons.size(); ++j) {
        InlinePolygon& polygon = pending.polygons[j];
        const std::string path = element(member(pending.path, "polygons"), j);
        if (polygon.holes.empty()) {
          add_face(std::move(polygon.vertices), {file_, path}, polygon.name, polygon.kind);
          continue;
        }
        // Holes: convex pieces of the polygon's own vertices, sharing its name.
        const core::PolygonHolesSplit split =
            core::split_polygon_with_holes_checked(polygon.vertices, polygon.holes, options_.planarity_tolerance);
        if (!split.error.empty()) {
          const std::string at =
              split.ring < 0 ? member(path, "vertices") : element(member(path, "holes"), static_cast<std::size_t>(split.ring));
          if (!options_.skip_invalid) fail(at, split.error + detail::skip_invalid_hint);
          scene_.skipped_faces.push_back({polygon.name, pending.name, {file_, at}, split.error});
          continue;
        }
        for (const std::vector<glm::dvec3>& piece : split.pieces) add_face(piece, {file_, path}, polygon.name, polygon.kind);
      }
    }
    scene_.meshes.back().face_count = scene_.faces.size() - scene_.meshes.back().first_face;
    finish_mesh(pending, first_mesh);
  }

  /// A model asked for an origin for the VTK outputs (it sits at projected coordinates); after
  /// placement the scene may not be far away any more: whole metres below the placed scene when
  /// it is still 1e4 or more from (0, 0, 0), else none.
  void place_origin() {
    glm::dvec3 low(std::numeric_limits<double>::infinity()), high(-std::numeric_limits<double>::infinity());
    for (const Face& face : scene_.faces)
      for (const glm::dvec3& v : face.vertices) {
        low = glm::dvec3(std::min(low.x, v.x), std::min(low.y, v.y), std::min(low.z, v.z));
        high = glm::dvec3(std::max(high.x, v.x), std::max(high.y, v.y), std::max(high.z, v.z));
      }
    scene_.origin.reset();
    if (!(low.x <= high.x) || !std::isfinite(low.x + low.y + low.z + high.x + high.y + high.z)) return;
    if (std::max({std::fabs(low.x), std::fabs(low.y), std::fabs(high.x), std::fabs(high.y)}) >= 1e4)
      scene_.origin = glm::dvec3(std::floor(low.x), std::floor(low.y), std::floor(low.z));
  }

  /// A mirroring placement (negative determinant, or up_axis with a mirroring transform) turns
  /// every face's front to its back: the faces of the mesh are reversed so that they keep facing
  /// where the model meant them to face.
  void finish_mesh(const PendingMesh& pending, std::size_t first_mesh) {
    if (!pending.transform) return;
    const glm::dmat4& m = *pending.transform;
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[2][1] * m[1][2]) -
                       m[1][0] * (m[0][1] * m[2][2] - m[2][1] * m[0][2]) +
                       m[2][0] * (m[0][1] * m[1][2] - m[1][1] * m[0][2]);
    if (!(det < 0)) return;
    std::size_t reversed = 0;
    for (std::size_t f = scene_.meshes[first_mesh].first_face; f < scene_.faces.size(); ++f) {
      Face& face = scene_.faces[f];
      std::reverse(face.vertices.begin(), face.vertices.end());
      ++reversed;
    }
    scene_.warnings.push_back({{file_, member(pending.path, "transform")},
                               "the transform mirrors the mesh (negative determinant): the vertex order of its " +
                                   std::to_string(reversed) + " faces was reversed so that their fronts keep facing "
                                   "outward"});
  }

  // -- materials --

  /// A colour: 3 numbers in [0, 1].
  glm::dvec3 get_color(const Json& value, const std::string& path) const {
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
  void read_radiosity_terms(const Json& m, const std::string& path, Material& material) const {
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

  void read_materials(const Json& materials) {
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

  // -- lights --

  void read_lights(const Json& lights, bool may_be_empty) {
    require_array(lights, "lights");
    if (lights.empty() && !may_be_empty)
      fail("lights", "the scene has no lights; at least one is needed (or a \"sun\" block)");
    std::map<std::string, std::size_t> seen;
    const std::vector<std::string> types = {"directional", "point", "area", "disk"};
    for (std::size_t i = 0; i < lights.size(); ++i) {
      const std::string path = element("lights", i);
      const Json& l = lights[i];
      require_object(l, path, "a light");
      // An unknown type first: its keys would otherwise be reported as unknown keys.
      const Json* type = find(l, "type");
      if (type != nullptr && !type->is_string())
        fail(member(path, "type"), "expected \"directional\", \"point\", \"area\" or \"disk\", got " +
                                       describe(*type));
      if (type != nullptr && std::find(types.begin(), types.end(), type->get<std::string>()) == types.end())
        fail(member(path, "type"), "unknown light type " + quote(type->get<std::string>()) +
                                       suggestion(type->get<std::string>(), types) +
                                       "; known types: \"directional\", \"point\", \"area\", \"disk\"");
      check_keys(l, path, {"name", "type", "to_light", "position", "intensity", "color", "polygon", "normal",
                           "radius", "angular_diameter"});
      Light light;
      light.name = get_name(l, path, "each light needs a unique name");
      if (const auto [it, inserted] = seen.emplace(light.name, i); !inserted)
        fail(member(path, "name"), "light name " + quote(light.name) + " is already used by " +
                                       element("lights", it->second));
      if (type == nullptr) fail(path, "missing \"type\" (\"directional\", \"point\", \"area\" or \"disk\")");
      const std::string kind = type->get<std::string>();
      const Json* to_light = find(l, "to_light");
      const Json* position = find(l, "position");
      // Keys that belong to other kinds of light: named, with what the kind takes instead.
      auto refuse = [&](const char* key, const std::string& instead) {
        if (find(l, key) != nullptr)
          fail(member(path, key), "a" + std::string(kind == "area" ? "n " : " ") + kind + " light has no \"" + key +
                                      "\"; " + instead);
      };
      if (kind != "directional") refuse("angular_diameter", "only a directional light (the sun's disk) has one");
      if (kind != "area") refuse("polygon", "only an area light has one");
      if (kind != "disk") {
        refuse("normal", "only a disk light has one");
        refuse("radius", "only a disk light has one");
      }
      if (kind == "directional") {
        light.type = LightType::Directional;
        if (position != nullptr)
          fail(member(path, "position"),
               "a directional light has no position; give \"to_light\", the direction toward the light");
        if (to_light == nullptr)
          fail(path, "missing \"to_light\" (the direction from the scene toward the light)");
        light.to_light = get_vec3(*to_light, member(path, "to_light"));
        if (light.to_light == glm::dvec3(0.0))
          fail(member(path, "to_light"), "direction has zero length");
        if (const Json* d = find(l, "angular_diameter")) {
          light.angular_diameter = get_number(*d, member(path, "angular_diameter"));
          if (light.angular_diameter < 0 || light.angular_diameter > detail::max_angular_diameter)
            fail(member(path, "angular_diameter"),
                 "angular_diameter must be in [0, " + format_number(detail::max_angular_diameter) +
                     "] degrees (0: a point sun; the sun's disk is about 0.53), got " +
                     format_number(light.angular_diameter));
        }
      } else if (kind == "point") {
        light.type = LightType::Point;
        if (to_light != nullptr)
          fail(member(path, "to_light"),
               "a point light has no \"to_light\" direction; give its \"position\"");
        if (position == nullptr) fail(path, "missing \"position\" (where the point light is)");
        light.position = get_vec3(*position, member(path, "position"));
      } else if (kind == "area") {
        light.type = LightType::Area;
        if (to_light != nullptr)
          fail(member(path, "to_light"), "an area light has no \"to_light\"; its \"polygon\" says where it is");
        if (position != nullptr)
          fail(member(path, "position"), "an area light has no \"position\"; its \"polygon\" says where it is");
        const Json* polygon = find(l, "polygon");
        if (polygon == nullptr)
          fail(path, "missing \"polygon\" (the luminous polygon, [[x, y, z], ...], counter-clockwise seen from "
                     "the side it lights)");
        const std::string polygon_path = member(path, "polygon");
        require_array(*polygon, polygon_path);
        for (std::size_t k = 0; k < polygon->size(); ++k)
          light.polygon.push_back(get_vec3((*polygon)[k], element(polygon_path, k)));
        detail::check_area_polygon(light.polygon, file_, polygon_path);
      } else {
        light.type = LightType::Disk;
        if (to_light != nullptr)
          fail(member(path, "to_light"), "a disk light has no \"to_light\"; give its \"normal\", the side it lights");
        if (position == nullptr) fail(path, "missing \"position\" (the disk's centre)");
        light.position = get_vec3(*position, member(path, "position"));
        const Json* normal = find(l, "normal");
        if (normal == nullptr) fail(path, "missing \"normal\" (the side the disk lights)");
        light.normal = get_vec3(*normal, member(path, "normal"));
        if (light.normal == glm::dvec3(0.0)) fail(member(path, "normal"), "normal has zero length");
        const Json* radius = find(l, "radius");
        if (radius == nullptr) fail(path, "missing \"radius\" (the disk's radius)");
        light.radius = get_number(*radius, member(path, "radius"));
        if (!(light.radius > 0)) fail(member(path, "radius"), "radius must be > 0, got " + format_number(light.radius));
      }
      if (const Json* intensity = find(l, "intensity")) {
        light.intensity = get_number(*intensity, member(path, "intensity"));
        if (light.intensity < 0)
          fail(member(path, "intensity"), "intensity must be >= 0, got " + format_number(light.intensity));
      }
      if (const Json* color = find(l, "color")) light.color = get_color(*color, member(path, "color"));
      scene_.lights.push_back(std::move(light));
    }
  }

  // -- sun --

  /// The `sun` block (docs/scene-format.md): a site and a period or times. Types are checked
  /// here, ranges by check_sun_period (same file, place `sun.<key>`).
  SunPeriod read_sun(const Json& sun) const {
    require_object(sun, "sun", "the sun block");
    check_keys(sun, "sun", {"latitude", "longitude", "elevation", "pressure", "temperature", "utc_offset",
                            "time_zone", "start", "end", "step_minutes", "times", "north_axis",
                            "min_elevation", "delta_t", "angular_diameter"});
    SunPeriod period;
    period.site.latitude = get_number(require(sun, "sun", "latitude", "degrees, north positive"), "sun.latitude");
    period.site.longitude = get_number(require(sun, "sun", "longitude", "degrees, east positive"), "sun.longitude");
    const std::pair<const char*, double*> numbers[] = {
        {"elevation", &period.site.elevation}, {"pressure", &period.site.pressure},
        {"temperature", &period.site.temperature}, {"north_axis", &period.north_axis},
        {"min_elevation", &period.min_elevation}, {"delta_t", &period.delta_t},
        {"angular_diameter", &period.angular_diameter}};
    for (const auto& [key, target] : numbers)
      if (const Json* value = find(sun, key)) *target = get_number(*value, member("sun", key));
    const Json* offset = find(sun, "utc_offset");
    const Json* zone = find(sun, "time_zone");
    if (offset != nullptr && zone != nullptr)
      fail("sun", "give either \"utc_offset\" or \"time_zone\", not both");
    if (offset != nullptr) period.utc_offset_hours = get_number(*offset, "sun.utc_offset");
    if (zone != nullptr) {
      if (!zone->is_string()) fail("sun.time_zone", "expected a string like \"UTC+05:30\", got " + describe(*zone));
      period.time_zone = zone->get<std::string>();
      const std::optional<int> minutes = parse_utc_offset(period.time_zone);
      if (!minutes)
        fail("sun.time_zone",
             "unknown time zone " + quote(period.time_zone) +
                 "; give \"UTC\", \"UTC+hh:mm\" or \"UTC-hh:mm\" (local standard time, no daylight saving), "
                 "or \"utc_offset\" in hours; zone names such as \"Europe/Paris\" are not read (their offset "
                 "changes with daylight saving)");
      period.utc_offset_hours = *minutes / 60.0;
    }
    auto date = [&](const char* key, std::string& out) {
      if (const Json* value = find(sun, key)) {
        if (!value->is_string()) fail(member("sun", key), "expected a date \"YYYY-MM-DD\", got " + describe(*value));
        out = value->get<std::string>();
        if (out.empty()) fail(member("sun", key), "expected a date \"YYYY-MM-DD\", got an empty string");
      }
    };
    date("start", period.start);
    date("end", period.end);
    if (const Json* step = find(sun, "step_minutes")) {
      if (!step->is_number_integer())
        fail("sun.step_minutes", "expected a whole number of minutes, got " + describe(*step));
      const auto minutes = step->get<std::int64_t>();
      if (minutes <= 0 || minutes > 1440 || 1440 % minutes != 0)
        fail("sun.step_minutes", "step_minutes must divide a day (1440 minutes: 1, 5, 10, 15, 30, 60, 120, ...), got " +
                                     std::to_string(minutes));
      period.step_minutes = static_cast<int>(minutes);
      if (find(sun, "times") != nullptr) fail("sun", "\"step_minutes\" belongs to a period; with \"times\" leave it out");
    }
    if (const Json* times = find(sun, "times")) {
      require_array(*times, "sun.times");
      if (times->empty()) fail("sun.times", "no times; give at least one (or a period)");
      if (times->size() > max_sun_instants)
        fail("sun.times", std::to_string(times->size()) + " times; at most " + std::to_string(max_sun_instants) +
                              " are allowed");
      // A time without Z or an offset is local standard time (utc_offset), like the period's dates.
      const double offset_minutes = period.utc_offset_hours * 60.0;
      const int local = std::abs(offset_minutes) <= 14 * 60 ? static_cast<int>(std::lround(offset_minutes)) : 0;
      for (std::size_t i = 0; i < times->size(); ++i) {
        const Json& t = (*times)[i];
        const std::string path = element("sun.times", i);
        if (!t.is_string()) fail(path, "expected an ISO 8601 time \"YYYY-MM-DDThh:mm:ssZ\", got " + describe(t));
        const std::optional<UtcSeconds> utc = parse_iso8601(t.get_ref<const std::string&>(), local);
        if (!utc)
          fail(path, "expected an ISO 8601 time that exists, \"YYYY-MM-DDThh:mm:ss\" with \"Z\", \"+hh:mm\" or "
                     "nothing (local standard time), got " + describe(t));
        period.times.push_back(*utc);
      }
    }
    check_sun_period(period, file_, "sun");
    return period;
  }

  // -- planes and receivers --

  // -- camera --

  /// The view of `shadow render`; the messages are the ones that tool gave when it read the key.
  void read_camera(const Json& c) {
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

  void read_planes(const Json& planes) {
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

  void read_receivers(const Json& receivers) {
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

  /// A name that is no scene mesh's may still be one a model file brings (checked once the model
  /// is read): `<mesh>/<model mesh>` (one building of a model file) or `type:<T>` (every city
  /// object of a CityJSON type). Anything else is an error now, before any mesh file is read.
  void check_model_mesh_name(const std::string& name, const std::string& path) const {
    if (name.rfind("type:", 0) == 0) return;
    const std::size_t slash = name.find('/');
    const auto parent = slash == std::string::npos ? mesh_names_.end()
                                                   : std::find(mesh_names_.begin(), mesh_names_.end(), name.substr(0, slash));
    if (parent == mesh_names_.end() || pending_[static_cast<std::size_t>(parent - mesh_names_.begin())].file.empty())
      fail(path, "no mesh is named " + quote(name) + suggestion(name, mesh_names_));
  }

  /// The scene meshes a name checked by check_model_mesh_name selects, now that the models are
  /// read (`mesh/<id>`: that mesh; `type:<T>`: every mesh of the type, select_meshes).
  std::vector<std::size_t> model_meshes(const std::string& name, const std::string& path) const {
    const auto it = std::find_if(scene_.meshes.begin(), scene_.meshes.end(), [&](const Mesh& m) { return m.name == name; });
    if (it != scene_.meshes.end()) return {static_cast<std::size_t>(it - scene_.meshes.begin())};
    if (name.rfind("type:", 0) == 0) return select_meshes(scene_, name, {file_, path});
    fail(path, "no mesh is named " + quote(name) + " (the model " + quote(name.substr(0, name.find('/'))) +
                   " has no mesh " + quote(name.substr(name.find('/') + 1)) + ")");
  }

  /// Receivers that name meshes of a model (`city/B`, `type:Building`): those meshes receive,
  /// the model's others do not (unless the model's own name is listed too).
  void apply_model_receivers() {
    for (const auto& receiver : model_receivers_)
      for (std::size_t m : model_meshes(receiver.second, receiver.first)) scene_.meshes[m].receiver = true;
  }

  /// `sun_hours_map`: the meshes whose faces get the exact sun-hours map (shadow/sun_hours.hpp),
  /// spelled as `receivers` are. Names are checked now; they become scene meshes once the mesh
  /// files are read (apply_sun_hours_map).
  void read_sun_hours_map(const Json& map) {
    require_array(map, "sun_hours_map");
    for (std::size_t i = 0; i < map.size(); ++i) {
      const std::string path = element("sun_hours_map", i);
      const Json& m = map[i];
      if (!m.is_string()) fail(path, "expected a mesh name, got " + describe(m));
      const std::string& name = m.get_ref<const std::string&>();
      if (std::find(mesh_names_.begin(), mesh_names_.end(), name) == mesh_names_.end()) check_model_mesh_name(name, path);
      sun_hours_map_names_.push_back({path, name});
    }
  }

  /// Scene::sun_hours_map from the names of `sun_hours_map`, in the order given: a mesh of the
  /// scene file stands for every scene mesh it became (all of a model file's meshes).
  void apply_sun_hours_map() {
    for (const auto& [path, name] : sun_hours_map_names_) {
      std::vector<std::size_t> chosen;
      const auto it = std::find(mesh_names_.begin(), mesh_names_.end(), name);
      if (it != mesh_names_.end()) {
        const auto [first, end] = scene_meshes_of_[static_cast<std::size_t>(it - mesh_names_.begin())];
        for (std::size_t m = first; m < end; ++m) chosen.push_back(m);
      } else {
        chosen = model_meshes(name, path);
      }
      for (std::size_t m : chosen)
        if (std::find(scene_.sun_hours_map.begin(), scene_.sun_hours_map.end(), m) == scene_.sun_hours_map.end())
          scene_.sun_hours_map.push_back(m);
    }
  }

  fs::path scene_file_;
  std::string file_;
  std::uintmax_t max_file_bytes_;
  LoadOptions options_;
  Scene scene_;
  std::vector<std::string> mesh_names_;
  std::vector<PendingMesh> pending_;
  std::vector<std::pair<std::string, std::string>> model_receivers_;  // (JSON path, mesh name)
  std::vector<std::pair<std::string, std::string>> sun_hours_map_names_;  // (JSON path, mesh name)
  std::vector<std::pair<std::size_t, std::size_t>> scene_meshes_of_;  // per scene-file mesh: [first, end) of scene_.meshes
};

}  // namespace

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
  if (scene.faces.empty())
    throw InputError({scene_file.string(), ""}, "the model has no geometry that libshadow reads (see docs/cityjson.md "
                                                "and docs/energyplus.md for what is read)");
  // The sun the model implies (EnergyPlus Site:Location and RunPeriod) lights it.
  if (model.sun) add_sun_lights(scene, *model.sun);
  validate_scene(scene, options);
  return scene;
}

}  // namespace shadow
