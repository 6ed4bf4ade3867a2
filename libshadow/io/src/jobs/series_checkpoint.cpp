// SPDX-License-Identifier: GPL-3.0-or-later
// Series columns as raw bytes: MPI messages and OUTDIR/series.checkpoint (series_checkpoint.hpp).
#include "jobs/series_checkpoint.hpp"

#include <shadow/error.hpp>
#include <shadow/output.hpp>
#include <shadow/version.hpp>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <type_traits>

namespace shadow::jobs {
namespace {

namespace fs = std::filesystem;

constexpr char kMagic[8] = {'S', 'H', 'D', 'W', 'C', 'K', 'P', 'T'};
constexpr std::uint32_t kFormat = 2;  // 2: the stats carry tiled_receivers and tiles
constexpr std::uint32_t kRecord = 0x52454331;  // "REC1"

/// FNV-1a, 64 bits: a digest of inputs and a checksum of records (not a defence against
/// tampering, a guard against changed inputs and torn writes).
struct Fnv {
  std::uint64_t h = 0xcbf29ce484222325ull;
  void bytes(const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) {
      h ^= p[i];
      h *= 0x100000001b3ull;
    }
  }
  template <typename T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes(&v, sizeof v);
  }
  void text(const std::string& s) {
    value(static_cast<std::uint64_t>(s.size()));
    bytes(s.data(), s.size());
  }
};

class Writer {
 public:
  template <typename T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    out.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  template <typename T>
  void put_all(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    put(static_cast<std::uint64_t>(v.size()));
    if (!v.empty()) out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void text(const std::string& s) {
    put(static_cast<std::uint64_t>(s.size()));
    out += s;
  }
  std::string out;
};

class Reader {
 public:
  explicit Reader(const std::string& bytes) : data_(bytes) {}
  template <typename T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    need(sizeof(T));
    T v;
    std::memcpy(&v, data_.data() + at_, sizeof v);
    at_ += sizeof v;
    return v;
  }
  template <typename T>
  std::vector<T> get_all() {
    const auto n = get<std::uint64_t>();
    if (n > (data_.size() - at_) / sizeof(T)) throw std::runtime_error("series message: truncated");
    std::vector<T> v(n);
    if (n > 0) std::memcpy(v.data(), data_.data() + at_, n * sizeof(T));
    at_ += n * sizeof(T);
    return v;
  }
  std::string text() {
    const auto n = get<std::uint64_t>();
    need(n);
    std::string s = data_.substr(at_, n);
    at_ += n;
    return s;
  }
  [[nodiscard]] bool at_end() const { return at_ == data_.size(); }

 private:
  void need(std::uint64_t n) const {
    if (n > data_.size() - at_) throw std::runtime_error("series message: truncated");
  }
  const std::string& data_;
  std::size_t at_ = 0;
};

void put_stats(Writer& w, const shadow::ShadowStats& s) {
  for (std::uint64_t v : {s.receivers, s.back_facing, s.candidate_pairs, s.casting_pairs, s.unshadowed,
                          s.fast_exact_fallbacks, s.fast_collapsed, s.tiled_receivers, s.tiles})
    w.put(v);
}

shadow::ShadowStats get_stats(Reader& r) {
  shadow::ShadowStats s;
  for (std::uint64_t* v : {&s.receivers, &s.back_facing, &s.candidate_pairs, &s.casting_pairs, &s.unshadowed,
                           &s.fast_exact_fallbacks, &s.fast_collapsed, &s.tiled_receivers, &s.tiles})
    *v = r.get<std::uint64_t>();
  return s;
}

void put_vec3(Writer& w, const glm::dvec3& p) {
  w.put(p.x);
  w.put(p.y);
  w.put(p.z);
}

glm::dvec3 get_vec3(Reader& r) {
  glm::dvec3 p;
  p.x = r.get<double>();
  p.y = r.get<double>();
  p.z = r.get<double>();
  return p;
}

std::string errno_text(int saved) { return saved != 0 ? std::strerror(saved) : "could not write the file"; }

