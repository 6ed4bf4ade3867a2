// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: JSON text read into a document that knows where everything is, and the words of the
// JSON readers' messages (scene files, epJSON, CityJSON): one home for both, so that every JSON
// reader names the file, the place (line and column, or JSON path) and the problem alike.
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>

namespace shadow::scene_readers {

/// `s` as a JSON string (quotes, escapes; bytes that are not UTF-8 become U+FFFD), whole.
std::string json_string(const std::string& s);

/// A user string for a message: json_string, cut after 60 bytes with `...`.
std::string quote(const std::string& s);

/// `path.key`, or `path["key"]` when the key is not a plain name (spaces, dots, escapes), so the
/// path stays unambiguous and on one line.
std::string member(const std::string& path, const std::string& key);

/// `path[index]`.
std::string element(const std::string& path, std::size_t index);

/// "line L, column C" (1-based, columns in UTF-8 characters) of byte `offset` of `text`.
std::string line_column(const std::string& text, std::size_t offset);

/// "string \"abc\"", "null", "an object", "number 17": what was found where something else belongs.
template <class Json>
std::string describe(const Json& value) {
  switch (value.type()) {
    case Json::value_t::object: return "an object";
    case Json::value_t::array: return "an array";
    case Json::value_t::null: return "null";
    case Json::value_t::string: return "string " + quote(value.template get_ref<const std::string&>());
    case Json::value_t::boolean: return value.template get<bool>() ? "true" : "false";
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
    case Json::value_t::number_float: return "number " + value.dump();
    default: return std::string(value.type_name());
  }
}

/// How a reader spells the member `key` of the object at `depth` (0: the document's top level)
/// whose own path is `path`. nullptr: member().
using MemberSpelling = std::string (*)(const std::string& path, std::size_t depth, const std::string& key);

/// Parses `text` (nlohmann::json or nlohmann::ordered_json) like Json::parse, strictly, but as
/// one line naming `file`:
/// - a syntax error at its line and column, in words ("malformed JSON: ...", bytes that are not
///   UTF-8 shown as `\xHH` by InputError);
/// - a number beyond a double (1e999) and a key that appears twice in one object (nlohmann
///   would keep only the last) at their JSON path, spelled with `spelling`.
/// @throws InputError
template <class Json>
Json parse_json_document(const std::string& text, const std::string& file, MemberSpelling spelling = nullptr);

extern template nlohmann::json parse_json_document<nlohmann::json>(const std::string&, const std::string&,
                                                                   MemberSpelling);
extern template nlohmann::ordered_json parse_json_document<nlohmann::ordered_json>(const std::string&,
                                                                                   const std::string&,
                                                                                   MemberSpelling);

/// nlohmann's exception text without its "[json.exception...]" tag and "parse error at ...:"
/// prefix, on one line: for the rare nlohmann exception a reader did not foresee.
std::string json_exception_reason(const std::string& what);

}  // namespace shadow::scene_readers
