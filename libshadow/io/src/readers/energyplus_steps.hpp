// SPDX-License-Identifier: GPL-3.0-or-later
// The EnergyPlus reader's steps (energyplus_reader.cpp), shared by their files: the schemas
// (energyplus_schema.cpp), the objects from either syntax, the globals and the sun period
// (energyplus_reader.cpp), the surfaces (energyplus_surfaces.cpp), and the openings cut out of
// their walls (energyplus_cut.cpp). Internal to scene/.
#pragma once

#include "readers/energyplus_reader.hpp"
#include "readers/energyplus_reveals.hpp"

#include <shadow/scene.hpp>
#include <shadow/scene_io.hpp>
#include <shadow/sun.hpp>

#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace shadow::scene_readers::energyplus {

inline std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return out;
}

inline bool same_text(std::string_view a, std::string_view b) { return lower(a) == lower(b); }

// ---------------------------------------------------------------------------------------------
// Schemas: the fields read, in the IDD's order (IDF position), with the epJSON key of each.

struct FieldSpec {
  const char* idd;  ///< IDD field name, for messages
  const char* key;  ///< epJSON key; nullptr: the object's name (the key of the epJSON object)
};

enum class Vertices { None, List, Four };  // "vertices" array, or vertex_1..4 keys (fenestration)

struct ClassSpec {
  const char* name;
  std::vector<FieldSpec> fields;
  Vertices vertices = Vertices::None;
};
/// `version`: major * 100 + minor (9.6 -> 906); the field lists changed in 9.0 and 9.6.
std::vector<ClassSpec> class_specs(int version);


/// Geometry classes this reader does not build: their objects are reported, never silently lost.
/// (Window:Interzone and Door:Interzone are skipped without a word: they sit in interzone
/// surfaces, which are left out anyway.)
const std::vector<std::string>& unsupported_geometry_classes();


// ---------------------------------------------------------------------------------------------
// Objects with positional fields, from either syntax.

struct Value {
  bool present = false;
  std::string text;  ///< IDF text or JSON string (empty for a JSON number)
  std::optional<double> json_number;
  std::string place;  ///< where the field is, for messages
};

struct Object {
  const ClassSpec* spec = nullptr;
  std::string name;
  std::string place;  ///< the object's place (Face::source)
  std::vector<Value> fields;                   ///< spec->fields.size() entries
  std::vector<std::array<Value, 3>> vertices;  ///< Vertices::List / Four
  std::string vertex_problem;                  ///< IDF: a vertex left with fewer than 3 coordinates
  std::string vertex_problem_place;
};

class Reader {
 public:
  Reader(std::string display_name, const LoadOptions& options) : file_(std::move(display_name)), options_(options) {}

  Model read(const std::string& text, bool epjson);

 private:
  // --- fields ---
  [[noreturn]] void fail(const std::string& place, const std::string& problem) const {
    throw InputError({file_, place}, problem);
  }
  const Value& field(const Object& o, std::string_view key) const;
  std::string text(const Object& o, std::string_view key) const { return field(o, key).text; }
  std::optional<double> number(const Value& v) const;
  double number_or(const Object& o, std::string_view key, double fallback) const {
    return number(field(o, key)).value_or(fallback);
  }
  double required_number(const Value& v, const char* what) const {
    const std::optional<double> x = number(v);
    if (!x) fail(v.place, std::string("missing ") + what);
    return *x;
  }

  // --- the two syntaxes ---
  void load_idf(const std::string& text);
  void load_epjson(const std::string& text);
  const ClassSpec* find_spec(std::string_view class_name) const;