/// Writes all of `bytes` at the file's end and flushes them to the disk.
void write_durably(std::FILE* file, const std::string& bytes, const fs::path& path) {
  errno = 0;
  if (std::fwrite(bytes.data(), 1, bytes.size(), file) != bytes.size() || std::fflush(file) != 0 ||
      ::fsync(::fileno(file)) != 0)
    throw shadow::OutputError(path.string() + ": " + errno_text(errno));
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

/// A regular file opened for reading, and its size.
struct OpenedFile {
  std::unique_ptr<std::FILE, FileCloser> in;
  std::uintmax_t size = 0;
};

/// Opens `path` under the rules of read_input_file (shadow/input_file.hpp): a regular file (the
/// type taken from the open descriptor, opened without blocking), at most `limit` bytes.
/// @throws shadow::InputError naming the file
OpenedFile open_checked(const fs::path& path, std::uintmax_t limit, const std::string& limit_name) {
  const std::string name = path.string();
  errno = 0;
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw shadow::InputError({name, ""}, std::string("cannot open: ") + std::strerror(errno != 0 ? errno : ENOENT));
  struct stat info {};
  if (::fstat(fd, &info) != 0 || S_ISDIR(info.st_mode)) {
    const int error = S_ISDIR(info.st_mode) ? EISDIR : errno;
    ::close(fd);
    throw shadow::InputError({name, ""}, std::string("cannot open: ") + std::strerror(error));
  }
  if (!S_ISREG(info.st_mode)) {
    ::close(fd);
    throw shadow::InputError({name, ""}, "cannot open: not a regular file (a device, FIFO or socket)");
  }
  OpenedFile file;
  file.size = static_cast<std::uintmax_t>(info.st_size);
  if (file.size > limit) {
    ::close(fd);
    throw shadow::InputError({name, ""}, "file is larger than the limit of " + std::to_string(limit) + " bytes (" +
                                             limit_name + ")");
  }
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);  // a regular file: reads never block anyway
  file.in.reset(::fdopen(fd, "rb"));
  if (!file.in) {
    const int error = errno;
    ::close(fd);
    throw shadow::InputError({name, ""}, std::string("cannot open: ") + std::strerror(error != 0 ? error : EIO));
  }
  return file;
}

}  // namespace

SeriesColumns columns_of(const shadow::SeriesResult& part, const std::vector<std::uint64_t>& instants) {
  if (part.instants != instants.size()) throw std::runtime_error("series columns: instants do not match");
  SeriesColumns c;
  c.instants = instants;
  c.rows = part.faces.size();
  const std::size_t n = c.rows * instants.size();
  c.lit_area.resize(n);
  c.lit_fraction.resize(n);
  c.lit_area_error_bound.resize(n);
  c.faces_light.resize(n);
  for (std::size_t k = 0; k < instants.size(); ++k)
    for (std::size_t r = 0; r < c.rows; ++r) {
      const std::size_t from = part.at(r, k), to = k * c.rows + r;
      c.lit_area[to] = part.lit_area[from];
      c.lit_fraction[to] = part.lit_fraction[from];
      c.lit_area_error_bound[to] = part.lit_area_error_bound[from];
      c.faces_light[to] = part.faces_light[from];
    }
  c.stats = part.stats;
  return c;
}

void place_columns(const SeriesColumns& c, shadow::SeriesResult& full) {
  const std::size_t n = c.rows * c.instants.size();
  if (c.rows != full.faces.size() || c.lit_area.size() != n || c.lit_fraction.size() != n ||
      c.lit_area_error_bound.size() != n || c.faces_light.size() != n)
    throw std::runtime_error("series columns: their shape is not the series'");
  for (std::size_t k = 0; k < c.instants.size(); ++k) {
    if (c.instants[k] >= full.instants) throw std::runtime_error("series columns: instant out of range");
    for (std::size_t r = 0; r < c.rows; ++r) {
      const std::size_t to = full.at(r, c.instants[k]), from = k * c.rows + r;
      full.lit_area[to] = c.lit_area[from];
      full.lit_fraction[to] = c.lit_fraction[from];
      full.lit_area_error_bound[to] = c.lit_area_error_bound[from];
      full.faces_light[to] = c.faces_light[from];
    }
  }
  full.stats += c.stats;
}

std::string encode_columns(const SeriesColumns& c) {
  Writer w;
  w.put(static_cast<std::uint64_t>(c.rows));
  w.put_all(c.instants);
  w.put_all(c.lit_area);
  w.put_all(c.lit_fraction);
  w.put_all(c.lit_area_error_bound);
  w.put_all(c.faces_light);
  put_stats(w, c.stats);
  return std::move(w.out);
}

