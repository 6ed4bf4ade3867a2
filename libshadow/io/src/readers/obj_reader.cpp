// SPDX-License-Identifier: GPL-3.0-or-later
// Wavefront OBJ reading: only `v` and `f` matter for shadows; everything else is skipped.
//
// The whole file is read into memory and scanned line by line with std::from_chars, so a
// million-line mesh parses in a fraction of a second.
#include "readers/obj_reader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "runtime/first_touch.hpp"
#include "runtime/parallel.hpp"
#include "runtime/uninit_vector.hpp"

#include <shadow/input_file.hpp>
#include <shadow/scene_io.hpp>

#include <glm/vec3.hpp>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace shadow {


namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

/// Splits a logical line into whitespace-separated tokens without copying.
class Tokens {
 public:
  explicit Tokens(std::string_view line) : rest_(line) {}
  /// The next token, or an empty view at the end.
  std::string_view next() {
    std::size_t i = 0;
    while (i < rest_.size() && is_blank(rest_[i])) ++i;
    std::size_t j = i;
    while (j < rest_.size() && !is_blank(rest_[j])) ++j;
    const std::string_view token = rest_.substr(i, j - i);
    rest_.remove_prefix(j);
    return token;
  }

 private:
  std::string_view rest_;
};

/// What went wrong on one line; turned into an InputError with the file name by the caller.
struct LineError {
  std::string problem;
};

std::string quoted(std::string_view token) {
  constexpr std::size_t kMax = 40;  // keep the error on one readable line
  std::string out = "\"";
  out.append(token.substr(0, kMax));
  if (token.size() > kMax) out += "...";
  out += '"';
  return out;
}

/// A coordinate: the whole token must be a finite number.
double parse_coordinate(std::string_view token, const char* axis) {
  std::string_view digits = token;
  // from_chars does not take a leading '+', which some exporters write.
  if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-' && digits[1] != '+')
    digits.remove_prefix(1);
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (ptr != digits.data() + digits.size() || (ec != std::errc() && ec != std::errc::result_out_of_range))
    throw LineError{std::string(axis) + " coordinate " + quoted(token) + " is not a number"};
  if (ec == std::errc::result_out_of_range) {
    // from_chars leaves the value unset; strtod tells overflow (inf) from underflow (tiny).
    value = std::strtod(std::string(digits).c_str(), nullptr);
  }
  if (!std::isfinite(value))
    throw LineError{std::string(axis) + " coordinate " + quoted(token) +
                    " is not finite (NaN, infinity or beyond the range of a double)"};
  return value;
}

/// The x, y and z of a `v` statement (after the keyword).
glm::dvec3 parse_vertex(Tokens& tokens) {
  glm::dvec3 v;
  const char* axes[3] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i) {
    const std::string_view token = tokens.next();
    if (token.empty()) throw LineError{"vertex has " + std::to_string(i) + " coordinates; 3 are needed (v x y z)"};
    v[i] = parse_coordinate(token, axes[i]);
  }
  return v;
}

/// An OBJ index (vertex, texture or normal part of a face reference).
bool parse_index(std::string_view text, long long& index) {
  if (!text.empty() && text[0] == '+') text.remove_prefix(1);
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), index);
  if (ec == std::errc::result_out_of_range && ptr == text.data() + text.size()) {
    index = text[0] == '-' ? -(1LL << 62) : (1LL << 62);  // surely out of range; reported as such
    return true;
  }
  return !text.empty() && ec == std::errc() && ptr == text.data() + text.size();
}

/// The vertex index of one face reference (`v`, `v/t`, `v//n` or `v/t/n`), its syntax checked;
/// `vertex_part` is set to the text of the vertex index.
long long parse_reference(std::string_view ref, std::string_view& vertex_part) {
  const std::size_t slash = ref.find('/');
  vertex_part = ref.substr(0, slash);
  long long index = 0;
  if (!parse_index(vertex_part, index))
    throw LineError{"face vertex reference " + quoted(ref) +
                    " is malformed (expected v, v/t, v//n or v/t/n with integer indices)"};
  if (slash != std::string_view::npos) {
    // Texture and normal indices are not used, but a malformed reference is still an error.
    const std::string_view rest = ref.substr(slash + 1);
    const std::size_t slash2 = rest.find('/');
    const std::string_view texture = rest.substr(0, slash2);
    const std::string_view normal =
        slash2 == std::string_view::npos ? std::string_view() : rest.substr(slash2 + 1);
    long long ignored = 0;
    const bool ok = (texture.empty() || parse_index(texture, ignored)) &&
                    (normal.empty() || parse_index(normal, ignored)) &&
                    !(slash2 != std::string_view::npos && normal.empty()) &&
                    !(slash2 == std::string_view::npos && texture.empty());
    if (!ok)
      throw LineError{"face vertex reference " + quoted(ref) +
                      " is malformed (expected v, v/t, v//n or v/t/n with integer indices)"};
  }
  return index;
}

