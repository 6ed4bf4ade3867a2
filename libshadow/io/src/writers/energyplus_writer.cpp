// SPDX-License-Identifier: GPL-3.0-or-later
// shadow/energyplus.hpp: the ShadowCalculation and Schedule:File:Shading objects that make
// EnergyPlus import energyplus-shading.csv, and a copy of a model with them in place. The IDF is
// copied as text (only the two classes' objects change), so comments and layout survive.
#include <shadow/energyplus.hpp>

#include <shadow/error.hpp>
#include <shadow/input_file.hpp>
#include <shadow/scene_io.hpp>

#include "readers/energyplus_reader.hpp"
#include "readers/idf_tokenizer.hpp"
#include "readers/json_document.hpp"
#include "readers/model_dispatch.hpp"
#include "readers/obj_reader.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <string_view>
#include <vector>

namespace shadow {
namespace {

bool same_text(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

/// The classes replaced: EnergyPlus takes one object of each (both are unique objects).
bool replaced_class(std::string_view name) {
  return same_text(name, "ShadowCalculation") || same_text(name, "Schedule:File:Shading");
}

// ShadowCalculation's fields in the order of EnergyPlus 9.6 and later: Imported, updated every
// time step (the CSV has a value per time step); the rest are EnergyPlus's defaults, written out
// so that a reader sees them.
struct Field {
  const char* value;
  const char* idd;
  const char* key;  // epJSON
  bool number;
};
const Field kShadowCalculation[] = {
    {"Imported", "Shading Calculation Method", "shading_calculation_method", false},
    {"Timestep", "Shading Calculation Update Frequency Method", "shading_calculation_update_frequency_method", false},
    {"1", "Shading Calculation Update Frequency", "shading_calculation_update_frequency", true},
    {"15000", "Maximum Figures in Shadow Overlap Calculations", "maximum_figures_in_shadow_overlap_calculations", true},
    {"SutherlandHodgman", "Polygon Clipping Algorithm", "polygon_clipping_algorithm", false},
    {"512", "Pixel Counting Resolution", "pixel_counting_resolution", true},
    {"SimpleSkyDiffuseModeling", "Sky Diffuse Modeling Algorithm", "sky_diffuse_modeling_algorithm", false},
    {"No", "Output External Shading Calculation Results", "output_external_shading_calculation_results", false},
};

void check_csv_name(const std::string& csv_file) {
  // An IDF field ends at ',' or ';' and '!' starts a comment: such a path cannot be written.
  if (csv_file.empty() || csv_file.find_first_of(",;!\r\n") != std::string::npos)
    throw InputError({csv_file, ""}, "an EnergyPlus File Name cannot hold ',', ';', '!' or a line break (nor be "
                                     "empty): write the CSV to a directory whose path has none");
}

std::string padded(const std::string& value_and_separator) {
  const std::size_t width = 28;  // the comments line up, as IDF editors write them
  return "  " + value_and_separator + std::string(value_and_separator.size() < width ? width - value_and_separator.size() : 1, ' ');
}

/// `[begin, end)` widened to whole lines when the object has its lines to itself (indentation
/// before it; blanks and a `!-` comment after its `;`), so that removing it leaves no debris.
std::pair<std::size_t, std::size_t> whole_lines(const std::string& text, std::size_t begin, std::size_t end) {
  std::size_t b = begin;
  while (b > 0 && (text[b - 1] == ' ' || text[b - 1] == '\t')) --b;
  if (b > 0 && text[b - 1] != '\n') b = begin;
  std::size_t e = end;
  while (e < text.size() && (text[e] == ' ' || text[e] == '\t' || text[e] == '\r')) ++e;
  if (e < text.size() && text[e] == '!') e = text.find('\n', e) == std::string::npos ? text.size() : text.find('\n', e);
  if (e < text.size() && text[e] == '\n')
    ++e;
  else if (e != text.size())
    e = end;  // something else follows on the line: keep it
  return {b, e};
}

EnergyPlusImportCopy idf_copy(const std::string& text, const std::string& display_name, const std::string& csv_file) {
  EnergyPlusImportCopy copy;
  const std::vector<scene_readers::IdfObject> objects = scene_readers::tokenize_idf(text, display_name);
  const std::string objects_text = "! The sunlit fractions of libshadow's `shadow series` (docs/energyplus.md)\n" +
                                   energyplus_import_objects(csv_file);
  std::size_t at = 0;
  bool placed = false;
  for (const scene_readers::IdfObject& o : objects) {
    if (same_text(o.fields[0].text, "Version") && o.fields.size() > 1 && copy.version.empty())
      copy.version = o.fields[1].text;
    if (!replaced_class(o.fields[0].text)) continue;
    const auto [b, e] = whole_lines(text, o.begin, o.end);
    copy.text.append(text, at, b - at);
    if (!placed) copy.text += objects_text;
    placed = true;
    at = e;
    ++copy.replaced;
  }
  copy.text.append(text, at, std::string::npos);
  if (!placed) {
    if (!copy.text.empty() && copy.text.back() != '\n') copy.text += '\n';
    copy.text += "\n" + objects_text;
  }
  return copy;
}

EnergyPlusImportCopy epjson_copy(const std::string& text, const std::string& display_name, const std::string& csv_file) {
  EnergyPlusImportCopy copy;
  copy.epjson = true;
  // The readers' parser: places and problems in words, duplicate keys refused.
  const nlohmann::ordered_json root = scene_readers::parse_json_document<nlohmann::ordered_json>(text, display_name);
  if (!root.is_object()) throw InputError({display_name, ""}, "an epJSON file must hold a JSON object (class -> objects)");
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  auto add_ours = [&] {
    nlohmann::ordered_json shadow_calculation = nlohmann::ordered_json::object();
    for (const Field& f : kShadowCalculation) {
      if (f.number)
        shadow_calculation[f.key] = std::stoi(f.value);
      else
        shadow_calculation[f.key] = f.value;
    }
    out["ShadowCalculation"] = {{"ShadowCalculation 1", shadow_calculation}};
    out["Schedule:File:Shading"] = {{"Schedule:File:Shading 1", {{"file_name", csv_file}}}};
  };
  bool placed = false;
  for (auto c = root.begin(); c != root.end(); ++c) {
    if (same_text(c.key(), "Version") && c.value().is_object())
      for (auto& [name, fields] : c.value().items())
        if (fields.is_object() && fields.contains("version_identifier") && fields["version_identifier"].is_string() &&
            copy.version.empty())
          copy.version = fields["version_identifier"].get<std::string>();
    if (replaced_class(c.key())) {
      copy.replaced += c.value().is_object() ? static_cast<int>(c.value().size()) : 1;
      if (!placed) add_ours();
      placed = true;
      continue;
    }
    out[c.key()] = c.value();
  }
  if (!placed) add_ours();
  copy.text = out.dump(4) + "\n";
  return copy;
}

}  // namespace

bool is_energyplus_model(const std::filesystem::path& file) {
  try {
    const std::string text = read_input_file(file, file.string(), LoadOptions{}.max_file_bytes);
    return scene_readers::model_format(file, text) == scene_readers::ModelFormat::energyplus;
  } catch (const InputError&) {
    return false;
  }
}

std::string energyplus_import_objects(const std::string& csv_file) {
  check_csv_name(csv_file);
  std::string out = "ShadowCalculation,\n";
  const std::size_t n = std::size(kShadowCalculation);
  for (std::size_t i = 0; i < n; ++i)
    out += padded(std::string(kShadowCalculation[i].value) + (i + 1 < n ? "," : ";")) + "!- " +
           kShadowCalculation[i].idd + "\n";
  out += "\nSchedule:File:Shading,\n" + padded(csv_file + ";") + "!- File Name\n";
  return out;
}

EnergyPlusImportCopy energyplus_model_importing_shading(const std::filesystem::path& model, const std::string& csv_file) {
  check_csv_name(csv_file);
  const std::string display_name = model.string();
  const std::string text = read_input_file(model, display_name, LoadOptions{}.max_file_bytes);
  if (scene_readers::model_format(model, text) != scene_readers::ModelFormat::energyplus)
    throw InputError({display_name, ""}, "not an EnergyPlus model (IDF or epJSON): --write-idf copies the model "
                                         "given as SCENE");
  const bool bom = text.compare(0, 3, "\xEF\xBB\xBF") == 0;
  const std::size_t first = text.find_first_not_of(" \t\r\n\xEF\xBB\xBF");
  std::string ext = model.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  const bool epjson = ext == ".epjson" || (first != std::string::npos && text[first] == '{');
  // The byte order mark stays where it was: the copy is the file, changed in two objects only.
  EnergyPlusImportCopy copy = epjson ? epjson_copy(bom ? text.substr(3) : text, display_name, csv_file)
                                     : idf_copy(text, display_name, csv_file);
  copy.version_code = scene_readers::energyplus_version_code(copy.version);
  return copy;
}

}  // namespace shadow