SeriesColumns decode_columns(const std::string& bytes) {
  Reader r(bytes);
  SeriesColumns c;
  c.rows = r.get<std::uint64_t>();
  c.instants = r.get_all<std::uint64_t>();
  c.lit_area = r.get_all<double>();
  c.lit_fraction = r.get_all<double>();
  c.lit_area_error_bound = r.get_all<double>();
  c.faces_light = r.get_all<unsigned char>();
  c.stats = get_stats(r);
  if (!r.at_end()) throw std::runtime_error("series message: trailing bytes");
  return c;
}

std::string encode_map(const shadow::SunHoursMap& map) {
  Writer w;
  w.put(map.total_hours);
  w.put(static_cast<std::uint64_t>(map.regions));
  w.put(static_cast<std::uint64_t>(map.cells.size()));
  for (const shadow::SunHoursCell& c : map.cells) {
    w.put(static_cast<std::uint64_t>(c.face_id));
    w.put(c.sun_hours);
    w.put(static_cast<std::uint64_t>(c.region_id));
    w.put(c.area);
    w.put(static_cast<std::uint64_t>(c.polygon.size()));
    for (const glm::dvec3& p : c.polygon) put_vec3(w, p);
  }
  w.put(static_cast<std::uint64_t>(map.faces.size()));
  for (const shadow::SunHoursFace& f : map.faces) {
    w.put(static_cast<std::uint64_t>(f.face_id));
    w.put(f.area);
    w.put(f.hour_area);
    w.put(f.dropped_area);
    w.put(static_cast<std::uint64_t>(f.instants_lit));
  }
  return std::move(w.out);
}

shadow::SunHoursMap decode_map(const std::string& bytes) {
  Reader r(bytes);
  shadow::SunHoursMap map;
  map.total_hours = r.get<double>();
  map.regions = r.get<std::uint64_t>();
  const auto cells = r.get<std::uint64_t>();
  for (std::uint64_t i = 0; i < cells; ++i) {
    shadow::SunHoursCell c;
    c.face_id = r.get<std::uint64_t>();
    c.sun_hours = r.get<double>();
    c.region_id = r.get<std::uint64_t>();
    c.area = r.get<double>();
    const auto points = r.get<std::uint64_t>();
    for (std::uint64_t p = 0; p < points; ++p) c.polygon.push_back(get_vec3(r));
    map.cells.push_back(std::move(c));
  }
  const auto faces = r.get<std::uint64_t>();
  for (std::uint64_t i = 0; i < faces; ++i) {
    shadow::SunHoursFace f;
    f.face_id = r.get<std::uint64_t>();
    f.area = r.get<double>();
    f.hour_area = r.get<double>();
    f.dropped_area = r.get<double>();
    f.instants_lit = r.get<std::uint64_t>();
    map.faces.push_back(f);
  }
  if (!r.at_end()) throw std::runtime_error("sun-hours map message: trailing bytes");
  return map;
}

shadow::SunHoursMap merge_maps(const std::vector<shadow::SunHoursMap>& parts) {
  shadow::SunHoursMap map;
  std::size_t offset = 0;
  for (const shadow::SunHoursMap& part : parts) {
    for (shadow::SunHoursCell c : part.cells) {
      c.region_id += offset;
      map.cells.push_back(std::move(c));
    }
    map.faces.insert(map.faces.end(), part.faces.begin(), part.faces.end());
    offset += part.regions;
    // Every part sums the same instants' hours (compute_sun_hours_map sums them whatever the faces).
    map.total_hours = part.total_hours;
  }
  map.regions = offset;
  return map;
}

std::uint64_t series_digest(const shadow::Scene& scene, const shadow::SunSeries& suns, const shadow::SeriesOptions& options) {
  Fnv d;
  d.text(shadow::version());
  d.value(static_cast<int>(options.arithmetic));
  // The tile threshold of the arithmetic, when not the default (the digests of default runs stay
  // as they were): fast tiles change lit areas within their bounds, and either changes the stats.
  const bool fast = options.arithmetic == shadow::Arithmetic::Fast;
  const shadow::SeriesOptions defaults;
  const std::size_t threshold = fast ? options.fast_tile_casters : options.tile_casters;
  if (threshold != (fast ? defaults.fast_tile_casters : defaults.tile_casters)) {
    d.text("tile_casters");
    d.value(static_cast<std::uint64_t>(threshold));
  }
  d.value(static_cast<std::uint64_t>(scene.faces.size()));
  for (const shadow::Face& f : scene.faces) {
    d.value(static_cast<std::uint64_t>(f.mesh));
    d.value(static_cast<unsigned char>(f.degenerate));
    d.value(static_cast<unsigned char>(f.mesh < scene.meshes.size() && scene.meshes[f.mesh].receiver));
    d.value(static_cast<std::uint64_t>(f.vertices.size()));
    for (const glm::dvec3& v : f.vertices) {
      d.value(v.x);
      d.value(v.y);
      d.value(v.z);
    }
  }
  d.value(static_cast<std::uint64_t>(suns.lights.size()));
  for (std::size_t i = 0; i < suns.lights.size(); ++i) {
    const shadow::Light& l = suns.lights[i];
    d.value(static_cast<int>(l.type));
    d.value(l.to_light.x);
    d.value(l.to_light.y);
    d.value(l.to_light.z);
    d.value(l.angular_diameter);
    d.value(static_cast<std::int64_t>(suns.times[i]));
  }
  return d.h;
}