/// `index` (written as `vertex_part`) as a 0-based vertex index, `vertex_count` vertices read so far.
std::size_t resolve_index(long long index, std::string_view vertex_part, std::size_t vertex_count) {
  const auto count = static_cast<long long>(vertex_count);
  // Negative indices count back from the last vertex defined so far (-1 is the last one).
  const long long resolved = index > 0 ? index - 1 : count + index;
  if (index != 0 && resolved >= 0 && resolved < count) return static_cast<std::size_t>(resolved);
  const std::string so_far = " (the file has " + std::to_string(vertex_count) +
                             (vertex_count == 1 ? " vertex" : " vertices") + " so far)";
  if (index == 0) throw LineError{"vertex index 0 is invalid: OBJ indices start at 1" + so_far};
  throw LineError{"vertex index " + std::string(vertex_part) + " is out of range" + so_far};
}

/// Resolves one face reference to a 0-based vertex index.
std::size_t resolve_reference(std::string_view ref, std::size_t vertex_count) {
  std::string_view vertex_part;
  const long long index = parse_reference(ref, vertex_part);
  return resolve_index(index, vertex_part, vertex_count);
}

/// The problem of a face with `n` references (fewer than 3).
LineError too_few_vertices(std::size_t n) {
  return LineError{"face has " + std::to_string(n) + (n == 1 ? " vertex" : " vertices") + "; at least 3 are needed"};
}

/// Calls `statement(text, line_number)` for every logical line: comments stripped, backslash
/// continuations joined, CR of CRLF endings removed. The line number is where it starts.
/// `text` may be a part of a file that starts at a line (`at_file_start` false: no BOM there).
template <typename Statement>
void for_each_statement(std::string_view text, Statement&& statement, bool at_file_start = true) {
  std::size_t pos = at_file_start && text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;  // skip a UTF-8 BOM
  std::size_t line_number = 0;
  std::string joined;  // only used for continued lines
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    ++line_number;
    const std::size_t first_line = line_number;
    std::string_view line(text.data() + pos, end - pos);
    pos = end + 1;
    auto trim_cr = [](std::string_view l) {
      while (!l.empty() && (l.back() == '\r' || l.back() == ' ' || l.back() == '\t')) l.remove_suffix(1);
      return l;
    };
    line = trim_cr(line);
    if (!line.empty() && line.back() == '\\') {
      joined.assign(line.data(), line.size() - 1);
      while (pos < text.size()) {
        std::size_t next_end = text.find('\n', pos);
        if (next_end == std::string::npos) next_end = text.size();
        ++line_number;
        std::string_view next = trim_cr(std::string_view(text.data() + pos, next_end - pos));
        pos = next_end + 1;
        const bool continues = !next.empty() && next.back() == '\\';
        if (continues) next.remove_suffix(1);
        joined += ' ';
        joined.append(next.data(), next.size());
        if (!continues) break;
      }
      line = joined;
    }
    const std::size_t hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    statement(line, first_line);
  }
}

/// One part of an OBJ text read on its own thread (parse_obj_in_chunks): its vertices in order
/// and its faces as vertex indices, resolved once every earlier part's vertex count is known.
/// Lines are numbered from 1 within the part.
struct ObjChunk {
  struct RawFace {
    std::size_t line = 0;
    std::string_view text;        ///< the statement, to find a bad reference's text again
    std::size_t refs_begin = 0, refs_end = 0;
    std::size_t vertices_before = 0;  ///< the part's vertices read before it
    long group = -1;              ///< index into `groups`; -1: the group the part starts with
  };
  std::string_view text;
  std::vector<glm::dvec3> vertices;
  std::vector<long long> refs;
  std::vector<RawFace> faces;
  std::vector<std::string> groups;  ///< the `o`/`g` names set in this part, in order
  // The part's first error, if any: its line and problem; `face_refs` set when a face's
  // reference was malformed, with the references before it (resolved first, as one thread does).
  std::size_t error_line = 0;
  std::string error;
  std::optional<RawFace> error_face;
};

struct ChunkStop {};

