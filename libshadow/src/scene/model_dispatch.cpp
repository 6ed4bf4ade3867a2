// SPDX-License-Identifier: GPL-3.0-or-later
// Which model format a file is, and the call of its reader (scene/model_dispatch.hpp).
#include "scene/model_dispatch.hpp"

#include "scene/cityjson_reader.hpp"
#include "scene/energyplus_reader.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>

namespace shadow::scene_readers {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

/// The top-level JSON object of `text`, or null when it is not one (a scene file with a syntax
/// error is left to the scene reader, which names the line and column).
nlohmann::json top_level(const std::string& text) {
  nlohmann::json document = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  return document.is_object() ? document : nlohmann::json();
}

}  // namespace

ModelFormat model_format(const std::filesystem::path& file, const std::string& text) {
  const std::string name = lower(file.filename().string());
  if (ends_with(name, ".idf") || ends_with(name, ".epjson")) return ModelFormat::energyplus;
  if (ends_with(name, ".city.json")) return ModelFormat::cityjson;
  if (ends_with(name, ".obj")) return ModelFormat::none;
  const std::size_t start = text.find_first_not_of(" \t\r\n\xEF\xBB\xBF");
  if (start == std::string::npos) return ModelFormat::none;
  const std::string head = lower(text.substr(0, 65536));
  if (text[start] == '{') {
    // Parse only when a marker is there: most JSON files met here are scene files.
    if (head.find("\"cityjson\"") != std::string::npos) {
      const nlohmann::json document = top_level(text);
      const auto type = document.is_object() ? document.find("type") : document.end();
      if (document.is_object() && type != document.end() && type->is_string() && *type == "CityJSON")
        return ModelFormat::cityjson;
    }
    if (head.find("\"version\"") != std::string::npos) {
      const nlohmann::json document = top_level(text);
      if (document.is_object() && document.contains("Version"))
        for (const char* key : {"BuildingSurface:Detailed", "Shading:Site:Detailed", "Shading:Building:Detailed",
                                "Zone", "GlobalGeometryRules", "Building"})
          if (document.contains(key)) return ModelFormat::energyplus;
    }
    return ModelFormat::none;
  }
  // IDF: comma-separated objects; OBJ files have no commas in their statements.
  if (head.find("buildingsurface:detailed,") != std::string::npos || head.find("globalgeometryrules,") != std::string::npos ||
      head.rfind("version,", start) == start || head.find("\nversion,") != std::string::npos)
    return ModelFormat::energyplus;
  return ModelFormat::none;
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