  // --- geometry ---
  struct Surface {
    const Object* object = nullptr;
    std::string kind;
    std::string zone;                 ///< zone name as written by the Zone object ("" for shading)
    enum Group { ZoneGroup, BuildingShading, SiteShading, NotExposed, Dropped } group = ZoneGroup;
    std::vector<glm::dvec3> vertices;  ///< model coordinates, counter-clockwise seen from outside
    std::vector<std::size_t> openings;
    /// The index in `vertices` of EnergyPlus's Vertex(2) (its lower left corner once it has put
    /// the upper left first, counter-clockwise): where its simple windows and doors are measured
    /// from (MakeRelativeRectangularVertices). 0 for the rectangles built here.
    std::size_t lower_left = 0;
    bool opening = false;
    std::string name;  ///< the object's name, or "<fin> Left"/"<fin> Right" for a fin's two shades
  };
  struct ZoneFrame {
    std::string name;
    double north = 0.0;
    glm::dvec3 origin{0.0};
    std::string place;
  };
  std::vector<glm::dvec3> raw_vertices(const Object& o) const;
  std::size_t lower_left_index(std::size_t n) const;
  glm::dvec3 zone_to_model(const glm::dvec3& p, const ZoneFrame& zone) const;
  glm::dvec3 world_to_model(const glm::dvec3& p) const;
  const ZoneFrame& zone_of(const Object& o, std::string_view key) const;
  std::size_t base_surface(const Object& o, std::string_view key) const;
  std::vector<glm::dvec3> rectangle_in_base(const Object& o, const Surface& base) const;
  std::vector<std::vector<glm::dvec3>> window_shades(const Object& o, const Surface& window) const;
  std::vector<glm::dvec3> rectangle(const Object& o, double default_tilt, const char* size_key,
                                    double extra_azimuth = 0.0, const glm::dvec3* start = nullptr) const;
  std::vector<glm::dvec3> crossed_rectangle(const Object& o, double default_tilt, const char* size_key,
                                            const ZoneFrame* zone) const;
  void read_globals();
  void read_surfaces();
  // read_surfaces's passes, in order: each may name surfaces of the earlier ones.
  void read_base_surfaces();
  void read_openings();
  void read_window_shades();
  void add_surface(Surface s);
  Surface::Group boundary_group(const Object& o) const;
  void warn_transmittance(const Object& o);
  void check_names();
  void cut_and_emit(Model& model);
  // Openings off their wall's plane (energyplus_reveals.hpp): checked, reveals added, reported.
  void check_placement(const Surface& opening, const Surface& base, const OpeningPlacement& placement,
                       double allowed);
  void add_reveal(const Surface& opening, const OpeningPlacement& placement, std::vector<Face>& out);
  void report_reveals();
  struct RevealCount {
    std::size_t openings = 0;
    double shallowest = 0.0, deepest = 0.0;
    const Surface* first = nullptr;
  } set_back_, proud_;
  std::optional<SunPeriod> read_sun();

  std::string file_;
  LoadOptions options_;
  int version_ = 2420;
  std::vector<ClassSpec> specs_;
  std::vector<Object> objects_;
  std::map<std::string, std::pair<std::size_t, std::string>> ignored_;  // lower class -> count, spelling
  std::vector<Warning> warnings_;

  bool clockwise_ = false;
  int start_corner_ = 0;  // Starting Vertex Position: 0 upper left, 1 lower left, 2 lower right, 3 upper right
  bool world_ = false;  // GlobalGeometryRules Coordinate System World/Absolute
  bool rectangular_world_ = false;
  double north_axis_ = 0.0;        // the sun's: the model frame's +y from true north (with appendix_g_)
  double building_north_ = 0.0;    // Building's North Axis as written (kept in world coordinates)
  double appendix_g_ = 0.0;        // Compliance:Building's Building Rotation for Appendix G
  std::vector<ZoneFrame> zones_;
  std::map<std::string, std::size_t> zone_index_;  // lower name -> zones_
  std::vector<Surface> surfaces_;
  std::map<std::string, std::size_t> surface_index_;  // lower name -> surfaces_
};

}  // namespace shadow::scene_readers::energyplus