void parse_chunk(ObjChunk& chunk, bool at_file_start) {
  long group = -1;
  try {
    for_each_statement(
        chunk.text,
        [&](std::string_view line, std::size_t line_number) {
          ObjChunk::RawFace face;
          try {
            Tokens tokens(line);
            const std::string_view keyword = tokens.next();
            if (keyword == "v") {
              chunk.vertices.push_back(parse_vertex(tokens));
            } else if (keyword == "f" || keyword == "fo") {
              face = {line_number, line, chunk.refs.size(), chunk.refs.size(), chunk.vertices.size(), group};
              std::string_view part;
              for (std::string_view ref = tokens.next(); !ref.empty(); ref = tokens.next()) {
                chunk.refs.push_back(parse_reference(ref, part));
                face.refs_end = chunk.refs.size();
              }
              chunk.faces.push_back(face);
            } else if (keyword == "o" || keyword == "g") {
              std::string name;
              for (std::string_view n = tokens.next(); !n.empty(); n = tokens.next()) {
                if (!name.empty()) name += ' ';
                name.append(n.data(), n.size());
              }
              chunk.groups.push_back(std::move(name));
              group = static_cast<long>(chunk.groups.size()) - 1;
            }
          } catch (const LineError& e) {
            chunk.error_line = line_number;
            chunk.error = e.problem;
            if (face.line == line_number) chunk.error_face = face;  // a face's reference was malformed
            throw ChunkStop{};
          }
        },
        at_file_start);
  } catch (const ChunkStop&) {
  }
}

/// Resolves `face`'s references with `before` vertices read before its part; the LineError of
/// the first bad one (as resolve_reference throws it), or of too few references.
void resolve_face(const ObjChunk& chunk, const ObjChunk::RawFace& face, std::size_t before, bool count_checked,
                  const runtime::UninitVector<glm::dvec3>& vertices, std::vector<glm::dvec3>* out) {
  const std::size_t so_far = before + face.vertices_before;
  for (std::size_t r = face.refs_begin; r < face.refs_end; ++r) {
    const long long index = chunk.refs[r];
    const long long count = static_cast<long long>(so_far);
    const long long resolved = index > 0 ? index - 1 : count + index;
    if (index != 0 && resolved >= 0 && resolved < count) {
      if (out != nullptr) out->push_back(vertices[static_cast<std::size_t>(resolved)]);
      continue;
    }
    // The error path: the reference's text again, for the message.
    Tokens tokens(face.text);
    tokens.next();
    std::string_view ref;
    for (std::size_t k = face.refs_begin; k <= r; ++k) ref = tokens.next();
    std::string_view part;
    parse_reference(ref, part);
    resolve_index(index, part, so_far);  // throws
  }
  if (count_checked && face.refs_end - face.refs_begin < 3) throw too_few_vertices(face.refs_end - face.refs_begin);
}

