// SPDX-License-Identifier: GPL-3.0-or-later
// The CityJSON reader (docs/cityjson.md): city objects' surfaces as faces, named and kinded.
//
// Vertices are integers scaled and translated by the file's `transform`. When the scale is a
// power of ten and the translation lies on its grid (the usual case: millimetres), each
// coordinate is computed as one integer divided by one power of ten, which is the double nearest
// to the decimal number the file means: exact input, whatever the magnitude (1e5 to 1e7 m for
// projected coordinates). Otherwise it is i * scale + translate, rounded once (fma).
#include "readers/cityjson_reader.hpp"
#include "validation/planarity.hpp"

#include "common/format.hpp"
#include "core/polygon_holes.hpp"
#include "readers/json_document.hpp"
#include "readers/obj_reader.hpp"

#include <shadow/input_file.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace shadow::scene_readers {
namespace {

using Json = nlohmann::ordered_json;  // keeps the file's order of city objects

/// City object ids always in brackets (`CityObjects["b1"]`), as Face::source spells them.
std::string cityjson_member(const std::string& path, std::size_t depth, const std::string& key) {
  return depth == 1 && path == "CityObjects" ? path + "[" + json_string(key) + "]" : member(path, key);
}

/// A level of detail as a number ("2.2" -> 2.2), for comparing; NaN if it is not one.
double lod_value(const Json& lod) {
  if (lod.is_number()) return lod.get<double>();
  if (lod.is_string()) {
    const std::string s = lod.get<std::string>();
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (end != s.c_str() && *end == '\0') return v;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

class Reader {
 public:
  Reader(std::string file, const LoadOptions& options) : file_(std::move(file)), options_(options) {}

  Model read(const std::string& text) {
    // Syntax errors at their line and column, numbers beyond a double and keys written twice
    // (JSON would keep one of them: a city object lost) at their path.
    const Json doc = parse_json_document<Json>(text, file_, cityjson_member);
    if (!doc.is_object()) fail("", "a CityJSON file is a JSON object, got " + describe(doc));
    const Json* type = find(doc, "type");
    if (type == nullptr || !type->is_string() || *type != "CityJSON")
      fail("type", "expected \"CityJSON\" (this is not a CityJSON file)");
    const Json* version = find(doc, "version");
    if (version == nullptr || !version->is_string())
      fail("version", "missing or not a string (\"1.1\" or \"2.0\")");
    const std::string v = version->get<std::string>();
    if (v != "1.0" && v != "1.1" && v != "2.0" && v.rfind("1.1.", 0) != 0 && v.rfind("2.0.", 0) != 0)
      fail("version", "CityJSON version " + json_string(v) + " is not read (1.1 and 2.0 are; 1.0 too)");
    if (!options_.cityjson_lod.empty() && std::isnan(lod_value(Json(options_.cityjson_lod))))
      fail("", "the level of detail to read, " + json_string(options_.cityjson_lod) +
                   ", is not one (a number like \"2\" or \"2.2\")");
    read_transform(doc);
    read_vertices(doc);
    templates_ = find(doc, "geometry-templates");
    const Json* objects = find(doc, "CityObjects");
    if (objects == nullptr || !objects->is_object()) fail("CityObjects", "missing or not an object");
    objects_ = objects;
    for (const auto& [id, object] : objects->items()) read_object(id, object);
    if (lost_parents_ > 0)
      model_.warnings.push_back({{file_, first_lost_parent_},
                                 std::to_string(lost_parents_) +
                                     (lost_parents_ == 1 ? " city object names a parent" : " city objects name a parent (this is the first)") +
                                     " that is not in CityObjects, or parents that lead back to it: its results per "
                                     "object stop at the last parent found"});
    // A level of detail no object has: the scene's loader makes it an error where no file has it
    // (else an empty scene is "computed", exit 0), naming the levels there are.
    if (skipped_lod_ > 0 && lods_present_.count(lod_value(Json(options_.cityjson_lod))) == 0) {
      for (double lod : lods_present_)
        model_.absent_lod_levels += (model_.absent_lod_levels.empty() ? "" : ", ") + detail::format_number(lod);
    }
    if (skipped_lod_ > 0)
      model_.warnings.push_back({{file_, "CityObjects"}, std::to_string(skipped_lod_) +
                                                              " city objects have no geometry of LoD " +
                                                              options_.cityjson_lod + " and were left out"});
    if (degenerate_ > 0)
      model_.warnings.push_back({{file_, first_degenerate_}, std::to_string(degenerate_) +
                                                                  (degenerate_ == 1 ? " surface has" : " surfaces have (this is the first)") +
                                                                  " fewer than 3 distinct vertices and no area; left out"});
    if (triangulated_ > 0)
      model_.warnings.push_back({{file_, "CityObjects"}, std::to_string(triangulated_) +
                                                              " surfaces are not planar (up to " + std::to_string(worst_off_) +
                                                              " m off their plane) and were split into triangles of their own "
                                                              "vertices; the triangles keep the surface's name"});
    // The VTK outputs' origin: whole metres below the model, when it is far from (0, 0, 0).
    if (used_any_ && std::max({std::fabs(low_.x), std::fabs(low_.y), std::fabs(high_.x), std::fabs(high_.y)}) >= 1e4)
      model_.origin = glm::dvec3(std::floor(low_.x), std::floor(low_.y), std::floor(low_.z));
    return std::move(model_);
  }

 private:
  [[noreturn]] void fail(const std::string& place, const std::string& problem) const {
    throw InputError({file_, place}, problem);
  }

  static const Json* find(const Json& object, const char* key) {
    const auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
  }

  double number(const Json& v, const std::string& place) const {
    if (!v.is_number()) fail(place, "expected a number, got " + describe(v));
    const double x = v.get<double>();
    if (!std::isfinite(x)) fail(place, "number is not finite");
    return x;
  }

  void read_transform(const Json& doc) {
    const Json* t = find(doc, "transform");
    if (t == nullptr) {  // CityJSON 1.0 allowed vertices without one; 1.1 and 2.0 require it
      const std::string v = find(doc, "version")->get<std::string>();
      if (v != "1.0")
        model_.warnings.push_back({{file_, "transform"},
                                   "missing, which CityJSON " + v + " requires (its vertices are integers scaled by "
                                   "it): the vertices are read as written, in metres"});
      return;
    }
    if (!t->is_object()) fail("transform", "expected an object {\"scale\", \"translate\"}, got " + describe(*t));
    for (const char* key : {"scale", "translate"}) {
      const Json* v = find(*t, key);
      const std::string place = std::string("transform.") + key;
      if (v == nullptr || !v->is_array() || v->size() != 3) fail(place, "expected 3 numbers");
      for (std::size_t i = 0; i < 3; ++i)
        (std::string(key) == "scale" ? scale_ : translate_)[static_cast<int>(i)] = number((*v)[i], element(place, i));
    }
    for (int i = 0; i < 3; ++i) {
      if (!(scale_[i] != 0)) fail(element("transform.scale", static_cast<std::size_t>(i)), "the scale is zero");
      // Scale 10^-k and a translation on that grid: coordinate = (integer + T) / 10^k exactly rounded.
      for (int k = 0; k <= 9; ++k) {
        const double power = std::pow(10.0, k);
        if (scale_[i] == 1.0 / power) {
          const double t = translate_[i] * power, rounded = std::nearbyint(t);
          // Only the decimal's own rounding (78612.16900000001 x 1000 is a few ulps off the
          // grid); a translation truly off the grid (4e-7 at scale 1) is kept (fma below).
          const double ulps = 16.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::fabs(t));
          if (std::fabs(t - rounded) <= ulps && std::fabs(rounded) < 0x1p52) {
            decimal_[i] = power;
            translate_units_[i] = rounded;
          }
          break;
        }
      }
    }
  }

  void read_vertices(const Json& doc) {
    const Json* vertices = find(doc, "vertices");
    if (vertices == nullptr || !vertices->is_array()) fail("vertices", "missing or not an array");
    vertices_.reserve(vertices->size());
    for (std::size_t i = 0; i < vertices->size(); ++i) {
      const Json& v = (*vertices)[i];
      const std::string place = element("vertices", i);
      if (!v.is_array() || v.size() != 3) fail(place, "expected 3 numbers [x, y, z], got " + describe(v));
      glm::dvec3 p;
      for (int c = 0; c < 3; ++c) {
        const double raw = number(v[static_cast<std::size_t>(c)], element(place, static_cast<std::size_t>(c)));
        if (decimal_[c] > 0 && raw == std::nearbyint(raw) && std::fabs(raw + translate_units_[c]) < 0x1p53)
          p[c] = (raw + translate_units_[c]) / decimal_[c];
        else
          p[c] = std::fma(raw, scale_[c], translate_[c]);
        if (!std::isfinite(p[c]) || std::fabs(p[c]) > max_coordinate)
          fail(element(place, static_cast<std::size_t>(c)), "the coordinate after the transform is out of range");
      }
      vertices_.push_back(p);
    }
  }

  void read_object(const std::string& id, const Json& object) {
    const std::string path = "CityObjects[" + json_string(id) + "]";
    if (!object.is_object()) fail(path, "expected a city object, got " + describe(object));
    const Json* geometry = find(object, "geometry");
    if (geometry == nullptr) return;  // e.g. a Building whose geometry is in its BuildingParts
    if (!geometry->is_array()) fail(path + ".geometry", "expected an array, got " + describe(*geometry));
    // The geometry to read: the chosen LoD, or the highest.
    std::size_t chosen = geometry->size();
    double best = -std::numeric_limits<double>::infinity();
    const bool want = !options_.cityjson_lod.empty();
    const double wanted = want ? lod_value(Json(options_.cityjson_lod)) : 0.0;
    bool any_surface = false;
    for (std::size_t g = 0; g < geometry->size(); ++g) {
      const Json& geom = (*geometry)[g];
      const std::string gpath = element(path + ".geometry", g);
      if (!geom.is_object()) fail(gpath, "expected a geometry object, got " + describe(geom));
      const Json* type = find(geom, "type");
      if (type == nullptr || !type->is_string()) fail(gpath + ".type", "missing or not a string");
      // A GeometryInstance stands for its template (its type and LoD), placed.
      const bool instance = type->get<std::string>() == "GeometryInstance";
      const Json& source = instance ? instance_template(geom, gpath) : geom;
      const std::string spath = instance ? gpath + ".template" : gpath;
      const Json* source_type = instance ? find(source, "type") : type;
      if (source_type == nullptr || !source_type->is_string()) fail(spath + ".type", "missing or not a string");
      const std::string t = source_type->get<std::string>();
      if (t == "MultiPoint" || t == "MultiLineString") continue;  // points and lines have no area
      // Any other name (a misspelt "Multisurface") would leave the object out without a word.
      if (t != "MultiSurface" && t != "CompositeSurface" && t != "Solid" && t != "MultiSolid" && t != "CompositeSolid")
        fail(spath + ".type", "unknown geometry type " + json_string(t) +
                                  " (CityJSON's are MultiPoint, MultiLineString, MultiSurface, CompositeSurface, Solid, "
                                  "MultiSolid, CompositeSolid" + (instance ? std::string(" for a template") : " and GeometryInstance") + ")");
      any_surface = true;
      const Json* lod = find(source, "lod");
      const double value = lod == nullptr ? 0.0 : lod_value(*lod);
      if (lod != nullptr && std::isnan(value)) fail(spath + ".lod", "expected a level of detail like \"2.2\", got " + describe(*lod));
      lods_present_.insert(value);
      if (want ? value == wanted && chosen == geometry->size() : value > best) {
        best = value;
        chosen = g;
      }
    }
    if (chosen == geometry->size()) {
      if (want && any_surface) ++skipped_lod_;
      return;
    }
    Mesh mesh;
    mesh.name = id;
    mesh.file = file_;
    mesh.object_type = object_type(object, path);
    if (const std::string root = top_level_parent(id, object, path); !root.empty()) {
      mesh.parent = root;
      mesh.parent_type = object_type(*city_object(root), "CityObjects[" + json_string(root) + "]");
    }
    mesh.first_face = model_.faces.size();
    const Json& chosen_geometry = (*geometry)[chosen];
    if (chosen_geometry["type"] == "GeometryInstance")
      read_instance(id, chosen_geometry, element(path + ".geometry", chosen));
    else
      read_geometry(id, chosen_geometry, element(path + ".geometry", chosen));
    mesh.face_count = model_.faces.size() - mesh.first_face;
    if (mesh.face_count == 0) return;
    for (std::size_t f = mesh.first_face; f < model_.faces.size(); ++f) model_.faces[f].mesh = model_.meshes.size();
    model_.meshes.push_back(std::move(mesh));
  }

  /// A city object's `type` ("" when it has none).
  std::string object_type(const Json& object, const std::string& path) const {
    const Json* type = object.is_object() ? find(object, "type") : nullptr;
    if (type == nullptr) return "";
    if (!type->is_string()) fail(path + ".type", "expected the city object's type as a string, got " + describe(*type));
    return type->get<std::string>();
  }

  /// The city object of that id, or null (looked up in an index: ordered_json finds by scanning).
  const Json* city_object(const std::string& id) {
    if (object_index_.empty())
      for (const auto& [key, value] : objects_->items()) object_index_.emplace(key, &value);
    const auto it = object_index_.find(id);
    return it == object_index_.end() ? nullptr : it->second;
  }

  /// The first of an object's `parents` (checked), or "".
  std::string first_parent(const Json& object, const std::string& path) const {
    const Json* parents = object.is_object() ? find(object, "parents") : nullptr;
    if (parents == nullptr) return "";
    if (!parents->is_array()) fail(path + ".parents", "expected an array of city object ids, got " + describe(*parents));
    if (parents->empty()) return "";
    if (!(*parents)[0].is_string()) fail(element(path + ".parents", 0), "expected a city object id, got " + describe((*parents)[0]));
    return (*parents)[0].get<std::string>();
  }

  /// The top-level object `id` is part of, following the first of `parents` up; "" when `id`
  /// has no parents. A missing parent ends the walk where it is, and a loop gives "" (counted).
  std::string top_level_parent(const std::string& id, const Json& object, const std::string& path) {
    std::string current = id, parent = first_parent(object, path);
    std::vector<std::string> seen{id};
    while (!parent.empty()) {
      const Json* next = city_object(parent);
      const bool loop = next != nullptr && std::find(seen.begin(), seen.end(), parent) != seen.end();
      if (next == nullptr || loop) {
        if (lost_parents_++ == 0) first_lost_parent_ = "CityObjects[" + json_string(current) + "].parents";
        // A loop has no top: each object on it counts on its own (ending at `current` would
        // give two objects of a loop each other's rows).
        if (loop) return "";
        break;
      }
      seen.push_back(parent);
      current = parent;
      parent = first_parent(*next, "CityObjects[" + json_string(current) + "]");
    }
    return current == id ? "" : current;
  }

  /// The semantic surface type of surface `value` (an index into `surfaces`), or "".
  std::string semantic(const Json* surfaces, const Json& value, const std::string& place) const {
    if (value.is_null() || surfaces == nullptr) return "";
    if (!value.is_number_unsigned()) fail(place, "expected a semantic surface index or null, got " + describe(value));
    const std::size_t i = value.get<std::size_t>();
    if (i >= surfaces->size())
      fail(place, "semantic surface index " + std::to_string(i) + " out of range (the geometry has " +
                      std::to_string(surfaces->size()) + ")");
    const Json& s = (*surfaces)[i];
    const Json* type = s.is_object() ? find(s, "type") : nullptr;
    return type != nullptr && type->is_string() ? type->get<std::string>() : "";
  }

  // ---- GeometryInstance: a template of `geometry-templates`, placed by a matrix at a vertex ----

  /// The template an instance names (checked).
  const Json& instance_template(const Json& geom, const std::string& gpath) const {
    const Json* list = templates_ != nullptr && templates_->is_object() ? find(*templates_, "templates") : nullptr;
    if (list == nullptr || !list->is_array())
      fail(gpath, "a GeometryInstance, but the file has no \"geometry-templates\" with \"templates\"");
    const Json* index = find(geom, "template");
    if (index == nullptr || !index->is_number_unsigned())
      fail(gpath + ".template", "expected the index of a template, got " + (index == nullptr ? std::string("nothing") : describe(*index)));
    const std::size_t t = index->get<std::size_t>();
    if (t >= list->size())
      fail(gpath + ".template", "template " + std::to_string(t) + " out of range (the file has " +
                                    std::to_string(list->size()) + ")");
    const Json& tmpl = (*list)[t];
    if (!tmpl.is_object()) fail("geometry-templates.templates[" + std::to_string(t) + "]", "expected a geometry object");
    if (const Json* type = find(tmpl, "type"); type != nullptr && *type == "GeometryInstance")
      fail("geometry-templates.templates[" + std::to_string(t) + "].type", "a template cannot be a GeometryInstance");
    return tmpl;
  }

  /// The template's surfaces, each template vertex v placed at M v + the reference point (M the
  /// instance's row-major 4 x 4 `transformationMatrix`, affine; the reference point the one vertex
  /// of its `boundaries`, in the file's vertices). A matrix that mirrors reverses the rings, so
  /// the surfaces keep facing the way the template's do.
  void read_instance(const std::string& id, const Json& geom, const std::string& gpath) {
    const Json& tmpl = instance_template(geom, gpath);
    const Json* reference = find(geom, "boundaries");
    if (reference == nullptr || !reference->is_array() || reference->size() != 1 || !(*reference)[0].is_number_unsigned())
      fail(gpath + ".boundaries", "expected one vertex index (the reference point), got " +
                                      (reference == nullptr ? std::string("nothing") : describe(*reference)));
    const std::size_t r = (*reference)[0].get<std::size_t>();
    if (r >= vertices_.size())
      fail(element(gpath + ".boundaries", 0), "vertex index " + std::to_string(r) + " out of range (the file has " +
                                                  std::to_string(vertices_.size()) + " vertices)");
    const glm::dvec3 origin = vertices_[r];
    const Json* matrix = find(geom, "transformationMatrix");
    if (matrix == nullptr || !matrix->is_array() || matrix->size() != 16)
      fail(gpath + ".transformationMatrix", "expected 16 numbers (a 4 x 4 matrix, row by row)");
    double m[16];
    for (std::size_t k = 0; k < 16; ++k) m[k] = number((*matrix)[k], element(gpath + ".transformationMatrix", k));
    if (m[12] != 0 || m[13] != 0 || m[14] != 0 || m[15] != 1)
      fail(gpath + ".transformationMatrix", "the last row must be 0, 0, 0, 1 (an affine placement)");
    load_template_vertices();
    const double det = m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
                       m[2] * (m[4] * m[9] - m[5] * m[8]);
    // The template's vertices are placed as its rings use them (ring()): an instance costs the
    // vertices of its template's surfaces, not every template vertex of the file.
    Placement placement;
    std::copy(m, m + 16, placement.m);
    placement.origin = origin;
    placement.matrix_path = gpath + ".transformationMatrix";
    placement_ = &placement;
    vertex_table_ = "the templates have";
    mirror_ = det < 0;
    struct Restore {  // also when the template's geometry fails
      Reader* reader;
      ~Restore() {
        reader->placement_ = nullptr;
        reader->mirror_ = false;
        reader->vertex_table_ = "the file has";
      }
    } restore{this};
    read_geometry(id, tmpl, gpath + ".template");
  }

  /// A template vertex placed by the instance being read: M v + the reference point.
  glm::dvec3 placed(const glm::dvec3& v) const {
    const Placement& at = *placement_;
    glm::dvec3 p;
    for (int row = 0; row < 3; ++row)
      p[row] = at.m[4 * row] * v.x + at.m[4 * row + 1] * v.y + at.m[4 * row + 2] * v.z + at.m[4 * row + 3] + at.origin[row];
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(p[c]) || std::fabs(p[c]) > max_coordinate)
        fail(at.matrix_path, "a placed template vertex is out of range");
    return p;
  }

  /// `geometry-templates.vertices-templates`, read once: real coordinates (no transform).
  void load_template_vertices() {
    if (template_vertices_loaded_) return;
    template_vertices_loaded_ = true;
    const Json* list = find(*templates_, "vertices-templates");
    if (list == nullptr || !list->is_array()) fail("geometry-templates.vertices-templates", "missing or not an array");
    for (std::size_t i = 0; i < list->size(); ++i) {
      const Json& v = (*list)[i];
      const std::string place = element("geometry-templates.vertices-templates", i);
      if (!v.is_array() || v.size() != 3) fail(place, "expected 3 numbers [x, y, z], got " + describe(v));
      template_vertices_.emplace_back(number(v[0], element(place, 0)), number(v[1], element(place, 1)),
                                      number(v[2], element(place, 2)));
    }
  }

  void read_geometry(const std::string& id, const Json& geom, const std::string& gpath) {
    const std::string type = geom["type"].get<std::string>();
    const Json* boundaries = find(geom, "boundaries");
    if (boundaries == nullptr || !boundaries->is_array()) fail(gpath + ".boundaries", "missing or not an array");
    const Json* semantics = find(geom, "semantics");
    const Json* surfaces = nullptr;
    const Json* values = nullptr;
    if (semantics != nullptr && semantics->is_object()) {
      surfaces = find(*semantics, "surfaces");
      values = find(*semantics, "values");
      if (surfaces != nullptr && !surfaces->is_array()) fail(gpath + ".semantics.surfaces", "expected an array");
      if (values != nullptr && !values->is_array() && !values->is_null())
        fail(gpath + ".semantics.values", "expected an array or null");
      if (values != nullptr && values->is_null()) values = nullptr;
    }
    const std::string bpath = gpath + ".boundaries";
    const std::string vpath = gpath + ".semantics.values";
    std::size_t counter = 0;  // surfaces in boundaries order: the `n` of `<id>/<n>`
    // Depth of surfaces: MultiSurface/CompositeSurface 1, Solid 2, MultiSolid/CompositeSolid 3.
    const int depth = type == "Solid" ? 2 : (type == "MultiSolid" || type == "CompositeSolid") ? 3 : 1;
    check_nesting(*boundaries, type, bpath, depth + 2);
    walk(id, *boundaries, values, surfaces, bpath, vpath, depth, counter);
  }

  /// Every vertex index of `boundaries` must sit `levels` arrays deep (a Solid's: shells,
  /// surfaces, rings, indices). Checked before the semantic values are matched with the
  /// boundaries, so that boundaries of another geometry type's depth are named as such.
  void check_nesting(const Json& boundaries, const std::string& type, const std::string& bpath, int levels) const {
    std::vector<std::size_t> trail;  // indices down to the first misplaced value
    const Json* bad = misplaced(boundaries, 0, levels, trail);
    if (bad == nullptr) return;
    static const char* const names[] = {"solids", "shells", "surfaces", "rings", "vertex indices"};
    std::string nesting, place = bpath;
    for (int i = 5 - levels; i < 5; ++i) nesting += std::string(nesting.empty() ? "" : ", ") + names[i];
    for (const std::size_t i : trail) place = element(place, i);
    fail(place, "boundaries nested at the wrong depth: a " + type + "'s vertex indices are " +
                    std::to_string(levels) + " arrays deep (" + nesting + "), but here " + describe(*bad) + " is " +
                    std::to_string(trail.size()) + " deep");
  }

  /// The first value (in file order) at the wrong depth below `node`, which is `depth` arrays
  /// deep: an array where a vertex index belongs, or anything else where an array belongs.
  /// Recurses at most `levels` (<= 5) deep.
  static const Json* misplaced(const Json& node, int depth, int levels, std::vector<std::size_t>& trail) {
    if (depth == levels) return node.is_array() ? &node : nullptr;  // an index's value is ring()'s check
    if (!node.is_array()) return &node;
    for (std::size_t i = 0; i < node.size(); ++i) {
      trail.push_back(i);
      if (const Json* bad = misplaced(node[i], depth + 1, levels, trail)) return bad;
      trail.pop_back();
    }
    return nullptr;
  }

  /// Descends `depth` levels of arrays to the surfaces, with their semantic values alongside.
  void walk(const std::string& id, const Json& node, const Json* values, const Json* surfaces, const std::string& bpath,
            const std::string& vpath, int depth, std::size_t& counter) {
    if (!node.is_array()) fail(bpath, "expected an array, got " + describe(node));
    if (values != nullptr && (!values->is_array() || values->size() != node.size()))
      fail(vpath, "the semantic values do not match the boundaries (" + std::to_string(node.size()) + " expected)");
    for (std::size_t i = 0; i < node.size(); ++i) {
      const Json* v = values != nullptr ? &(*values)[i] : nullptr;
      if (depth > 1) {
        walk(id, node[i], v != nullptr && !v->is_null() ? v : nullptr, surfaces, element(bpath, i), element(vpath, i), depth - 1,
             counter);
      } else {
        const std::string kind = v != nullptr ? semantic(surfaces, *v, element(vpath, i)) : "";
        read_surface(id, node[i], element(bpath, i), kind, counter++);
      }
    }
  }

  std::vector<glm::dvec3> ring(const Json& r, const std::string& place) {
    if (!r.is_array()) fail(place, "expected a ring (an array of vertex indices), got " + describe(r));
    std::vector<glm::dvec3> out;
    out.reserve(r.size());
    for (std::size_t k = 0; k < r.size(); ++k) {
      const Json& i = r[k];
      if (!i.is_number_unsigned()) fail(element(place, k), "expected a vertex index, got " + describe(i));
      const std::size_t index = i.get<std::size_t>();
      const std::vector<glm::dvec3>& table = placement_ != nullptr ? template_vertices_ : vertices_;
      if (index >= table.size())
        fail(element(place, k), "vertex index " + std::to_string(index) + " out of range (" + vertex_table_ + " " +
                               std::to_string(table.size()) + " vertices)");
      const glm::dvec3 p = placement_ != nullptr ? placed(table[index]) : table[index];
      out.push_back(p);
      if (!used_any_) low_ = high_ = p;
      used_any_ = true;
      low_ = glm::dvec3(std::min(low_.x, p.x), std::min(low_.y, p.y), std::min(low_.z, p.z));
      high_ = glm::dvec3(std::max(high_.x, p.x), std::max(high_.y, p.y), std::max(high_.z, p.z));
    }
    if (mirror_) std::reverse(out.begin(), out.end());
    return out;
  }

  void read_surface(const std::string& id, const Json& surface, const std::string& place, const std::string& kind,
                    std::size_t n) {
    if (!surface.is_array() || surface.empty())
      fail(place, "expected a surface (an array of rings), got " + (surface.is_array() ? std::string("an empty array") : describe(surface)));
    const std::string name = id + "/" + std::to_string(n);
    std::vector<glm::dvec3> outer = ring(surface[0], element(place, 0));
    // Fewer than 3 distinct corners: nothing to shade; real models have a few. Warn and skip.
    std::vector<glm::dvec3> distinct = outer;
    std::sort(distinct.begin(), distinct.end(), [](const glm::dvec3& a, const glm::dvec3& b) {
      return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z < b.z;
    });
    distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
    if (distinct.size() < 3) {
      if (degenerate_++ == 0) first_degenerate_ = place;
      return;
    }
    std::vector<std::vector<glm::dvec3>> holes;
    for (std::size_t h = 1; h < surface.size(); ++h) holes.push_back(ring(surface[h], element(place, h)));
    // Validation's own measure (scene/planarity.hpp): a surface kept whole passes validation.
    const detail::PlaneDeviation deviation = detail::plane_deviation(outer, options_.planarity_tolerance);
    const double off = deviation.worst, allowed = deviation.allowed;
    if (off > allowed) {
      // Not planar (LoD2 roofs often are, by millimetres): the documented split into triangles.
      try {
        for (std::vector<glm::dvec3>& t : core::triangulate_polygon_with_holes(outer, holes)) add(std::move(t), place, name, kind);
      } catch (const core::PolygonHolesError& e) {
        reject(id, name, element(place, e.ring < 0 ? 0 : static_cast<std::size_t>(e.ring) + 1),
               std::string("surface is not planar (") + std::to_string(off) + " m off its plane) and cannot be "
               "split into triangles: " + e.what());
        return;
      }
      ++triangulated_;
      worst_off_ = std::max(worst_off_, off);
      return;
    }
    if (holes.empty()) {
      add(std::move(outer), place, name, kind);
      return;
    }
    core::PolygonHolesSplit split =
        core::split_polygon_with_holes_checked(outer, holes, options_.planarity_tolerance);
    if (!split.error.empty() && split.error.find("not in the plane") != std::string::npos) {
      // A hole off the outer ring's plane: triangles, which may still fail (a hole outside it).
      try {
        for (std::vector<glm::dvec3>& t : core::triangulate_polygon_with_holes(outer, holes)) add(std::move(t), place, name, kind);
      } catch (const core::PolygonHolesError& e) {
        reject(id, name, element(place, e.ring < 0 ? 0 : static_cast<std::size_t>(e.ring) + 1),
               std::string("an inner ring is off the surface's plane, and the surface cannot be split into "
                           "triangles: ") + e.what());
        return;
      }
      ++triangulated_;
      return;
    }
    if (!split.error.empty()) {
      const std::size_t r = split.ring < 0 ? 0 : static_cast<std::size_t>(split.ring) + 1;
      std::string problem = split.error;
      if (split.ring >= 0)  // "hole 0" is the surface's inner ring 1
        problem = "inner ring " + std::to_string(r) + problem.substr(problem.find(' ', 5));
      reject(id, name, element(place, r), problem);
      return;
    }
    for (const std::vector<glm::dvec3>& piece : split.pieces) add(piece, place, name, kind);
  }

  /// A surface no face can be made of: left out with LoadOptions::skip_invalid (validation warns
  /// about it with the faces it skips), else the error, which says how to skip it.
  void reject(const std::string& id, const std::string& name, const std::string& place, const std::string& problem) {
    if (!options_.skip_invalid) fail(place, problem + detail::skip_invalid_hint);
    model_.skipped.push_back({name, id, {file_, place}, problem});
  }

  void add(std::vector<glm::dvec3> vertices, const std::string& place, const std::string& name, const std::string& kind) {
    Face face;
    face.vertices = std::move(vertices);
    face.source = {file_, place};
    face.name = name;
    face.kind = kind;
    model_.faces.push_back(std::move(face));
  }

  std::string file_;
  LoadOptions options_;
  Model model_;
  glm::dvec3 scale_{1.0}, translate_{0.0};
  glm::dvec3 decimal_{0.0}, translate_units_{0.0};  // 10^k and translate * 10^k where exact
  std::vector<glm::dvec3> vertices_;
  glm::dvec3 low_{0.0}, high_{0.0};
  bool used_any_ = false;
  std::set<double> lods_present_;  ///< the surfaces' levels of detail, for an error naming them
  std::size_t skipped_lod_ = 0, triangulated_ = 0, degenerate_ = 0;
  const Json* templates_ = nullptr;                 // geometry-templates
  std::vector<glm::dvec3> template_vertices_;       // its vertices-templates, once read
  bool template_vertices_loaded_ = false;
  std::string vertex_table_ = "the file has";       // whose vertices ring() indexes (for errors)
  bool mirror_ = false;                             // an instance whose matrix mirrors: rings reversed
  struct Placement {                                // the instance being read (read_instance)
    double m[16];
    glm::dvec3 origin;
    std::string matrix_path;
  };
  const Placement* placement_ = nullptr;            // set while an instance's template is read
  std::string first_degenerate_;
  double worst_off_ = 0;
  const Json* objects_ = nullptr;  // CityObjects
  std::unordered_map<std::string, const Json*> object_index_;
  std::size_t lost_parents_ = 0;
  std::string first_lost_parent_;
};

}  // namespace

Model read_cityjson(const std::filesystem::path& path, const std::string& display_name, const LoadOptions& options) {
  const std::string text = read_input_file(path, display_name, options.max_file_bytes);
  try {
    return Reader(display_name, options).read(text);
  } catch (const nlohmann::json::exception& e) {
    throw InputError({display_name, ""}, "unexpected JSON content: " + json_exception_reason(e.what()));
  }
}

}  // namespace shadow::scene_readers
