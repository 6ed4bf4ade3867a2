// SPDX-License-Identifier: GPL-3.0-or-later
// Which model format a file is, and the call of its reader (scene/model_dispatch.hpp).
#include "readers/model_dispatch.hpp"

#include "readers/cityjson_reader.hpp"
#include "readers/energyplus_reader.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <set>

namespace shadow::scene_readers {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

/// The top level of a JSON document, read by a SAX pass that builds nothing: the keys of the
/// top-level object and its "type" when that is a string. A real CityJSON file may put "type"
/// after megabytes of city objects (cjio writes keys in any order), so no prefix of the text
/// will do. The pass stops as soon as the keys decide: `"type": "CityJSON"`, or a key of the
/// scene format (which no CityJSON or epJSON file has at its top level; a scene file names
/// its "meshes" first, usually), or "Version" with an EnergyPlus geometry object.
class TopLevel : public nlohmann::json_sax<nlohmann::json> {
 public:
  std::set<std::string> keys;
  std::string type;
  bool scene = false;  ///< a scene file's key was seen first
  bool cityjson() const { return type == "CityJSON"; }
  bool energyplus() const;

  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t) override { return value(); }
  bool number_unsigned(number_unsigned_t) override { return value(); }
  bool number_float(number_float_t, const string_t&) override { return value(); }
  bool string(string_t& text) override {
    if (depth_ == 1 && key_ == "type") type = text;
    return !cityjson();  // false ends the pass: nothing more is needed
  }
  bool binary(binary_t&) override { return value(); }
  bool start_object(std::size_t) override {
    ++depth_;
    return true;
  }
  bool key(string_t& name) override {
    if (depth_ != 1) return true;
    key_ = name;
    keys.insert(name);
    for (const char* scene_key : {"meshes", "lights", "planes", "receivers", "materials", "camera", "sun",
                                  "sun_hours_map", "energyplus_shading"})
      if (name == scene_key) scene = true;
    return !scene && !energyplus();  // false ends the pass: decided
  }
  bool end_object() override {
    --depth_;
    return true;
  }
  bool start_array(std::size_t) override {
    ++depth_;
    return true;
  }
  bool end_array() override {
    --depth_;
    return true;
  }
  // A syntax error ends the pass; what was seen before it still decides (the reader it goes
  // to, or the scene reader, then names the error's place).
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }

 private:
  bool value() { return true; }
  int depth_ = 0;
  std::string key_;
};

/// EnergyPlus's geometry objects, any of which (with "Version") makes a JSON object an epJSON model.
bool has_energyplus_geometry(const std::set<std::string>& keys) {
  for (const char* key : {"BuildingSurface:Detailed", "FenestrationSurface:Detailed", "Shading:Site:Detailed",
                          "Shading:Building:Detailed", "Shading:Zone:Detailed", "Zone", "GlobalGeometryRules", "Building"})
    if (keys.count(key) != 0) return true;
  return false;
}

/// Case-insensitive: does `line` (leading blanks skipped) start with `word` followed by blanks and a comma?
bool starts_idf_object(std::string_view text, std::size_t begin, std::size_t end, const char* word) {
  while (begin < end && (text[begin] == ' ' || text[begin] == '\t')) ++begin;
  for (const char* c = word; *c != '\0'; ++c, ++begin)
    if (begin >= end || std::tolower(static_cast<unsigned char>(text[begin])) != *c) return false;
  while (begin < end && (text[begin] == ' ' || text[begin] == '\t')) ++begin;
  return begin < end && (text[begin] == ',' || text[begin] == ';');
}

/// IDF by content, over the whole text: a line that opens an EnergyPlus object that every
/// geometric model has. OBJ statements are a keyword and blanks, never a word and a comma.
bool looks_like_idf(std::string_view text) {
  std::size_t begin = 0;
  while (begin < text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    for (const char* word : {"version", "buildingsurface:detailed", "globalgeometryrules", "zone", "building"})
      if (starts_idf_object(text, begin, end, word)) return true;
    begin = end + 1;
  }
  return false;
}

bool TopLevel::energyplus() const { return keys.count("Version") != 0 && has_energyplus_geometry(keys); }

}  // namespace

bool is_json_text(std::string_view text) {
  std::size_t start = 0;
  if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) start = 3;  // a UTF-8 byte order mark
  start = text.find_first_not_of(" \t\r\n", start);
  return start != std::string::npos && (text[start] == '{' || text[start] == '[');
}

ModelFormat model_format(const std::filesystem::path& file, std::string_view text) {
  const std::string name = lower(file.filename().string());
  if (ends_with(name, ".idf") || ends_with(name, ".epjson")) return ModelFormat::energyplus;
  if (ends_with(name, ".city.json")) return ModelFormat::cityjson;
  if (ends_with(name, ".obj")) return ModelFormat::none;
  if (is_json_text(text)) {
    // JSON: decided by its top level, parsed (a scene file's keys are "meshes", "lights", ...).
    TopLevel top;
    nlohmann::json::sax_parse(text, &top, nlohmann::detail::input_format_t::json, /*strict=*/true,
                              /*ignore_comments=*/false);
    if (top.scene) return ModelFormat::none;
    if (top.cityjson()) return ModelFormat::cityjson;
    if (top.energyplus()) return ModelFormat::energyplus;
    return ModelFormat::none;
  }
  return looks_like_idf(text) ? ModelFormat::energyplus : ModelFormat::none;
}

Model read_model(ModelFormat format, const std::filesystem::path& path, const std::string& display_name,
                 const LoadOptions& options) {
  switch (format) {
    case ModelFormat::cityjson: return read_cityjson(path, display_name, options);
    case ModelFormat::energyplus: return read_energyplus(path, display_name, options);
    case ModelFormat::none: break;
  }
  throw InputError({display_name, ""}, "not a model file (CityJSON, EnergyPlus IDF or epJSON)");
}

}  // namespace shadow::scene_readers