/// parse_obj_with_lines on `threads` threads, when the text is large enough and has no continued
/// line (those can join lines across a cut); false: read it on one thread instead.
bool parse_obj_in_chunks(std::string_view text, const std::string& display_name, std::vector<std::size_t>* face_lines,
                         std::vector<std::string>* face_groups, unsigned threads, std::size_t min_chunk_bytes,
                         std::vector<std::vector<glm::dvec3>>& faces) {
  threads = std::min(runtime::resolve_threads(threads), runtime::kMaxThreads);  // (validation rejects more)
  min_chunk_bytes = std::max<std::size_t>(min_chunk_bytes, 1);
  if (threads < 2 || text.size() < 2 * min_chunk_bytes || text.find('\\') != std::string_view::npos) return false;
  // Parts that start at a line: a few per thread, so that uneven ones even out.
  const std::size_t parts = std::min<std::size_t>(std::size_t{4} * threads, text.size() / min_chunk_bytes);
  std::vector<ObjChunk> chunks;
  for (std::size_t begin = 0, k = 1; begin < text.size(); ++k) {
    std::size_t end = k >= parts ? text.size() : std::max(begin + 1, text.size() * k / parts);
    end = end >= text.size() ? text.size() : text.find('\n', end - 1);
    end = end == std::string_view::npos ? text.size() : end + 1;
    chunks.emplace_back().text = text.substr(begin, end - begin);
    begin = end;
  }
  const std::size_t n = chunks.size();
  if (n == 0 || n > text.size()) return false;  // (never: the text is not empty)
  std::vector<std::size_t> newlines(n, 0);
  runtime::parallel_for(n, threads, [&](unsigned, std::size_t k) {
    parse_chunk(chunks[k], k == 0);
    newlines[k] = static_cast<std::size_t>(std::count(chunks[k].text.begin(), chunks[k].text.end(), '\n'));
  });
  // Where each part starts: its first line, its first vertex and face, the group in force.
  std::vector<std::size_t> line0(n, 0), vertex0(n, 0), face0(n + 1, 0);
  std::vector<std::string> group0(n);
  for (std::size_t k = 1; k < n; ++k) {
    line0[k] = line0[k - 1] + newlines[k - 1];
    vertex0[k] = vertex0[k - 1] + chunks[k - 1].vertices.size();
    group0[k] = chunks[k - 1].groups.empty() ? group0[k - 1] : chunks[k - 1].groups.back();
  }
  for (std::size_t k = 0; k < n; ++k) face0[k + 1] = face0[k] + chunks[k].faces.size();
  // Written in full by the parts' copies below (uninitialised: first touched there, not zeroed here).
  runtime::UninitVector<glm::dvec3> vertices(vertex0.back() + chunks.back().vertices.size());
  runtime::parallel_for(n, threads, [&](unsigned, std::size_t k) {
    std::copy(chunks[k].vertices.begin(), chunks[k].vertices.end(), vertices.begin() + static_cast<std::ptrdiff_t>(vertex0[k]));
  });
  // Sized on this thread, their pages first touched on every thread (runtime/first_touch.hpp).
  faces.clear();
  runtime::resize_touched(faces, face0[n], threads);
  if (face_lines != nullptr) {
    face_lines->clear();
    runtime::resize_touched(*face_lines, face0[n], threads);  // (zeros, as assign(n, 0) gave)
  }
  if (face_groups != nullptr) {
    face_groups->clear();
    runtime::resize_touched(*face_groups, face0[n], threads);
  }
  // Every part's faces; the first error of the file is the first part's that has one: a bad
  // reference comes before the part's own error (its faces precede that line).
  std::vector<std::optional<LineError>> failed(n);
  std::vector<std::size_t> failed_line(n, 0);
  runtime::parallel_for(n, threads, [&](unsigned, std::size_t k) {
    const ObjChunk& chunk = chunks[k];
    for (std::size_t i = 0; i < chunk.faces.size(); ++i) {
      const ObjChunk::RawFace& face = chunk.faces[i];
      std::vector<glm::dvec3>& out = faces[face0[k] + i];
      out.reserve(face.refs_end - face.refs_begin);
      try {
        resolve_face(chunk, face, vertex0[k], true, vertices, &out);
      } catch (const LineError& e) {
        failed[k] = e;
        failed_line[k] = face.line;
        return;
      }
      if (face_lines != nullptr) (*face_lines)[face0[k] + i] = line0[k] + face.line;
      if (face_groups != nullptr)
        (*face_groups)[face0[k] + i] = face.group < 0 ? group0[k] : chunk.groups[static_cast<std::size_t>(face.group)];
    }
    if (chunk.error.empty()) return;
    failed_line[k] = chunk.error_line;
    failed[k] = LineError{chunk.error};
    if (chunk.error_face) {
      try {
        resolve_face(chunk, *chunk.error_face, vertex0[k], false, vertices, nullptr);
      } catch (const LineError& e) {
        failed[k] = e;
      }
    }
  });
  for (std::size_t k = 0; k < n; ++k)
    if (failed[k]) throw InputError({display_name, "line " + std::to_string(line0[k] + failed_line[k])}, failed[k]->problem);
  return true;
}

[[noreturn]] void throw_open_error(const std::string& display_name, const char* what, int error) {
  throw InputError({display_name, ""}, std::string(what) + ": " + std::strerror(error));
}


}  // namespace