Checkpoint Checkpoint::create(const fs::path& path, std::uint64_t digest, std::size_t rows, std::size_t instants,
                              const std::string& started_utc) {
  Writer w;
  w.out.append(kMagic, sizeof kMagic);
  w.put(kFormat);
  w.put(digest);
  w.put(static_cast<std::uint64_t>(rows));
  w.put(static_cast<std::uint64_t>(instants));
  w.text(started_utc);
  Fnv check;
  check.bytes(w.out.data(), w.out.size());
  w.put(check.h);
  // The header under a temporary name, renamed into place: a checkpoint is whole or absent.
  const fs::path temp = path.parent_path() / ("." + path.filename().string() + ".tmp-" + std::to_string(::getpid()));
  std::error_code ignored;
  fs::remove(temp, ignored);
  std::FILE* file = std::fopen(temp.c_str(), "wb");
  if (file == nullptr) throw shadow::OutputError(path.string() + ": " + errno_text(errno));
  try {
    write_durably(file, w.out, path);
  } catch (...) {
    std::fclose(file);
    fs::remove(temp, ignored);
    throw;
  }
  std::fclose(file);
  std::error_code ec;
  fs::rename(temp, path, ec);
  if (ec) {
    fs::remove(temp, ignored);
    throw shadow::OutputError(path.string() + ": cannot move the checkpoint into place: " + ec.message());
  }
  return reopen(path, w.out.size());
}

Checkpoint::Contents Checkpoint::read(const fs::path& path, std::uint64_t digest, std::size_t rows,
                                      std::size_t instants) {
  Contents out;
  Contents read = Checkpoint::read(path, digest, rows, instants,
                                   [&](const SeriesColumns& c) { out.records.push_back(c); });
  read.records = std::move(out.records);
  return read;
}

