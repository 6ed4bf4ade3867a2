// SPDX-License-Identifier: GPL-3.0-or-later
/// @file
/// @brief Handing a sun series back to EnergyPlus: the objects that make EnergyPlus read
/// `energyplus-shading.csv` instead of computing its own shading, and a copy of a model with
/// them in place (docs/energyplus.md, "Results back into EnergyPlus").
#pragma once

#include <filesystem>
#include <string>

namespace shadow {

/// Whether `file` is an EnergyPlus model (IDF or epJSON), decided as load_scene decides it: by
/// its name (`.idf`, `.epJSON`), else by its content. False for a file that cannot be read.
bool is_energyplus_model(const std::filesystem::path& file);

/// The IDF text of the two objects that make EnergyPlus import a sunlit-fraction CSV:
/// `ShadowCalculation` (Shading Calculation Method `Imported`, updated every time step, the
/// other fields at EnergyPlus's defaults, in the field order of EnergyPlus 9.6 and later) and
/// `Schedule:File:Shading` whose File Name is `csv_file` (written as given: pass an absolute
/// path, EnergyPlus runs in a directory of its own). Lines end in `\n`; each field carries its
/// `!-` comment.
std::string energyplus_import_objects(const std::string& csv_file);

/// A copy of an EnergyPlus model with the objects of energyplus_import_objects() in place.
struct EnergyPlusImportCopy {
  std::string text;     ///< the model, in its own syntax (IDF text or epJSON)
  bool epjson = false;  ///< the model (and so `text`) is epJSON
  std::string version;  ///< the model's Version (its version identifier), empty when it has none
  /// `version` as major * 100 + minor (9.6 -> 906), as the reader picks its field lists; 0 when
  /// there is none or it is no version identifier.
  int version_code = 0;
  /// How many ShadowCalculation and Schedule:File:Shading objects of the model were replaced.
  int replaced = 0;
};

/// Reads the EnergyPlus model `model` (IDF, or epJSON by name or content, as load_scene decides)
/// and returns a copy that imports `csv_file`: IDF text is kept byte for byte except that every
/// ShadowCalculation and Schedule:File:Shading object is removed and the new pair is put where
/// the first ShadowCalculation was (at the end when there was none); epJSON is parsed and written
/// again (4-space indentation) with the two classes replaced.
/// @throws InputError when `model` is not an EnergyPlus model, cannot be read, or is malformed
/// (an IDF object without its `;`, JSON that does not parse)
EnergyPlusImportCopy energyplus_model_importing_shading(const std::filesystem::path& model,
                                                        const std::string& csv_file);

}  // namespace shadow