namespace {

/// A user's file opened under read_input_file's rules: a regular file of at most `max_bytes`
/// bytes when stat'ed. Closes its descriptor when it goes.
struct OpenedInput {
  int fd = -1;
  std::uintmax_t size = 0;
  OpenedInput() = default;
  OpenedInput(const OpenedInput&) = delete;
  OpenedInput& operator=(const OpenedInput&) = delete;
  ~OpenedInput() {
    if (fd >= 0) ::close(fd);
  }
};

InputError too_big_error(const std::string& display_name, std::uintmax_t max_bytes, const std::string& limit_name) {
  return InputError({display_name, ""}, "file is larger than the limit of " + std::to_string(max_bytes) + " bytes (" +
                                            limit_name + ")");
}

void open_input(const std::filesystem::path& file, const std::string& display_name, std::uintmax_t max_bytes,
                const std::string& limit_name, OpenedInput& opened) {
  // Regular files only (symlinks followed): a FIFO would block forever, /dev/zero never ends.
  // The file is opened without blocking and its type taken from the open descriptor, so a FIFO
  // swapped in after a check cannot block the open or the reads.
  errno = 0;
  opened.fd = ::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (opened.fd < 0) throw_open_error(display_name, "cannot open", errno != 0 ? errno : ENOENT);
  struct stat info {};
  if (::fstat(opened.fd, &info) != 0) throw_open_error(display_name, "cannot open", errno);
  if (S_ISDIR(info.st_mode)) throw_open_error(display_name, "cannot open", EISDIR);
  if (!S_ISREG(info.st_mode))
    throw InputError({display_name, ""}, "cannot open: not a regular file (a device, FIFO or socket)");
  opened.size = static_cast<std::uintmax_t>(info.st_size);
  if (opened.size > max_bytes) throw too_big_error(display_name, max_bytes, limit_name);
  ::fcntl(opened.fd, F_SETFL, ::fcntl(opened.fd, F_GETFL) & ~O_NONBLOCK);  // a regular file: reads never block anyway
}

/// Reads up to `count` bytes into `to` from the file's position (offset < 0: read(2)) or at
/// `offset` (pread(2), the position unchanged: for parts of one file on several threads), as
/// many as there are: fewer only at the file's end. Throws "cannot read" on an error.
std::size_t read_bytes(int fd, char* to, std::size_t count, const std::string& display_name, off_t offset = -1) {
  std::size_t done = 0;
  while (done < count) {
    const ssize_t n = offset < 0 ? ::read(fd, to + done, count - done)
                                 : ::pread(fd, to + done, count - done, offset + static_cast<off_t>(done));
    if (n < 0) {
      if (errno == EINTR) continue;
      throw_open_error(display_name, "cannot read", errno != 0 ? errno : EIO);
    }
    if (n == 0) break;
    done += static_cast<std::size_t>(n);
  }
  return done;
}

/// Appends the rest of the file (from its position) to `out`, the limit holding for what is read.
template <class Bytes>
void read_rest(int fd, Bytes& out, const std::string& display_name, std::uintmax_t max_bytes,
               const std::string& limit_name) {
  char buffer[1 << 16];
  for (std::size_t n = 0; (n = read_bytes(fd, buffer, sizeof buffer, display_name)) > 0;) {
    // The file may grow while it is read: the limit holds for what is read, not what was stat'ed.
    if (out.size() + n > max_bytes) throw too_big_error(display_name, max_bytes, limit_name);
    out.insert(out.end(), buffer, buffer + n);
  }
}

}  // namespace

std::string read_input_file(const std::filesystem::path& file, const std::string& display_name,
                            std::uintmax_t max_bytes, const std::string& limit_name) {
  OpenedInput opened;
  open_input(file, display_name, max_bytes, limit_name, opened);
  std::string text;
  text.reserve(static_cast<std::size_t>(opened.size));
  read_rest(opened.fd, text, display_name, max_bytes, limit_name);
  return text;
}

