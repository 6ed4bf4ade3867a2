// SPDX-License-Identifier: GPL-3.0-or-later
// JSON documents with places, and the words of JSON errors (json_document.hpp).
#include "readers/json_document.hpp"

#include <shadow/error.hpp>

#include <algorithm>
#include <type_traits>
#include <unordered_set>
#include <utility>
#include <vector>

namespace shadow::scene_readers {

std::string json_string(const std::string& s) {
  return nlohmann::json(s).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string quote(const std::string& s) {
  constexpr std::size_t kMax = 60;
  return json_string(s.size() > kMax ? s.substr(0, kMax) + "..." : s);
}

std::string member(const std::string& path, const std::string& key) {
  const bool plain = !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '$';
  });
  if (!plain) return path + "[" + quote(key) + "]";
  return path.empty() ? key : path + "." + key;
}

std::string element(const std::string& path, std::size_t index) {
  return path + "[" + std::to_string(index) + "]";
}

std::string line_column(const std::string& text, std::size_t offset) {
  offset = std::min(offset, text.size());
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < offset; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c == '\n') {
      ++line;
      column = 1;
    } else if ((c & 0xC0) != 0x80) {  // count UTF-8 characters, not continuation bytes
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

std::string json_exception_reason(const std::string& what) {
  std::string reason = what;
  if (reason.rfind("[json.exception.", 0) == 0) {
    const std::size_t close = reason.find("] ");
    if (close != std::string::npos) reason.erase(0, close + 2);
  }
  if (reason.rfind("parse error", 0) == 0) {
    const std::size_t colon = reason.find(": ");
    if (colon != std::string::npos) reason.erase(0, colon + 2);
  }
  // "last read: '<everything since the token began>'": a long string would fill the line; its
  // end (where the problem is) is what helps.
  const std::string marker = "last read: '";
  const std::size_t start = reason.find(marker);
  if (start != std::string::npos) {
    const std::size_t begin = start + marker.size();
    const std::size_t end = reason.rfind('\'');
    constexpr std::size_t kKeep = 40;
    if (end != std::string::npos && end > begin + kKeep) {
      std::size_t cut = end - kKeep;
      while (cut < end && (static_cast<unsigned char>(reason[cut]) & 0xC0) == 0x80) ++cut;  // whole characters
      reason.replace(begin, cut - begin, "...");
    }
  }
  std::replace(reason.begin(), reason.end(), '\n', ' ');
  std::replace(reason.begin(), reason.end(), '\r', ' ');
  return reason;
}

namespace {

/// Builds the document like Json::parse, knowing the JSON path of what it is reading. nlohmann's
/// own parser silently keeps the last of two equal keys; this one refuses them, and names a
/// number that overflows a double by its path and a syntax error by its line and column.
template <class Json>
class DocumentBuilder : public nlohmann::json_sax<Json> {
  using Base = nlohmann::json_sax<Json>;

 public:
  DocumentBuilder(const std::string& text, const std::string& file, MemberSpelling spelling)
      : text_(text), file_(file), spelling_(spelling) {}

  Json take() { return std::move(root_); }

  bool null() override { return add(Json(nullptr)); }
  bool boolean(bool value) override { return add(Json(value)); }
  bool number_integer(typename Base::number_integer_t value) override { return add(Json(value)); }
  bool number_unsigned(typename Base::number_unsigned_t value) override { return add(Json(value)); }
  bool number_float(typename Base::number_float_t value, const typename Base::string_t&) override {
    return add(Json(value));
  }
  bool string(typename Base::string_t& value) override { return add(Json(std::move(value))); }
  bool binary(typename Base::binary_t& value) override { return add(Json::binary(std::move(value))); }

  bool start_object(std::size_t) override {
    frames_.push_back({insert(Json::object()), false, 0, {}, {}});
    return true;
  }
  bool key(typename Base::string_t& key) override {
    Frame& frame = frames_.back();
    // An ordered object looks keys up one by one: a set keeps a class of 10,000 EnergyPlus
    // objects from costing 50 million comparisons.
    const bool seen = kOrdered ? !frame.keys.insert(key).second : frame.value->contains(key);
    if (seen) {
      const std::string where = path(frames_.size() - 1);
      throw InputError({file_, where.empty() ? "top level" : where},
                       "duplicate key " + quote(key) + ": an object holds one value per key, so one of the two "
                       "would be lost");
    }
    frame.key = key;
    return true;
  }
  bool end_object() override {
    frames_.pop_back();
    element_done();
    return true;
  }
  bool start_array(std::size_t) override {
    frames_.push_back({insert(Json::array()), true, 0, {}, {}});
    return true;
  }
  bool end_array() override { return end_object(); }

  bool parse_error(std::size_t position, const std::string& last_token,
                   const nlohmann::detail::exception& error) override {
    if (error.id == 406)  // number overflow: name the value, like any other non-finite number
      throw InputError({file_, path(frames_.size())},
                       "number " + last_token + " is not finite (it is beyond the range of a double)");
    // `position` counts the characters read; the offending one is the last of them.
    throw InputError({file_, line_column(text_, position == 0 ? 0 : position - 1)},
                     "malformed JSON: " + json_exception_reason(error.what()));
  }

 private:
  static constexpr bool kOrdered = !std::is_same_v<Json, nlohmann::json>;

  struct Frame {
    Json* value;
    bool is_array;
    std::size_t index;                     // arrays: index of the element being read
    std::string key;                       // objects: key of the member being read
    std::unordered_set<std::string> keys;  // ordered objects: the keys read so far
  };

  /// The JSON path of the value being read inside the first `depth` open containers.
  std::string path(std::size_t depth) const {
    std::string p;
    for (std::size_t i = 0; i < depth; ++i) {
      const Frame& f = frames_[i];
      p = f.is_array ? element(p, f.index) : spelling_ != nullptr ? spelling_(p, i, f.key) : member(p, f.key);
    }
    return p;
  }

  Json* insert(Json value) {
    if (frames_.empty()) {
      root_ = std::move(value);
      return &root_;
    }
    Frame& frame = frames_.back();
    if (frame.is_array) {
      frame.value->push_back(std::move(value));
      return &frame.value->back();
    }
    if constexpr (kOrdered) {
      // The key is new (key() checked it): appended without ordered_map's search of every key.
      auto& members = static_cast<typename Json::object_t::Container&>(
          frame.value->template get_ref<typename Json::object_t&>());
      members.emplace_back(frame.key, std::move(value));
      return &members.back().second;
    } else {
      Json& slot = (*frame.value)[frame.key];
      slot = std::move(value);
      return &slot;
    }
  }

  bool add(Json value) {
    insert(std::move(value));
    element_done();
    return true;
  }

  void element_done() {
    if (!frames_.empty() && frames_.back().is_array) ++frames_.back().index;
  }

  const std::string& text_;
  const std::string& file_;
  MemberSpelling spelling_;
  Json root_;
  std::vector<Frame> frames_;
};

}  // namespace

template <class Json>
Json parse_json_document(const std::string& text, const std::string& file, MemberSpelling spelling) {
  DocumentBuilder<Json> builder(text, file, spelling);
  Json::sax_parse(text, &builder, nlohmann::detail::input_format_t::json, /*strict=*/true,
                  /*ignore_comments=*/false);
  return builder.take();
}

template nlohmann::json parse_json_document<nlohmann::json>(const std::string&, const std::string&, MemberSpelling);
template nlohmann::ordered_json parse_json_document<nlohmann::ordered_json>(const std::string&, const std::string&,
                                                                            MemberSpelling);

}  // namespace shadow::scene_readers