Checkpoint::Contents Checkpoint::read(const fs::path& path, std::uint64_t digest, std::size_t rows, std::size_t instants,
                                      const std::function<void(const SeriesColumns&)>& record) {
  // The rules of scene files: a regular file (a FIFO would block the read forever, a link to
  // /dev/zero fill the memory), and no longer than a checkpoint of this run can be: its header
  // and at most one record per instant, each with every row's columns. Read record by record:
  // only one is in memory at a time.
  constexpr std::uintmax_t kHeaderBytes = 4096, kRecordBytes = 256, kRowBytes = 3 * sizeof(double) + 1;
  const std::uintmax_t per_instant = kRecordBytes + kRowBytes * static_cast<std::uintmax_t>(rows);
  const std::uintmax_t limit = kHeaderBytes + per_instant * static_cast<std::uintmax_t>(instants);
  OpenedFile file = open_checked(path, limit,
                                 "the most a checkpoint of this run can hold: " + std::to_string(rows) +
                                     " receiving faces x " + std::to_string(instants) + " instants");
  const std::uintmax_t size = file.size;
  const std::string place = "";
  auto refuse = [&](const std::string& why) {
    throw shadow::InputError({path.string(), place}, why + "; remove it (or run without --resume) to start afresh");
  };
  // Up to `n` more bytes (fewer at the file's end).
  auto take = [&](std::size_t n) {
    std::string bytes(n, '\0');
    const std::size_t got = n == 0 ? 0 : std::fread(bytes.data(), 1, n, file.in.get());
    bytes.resize(got);
    return bytes;
  };
  Contents out;
  std::uint64_t at = 0;
  try {
    // The header: the fixed fields, then the start time's text and the checksum.
    constexpr std::size_t kFixed = sizeof kMagic + 4 + 3 * 8 + 8;
    std::string head = take(kFixed);
    if (head.size() < sizeof kMagic || std::memcmp(head.data(), kMagic, sizeof kMagic) != 0)
      refuse("not a shadow series checkpoint");
    if (head.size() < kFixed) refuse("its header is truncated");
    std::uint64_t text_length;
    std::memcpy(&text_length, head.data() + kFixed - 8, 8);
    if (text_length > kHeaderBytes) refuse("its header is damaged");
    head += take(static_cast<std::size_t>(text_length) + 8);
    Reader r(head);
    for (std::size_t i = 0; i < sizeof kMagic; ++i) r.get<char>();
    if (r.get<std::uint32_t>() != kFormat) refuse("a checkpoint of another format version");
    const auto their_digest = r.get<std::uint64_t>();
    const auto their_rows = r.get<std::uint64_t>();
    const auto their_instants = r.get<std::uint64_t>();
    out.started_utc = r.text();
    at = sizeof kMagic + 4 + 3 * 8 + 8 + out.started_utc.size();
    Fnv check;
    check.bytes(head.data(), at);
    if (r.get<std::uint64_t>() != check.h) refuse("its header is damaged");
    at += 8;
    if (their_digest != digest || their_rows != rows || their_instants != instants)
      refuse("written for another scene or other options (" + std::to_string(their_rows) + " receiving faces x " +
             std::to_string(their_instants) + " instants, digest " + std::to_string(their_digest) +
             "; this run: " + std::to_string(rows) + " x " + std::to_string(instants) + ", digest " +
             std::to_string(digest) + ")");
  } catch (const std::runtime_error& e) {
    if (dynamic_cast<const shadow::InputError*>(&e) != nullptr) throw;
    refuse("its header is truncated");
  }
  // Records until the first that is incomplete or fails its checksum: a kill mid-write.
  while (at < size) {
    if (size - at < 4 + 8) break;
    const std::string frame = take(12);
    if (frame.size() < 12) break;
    std::uint32_t tag;
    std::uint64_t length;
    std::memcpy(&tag, frame.data(), 4);
    std::memcpy(&length, frame.data() + 4, 8);
    if (tag != kRecord || length > size - at - 12 || size - at - 12 - length < 8) break;
    const std::string payload = take(static_cast<std::size_t>(length));
    const std::string tail = take(8);
    if (payload.size() != length || tail.size() != 8) break;
    std::uint64_t sum;
    std::memcpy(&sum, tail.data(), 8);
    Fnv check;
    check.bytes(payload.data(), payload.size());
    if (check.h != sum) break;
    try {
      const SeriesColumns c = decode_columns(payload);
      bool fits = c.rows == rows;
      for (std::uint64_t i : c.instants) fits = fits && i < instants;
      if (!fits) break;
      record(c);
    } catch (const std::runtime_error& e) {
      if (dynamic_cast<const shadow::InputError*>(&e) != nullptr ||
          dynamic_cast<const shadow::OutputError*>(&e) != nullptr)
        throw;  // not the record's fault: the consumer's
      break;
    }
    at += 12 + length + 8;
  }
  out.valid_bytes = at;
  out.torn = at < size;
  return out;
}

Checkpoint Checkpoint::reopen(const fs::path& path, std::uint64_t valid_bytes) {
  if (::truncate(path.c_str(), static_cast<off_t>(valid_bytes)) != 0)
    throw shadow::OutputError(path.string() + ": cannot cut the checkpoint's torn end: " + std::strerror(errno));
  std::FILE* file = std::fopen(path.c_str(), "ab");
  if (file == nullptr) throw shadow::OutputError(path.string() + ": " + errno_text(errno));
  return Checkpoint(path, file);
}

Checkpoint::Checkpoint(Checkpoint&& other) noexcept : path_(std::move(other.path_)), file_(other.file_) {
  other.file_ = nullptr;
}

Checkpoint::~Checkpoint() {
  if (file_ != nullptr) std::fclose(file_);
}

void Checkpoint::append(const SeriesColumns& columns) {
  const std::string payload = encode_columns(columns);
  Fnv check;
  check.bytes(payload.data(), payload.size());
  Writer w;
  w.put(kRecord);
  w.put(static_cast<std::uint64_t>(payload.size()));
  w.out += payload;
  w.put(check.h);
  write_durably(file_, w.out, path_);
}

void Checkpoint::remove() {
  if (file_ != nullptr) std::fclose(file_);
  file_ = nullptr;
  std::error_code ignored;
  fs::remove(path_, ignored);
}

}  // namespace shadow::jobs
