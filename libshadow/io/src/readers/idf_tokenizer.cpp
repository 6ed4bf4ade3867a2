// SPDX-License-Identifier: GPL-3.0-or-later
// IDF tokenizer: one pass over the text, tracking lines for error messages.
#include "readers/idf_tokenizer.hpp"

#include <shadow/error.hpp>

namespace shadow::scene_readers {
namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

std::string trimmed(const std::string& s) {
  std::size_t a = 0, b = s.size();
  while (a < b && is_blank(s[a])) ++a;
  while (b > a && is_blank(s[b - 1])) --b;
  return s.substr(a, b - a);
}

}  // namespace

std::vector<IdfObject> tokenize_idf(const std::string& text, const std::string& display_name) {
  std::vector<IdfObject> objects;
  IdfObject current;
  std::string field;
  std::size_t line = 1;
  std::size_t field_line = 0;  // line of the field's first non-blank character, 0 while none
  bool in_comment = false;
  std::size_t at = 0;           // byte offset of the character being read
  std::size_t field_begin = 0;  // offset of the field's first non-blank character (with field_line)
  auto finish_field = [&](std::size_t separator_line) {
    IdfField f{trimmed(field), field_line != 0 ? field_line : separator_line};
    if (current.fields.empty()) {
      current.line = f.line;
      current.begin = field_line != 0 ? field_begin : at;
    }
    current.fields.push_back(std::move(f));
    field.clear();
    field_line = 0;
  };
  for (; at < text.size(); ++at) {
    const char c = text[at];
    if (c == '\n') {
      ++line;
      in_comment = false;
      field.push_back(' ');
      continue;
    }
    if (in_comment) continue;
    if (c == '!') {
      in_comment = true;
      continue;
    }
    if (c == ',' || c == ';') {
      finish_field(line);
      if (c == ';') {
        current.end = at + 1;
        // A lone `;` (no class name) is no object: EnergyPlus skips empty statements too.
        if (!(current.fields.size() == 1 && current.fields[0].text.empty())) objects.push_back(std::move(current));
        current = IdfObject{};
      }
      continue;
    }
    if (field_line == 0 && !is_blank(c)) {
      field_line = line;
      field_begin = at;
    }
    field.push_back(c);
  }
  if (!current.fields.empty() || field_line != 0) {
    const std::size_t start = current.fields.empty() ? field_line : current.line;
    const std::string name = current.fields.empty() ? trimmed(field) : current.fields[0].text;
    throw InputError({display_name, "line " + std::to_string(start)},
                     "object " + name + " is not terminated by ';' before the end of the file");
  }
  return objects;
}

}  // namespace shadow::scene_readers