namespace detail {

std::vector<std::vector<glm::dvec3>> parse_obj_with_lines(std::string_view obj_text,
                                                          const std::string& display_name,
                                                          std::vector<std::size_t>* face_lines,
                                                          std::vector<std::string>* face_groups, unsigned threads,
                                                          std::size_t min_chunk_bytes) {
  if (std::vector<std::vector<glm::dvec3>> faces;
      parse_obj_in_chunks(obj_text, display_name, face_lines, face_groups, threads, min_chunk_bytes, faces))
    return faces;
  std::vector<glm::dvec3> vertices;
  std::string group;  // the latest `o` or `g` name: the name of the faces that follow
  std::vector<std::vector<glm::dvec3>> faces;
  std::vector<glm::dvec3> scratch;  // the face being read, reused
  if (face_lines != nullptr) face_lines->clear();
  if (face_groups != nullptr) face_groups->clear();
  for_each_statement(obj_text, [&](std::string_view line, std::size_t line_number) {
    try {
      Tokens tokens(line);
      const std::string_view keyword = tokens.next();
      if (keyword == "v") {
        const glm::dvec3 v = parse_vertex(tokens);
        // An optional w, or the vertex colours some exporters append: not needed here.
        vertices.push_back(v);
      } else if (keyword == "f" || keyword == "fo") {  // `fo` is the old spelling of `f`
        scratch.clear();
        for (std::string_view ref = tokens.next(); !ref.empty(); ref = tokens.next())
          scratch.push_back(vertices[resolve_reference(ref, vertices.size())]);
        if (scratch.size() < 3) throw too_few_vertices(scratch.size());
        faces.emplace_back(scratch.begin(), scratch.end());  // one allocation of the right size
        if (face_lines != nullptr) face_lines->push_back(line_number);
        if (face_groups != nullptr) face_groups->push_back(group);
      } else if (keyword == "o" || keyword == "g") {
        // The rest of the line, names separated by single spaces (`g a b` belongs to groups a
        // and b: its name is "a b"); `g` alone goes back to no name.
        group.clear();
        for (std::string_view name = tokens.next(); !name.empty(); name = tokens.next()) {
          if (!group.empty()) group += ' ';
          group.append(name.data(), name.size());
        }
      }
      // vt, vn, vp, s, usemtl, mtllib, l, p, curves and unknown statements: not geometry
      // that casts shadows, ignored.
    } catch (const LineError& e) {
      throw InputError({display_name, "line " + std::to_string(line_number)}, e.problem);
    }
  });
  return faces;
}

runtime::UninitVector<char> read_input_bytes(const std::filesystem::path& file, const std::string& display_name,
                                             std::uintmax_t max_bytes, const std::string& limit_name, unsigned threads) {
  OpenedInput opened;
  open_input(file, display_name, max_bytes, limit_name, opened);
  runtime::UninitVector<char> bytes;
  // A regular file that cannot be read at an offset (some FUSE and proc files): from start to end
  // on this thread, as read_input_file reads.
  char probe = 0;
  if (::pread(opened.fd, &probe, 0, 0) < 0 && errno == ESPIPE) {
    bytes.reserve(static_cast<std::size_t>(opened.size));
    read_rest(opened.fd, bytes, display_name, max_bytes, limit_name);
    return bytes;
  }
  const auto size = static_cast<std::size_t>(opened.size);
  bytes.resize(size);
  // The stat'ed size in parts of kPart bytes, each read on the thread that takes it (at most
  // kReaders at once: more concurrent reads gain nothing from a disk).
  constexpr std::size_t kPart = std::size_t{8} << 20;
  constexpr unsigned kReaders = 8;
  const std::size_t parts = (size + kPart - 1) / kPart;
  std::vector<std::size_t> got(parts, 0);
  const unsigned readers = static_cast<unsigned>(
      std::min<std::size_t>({runtime::resolve_threads(threads), kReaders, std::max<std::size_t>(parts, 1)}));
  runtime::parallel_for(parts, readers, [&](unsigned, std::size_t k) {
    const std::size_t begin = k * kPart, count = std::min(kPart, size - begin);
    got[k] = read_bytes(opened.fd, bytes.data() + begin, count, display_name, static_cast<off_t>(begin));
  });
  // A file that shrank while it was read: what its parts still held, up to the first short one.
  std::size_t have = 0;
  for (std::size_t k = 0; k < parts; ++k) {
    have += got[k];
    if (got[k] < std::min(kPart, size - k * kPart)) {
      bytes.resize(have);
      return bytes;
    }
  }
  // A file that grew: the rest, as read_input_file reads it.
  if (::lseek(opened.fd, static_cast<off_t>(have), SEEK_SET) < 0)
    throw_open_error(display_name, "cannot read", errno != 0 ? errno : EIO);
  read_rest(opened.fd, bytes, display_name, max_bytes, limit_name);
  return bytes;
}

std::vector<std::vector<glm::dvec3>> read_obj_with_lines(const std::filesystem::path& obj_file,
                                                         const std::string& display_name,
                                                         std::vector<std::size_t>* face_lines,
                                                         std::uintmax_t max_bytes,
                                                         std::vector<std::string>* face_groups) {
  return parse_obj_with_lines(read_input_file(obj_file, display_name, max_bytes), display_name, face_lines,
                              face_groups);
}

}  // namespace detail

std::vector<std::vector<glm::dvec3>> read_obj(const std::filesystem::path& obj_file,
                                             const std::string& display_name, std::uintmax_t max_bytes) {
  return detail::read_obj_with_lines(obj_file, display_name, nullptr, max_bytes);
}

std::vector<std::vector<glm::dvec3>> parse_obj(const std::string& obj_text,
                                              const std::string& display_name) {
  return detail::parse_obj_with_lines(obj_text, display_name, nullptr);
}

}  // namespace shadow
