// SPDX-License-Identifier: GPL-3.0-or-later
// The scene reader's meshes (scene/scene_json_reader.hpp): each mesh's entry checked in the
// first pass, its faces read in the second (inline polygons, OBJ, CityJSON or EnergyPlus
// files), placed by its transform and up axis, and reversed when the placement mirrors.
#include "readers/scene_json_reader.hpp"

#include "core/lights.hpp"
#include "core/polygon_holes.hpp"
#include "readers/json_document.hpp"
#include "readers/model_dispatch.hpp"
#include "readers/obj_reader.hpp"
#include "runtime/first_touch.hpp"
#include "runtime/parallel.hpp"
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
#include <string_view>
#include <utility>
#include <vector>

namespace shadow::scene_json {
namespace {

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

}  // namespace

std::vector<PendingMesh> SceneReader::read_meshes(const Json& meshes) {
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

void SceneReader::read_placement(const Json& m, const std::string& path, PendingMesh& p) const {
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

glm::dmat4 SceneReader::read_transform(const Json& t, const std::string& path) const {
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

std::vector<InlinePolygon> SceneReader::read_inline_polygons(const Json& polygons, const std::string& path) const {
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

std::vector<glm::dvec3> SceneReader::read_ring(const Json& polygon, const std::string& polygon_path) const {
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

void SceneReader::load_faces(PendingMesh pending) {
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
    runtime::UninitVector<char> bytes;  // the file, read on every thread
    try {
      bytes = detail::read_input_bytes(file, display, max_file_bytes_, "LoadOptions::max_file_bytes", options_.threads);
    } catch (const InputError& e) {
      // The file could not be opened: say which mesh of the scene wanted it.
      std::string problem = e.problem();
      const std::string prefix = "cannot open";
      if (problem.rfind(prefix, 0) == 0) problem.insert(prefix.size(), " " + quote(display));
      else problem = quote(display) + ": " + problem;
      fail(member(pending.path, "file"), problem);
    }
    const std::string_view text(bytes.data(), bytes.size());
    const scene_readers::ModelFormat format = scene_readers::model_format(file, text);
    if (format != scene_readers::ModelFormat::none) {
      bytes = {};  // (`text` is not read again)
      scene_readers::Model model = scene_readers::read_model(format, file, display, options_);
      if (format == scene_readers::ModelFormat::cityjson && !options_.cityjson_lod.empty()) {
        ++lod_files_;
        if (!model.absent_lod_levels.empty())
          lod_absent_.emplace_back(member(pending.path, "file"), quote(pending.file) + " has " + model.absent_lod_levels);
      }
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
        mesh.scene_mesh = pending.name;
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
    std::vector<std::vector<glm::dvec3>> polygons = detail::parse_obj_with_lines(text, display, &lines, &groups, options_.threads);
    bytes = {};
    if (polygons.empty())
      // An empty result would pass for a computed one: a mesh file with no face is an error.
      fail(member(pending.path, "file"), quote(display) + " has no faces: no f statements (read as Wavefront OBJ; "
                                                            "a CityJSON or EnergyPlus model is recognised by its content)");
    new_mesh(pending.name);
    // The faces made on every thread (a million-face file: placing vertices, a source and a
    // name each), in file order.
    const std::size_t first = scene_.faces.size(), mesh = scene_.meshes.size() - 1;
    const unsigned threads = std::min(runtime::resolve_threads(options_.threads), runtime::kMaxThreads);
    runtime::resize_touched(scene_.faces, first + polygons.size(), threads);
    runtime::parallel_for_blocks(polygons.size(), 4096, threads, [&](unsigned, std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t j = begin; j < end; ++j) {
        Face& face = scene_.faces[first + j];
        face.vertices = std::move(polygons[j]);
        for (glm::dvec3& v : face.vertices) v = place(pending, v);
        face.mesh = mesh;
        face.source = {display, "line " + std::to_string(lines[j])};
        face.name = std::move(groups[j]);
      }
    });
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

void SceneReader::place_origin() {
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

void SceneReader::finish_mesh(const PendingMesh& pending, std::size_t first_mesh) {
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

}  // namespace shadow::scene_json
