// SPDX-License-Identifier: GPL-3.0-or-later
// The .vtp files whose zlib blocks libdeflate makes, on several threads before VTK writes them
// (writers/vtk_zlib_blocks.hpp), against VTK's own vtkXMLPolyDataWriter with the settings the
// library uses: once every block is inflated (by zlib), the same XML and the same arrays, block
// for block; the same bytes at 1, 2 and 4 threads; every block the writer asked for found among
// those compressed ahead; and every array read back by vtkXMLPolyDataReader.
#include "writers/vtk_datasets.hpp"
#include "writers/vtk_zlib_blocks.hpp"
#include "writers/vtp_writer.hpp"

#include <gtest/gtest.h>

#include <vtkBitArray.h>
#include <vtkCallbackCommand.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSOADataArrayTemplate.h>
#include <vtkStringArray.h>
#include <vtkTypeInt32Array.h>
#include <vtkTypeInt64Array.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtk_zlib.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace fs = std::filesystem;
using shadow::detail::ZLibBlockStats;

namespace {

fs::path temp_dir() {
  const fs::path dir = fs::temp_directory_path() / ("libshadow-test_vtp_zlib-" + std::to_string(getpid()));
  fs::create_directories(dir);
  return dir;
}

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The file as VTK writes it with vtp_writer's settings and VTK's own zlib compressor.
std::string vtk_bytes(vtkPolyData* poly, const fs::path& path) {
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetFileName(path.string().c_str());
  writer->SetInputData(poly);
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff();
  writer->SetCompressorTypeToZLib();
  writer->SetCompressionLevel(shadow::detail::kVtpZlibLevel);
  writer->SetHeaderTypeToUInt64();
  writer->SetIdTypeToInt64();
  EXPECT_EQ(writer->Write(), 1);
  return read_bytes(path);
}

/// A .vtp file (appended raw data, UInt64 headers, zlib) as the arrays it holds: its XML with
/// the arrays' offsets left out (they follow from the compressed sizes), and for each array its
/// header (blocks, block size, last block's size) and its bytes, every block inflated by zlib.
struct Inflated {
  std::string xml;
  std::vector<std::array<std::uint64_t, 3>> headers;
  std::vector<std::string> arrays;
  bool operator==(const Inflated& o) const { return xml == o.xml && headers == o.headers && arrays == o.arrays; }
};

Inflated inflate_file(const std::string& file) {
  Inflated out;
  const std::string marker = "<AppendedData encoding=\"raw\">";
  const std::size_t appended = file.find(marker);
  if (appended == std::string::npos) {
    out.xml = file;
    return out;
  }
  const std::size_t data = file.find('_', appended) + 1;
  // The XML without the offsets' values (taken out here), nor the spaces that pad them to the
  // room the writer kept.
  std::vector<std::uint64_t> offsets;
  out.xml = file.substr(0, data);
  for (std::size_t at = 0; (at = out.xml.find(" offset=\"", at)) != std::string::npos;) {
    at += 9;
    const std::size_t digits = out.xml.find('"', at) - at;
    offsets.push_back(std::stoull(out.xml.substr(at, digits)));
    out.xml.erase(at, digits);
    const std::size_t padding = at + 1;
    out.xml.erase(padding, out.xml.find_first_not_of(' ', padding) - padding);
  }
  std::sort(offsets.begin(), offsets.end());
  offsets.erase(std::unique(offsets.begin(), offsets.end()), offsets.end());
  auto word = [&](std::size_t at) {
    std::uint64_t w = 0;
    std::memcpy(&w, file.data() + at, sizeof w);
    return w;
  };
  for (const std::uint64_t offset : offsets) {
    std::size_t at = data + offset;
    const std::array<std::uint64_t, 3> header{word(at), word(at + 8), word(at + 16)};
    out.headers.push_back(header);
    std::size_t block_at = at + 24 + 8 * header[0];
    std::string bytes;
    for (std::uint64_t b = 0; b < header[0]; ++b) {
      const std::uint64_t compressed = word(at + 24 + 8 * b);
      const std::uint64_t size = b + 1 == header[0] && header[2] != 0 ? header[2] : header[1];
      std::string block(size, '\0');
      uLongf inflated = static_cast<uLongf>(size);
      uLong consumed = static_cast<uLong>(compressed);
      EXPECT_EQ(uncompress2(reinterpret_cast<Bytef*>(block.data()), &inflated,
                            reinterpret_cast<const Bytef*>(file.data() + block_at), &consumed),
                Z_OK)
          << "array at " << offset << ", block " << b;
      EXPECT_EQ(inflated, size) << "array at " << offset << ", block " << b;
      EXPECT_EQ(consumed, compressed) << "array at " << offset << ", block " << b << ": the size in its header";
      bytes += block;
      block_at += compressed;
    }
    out.arrays.push_back(std::move(bytes));
  }
  return out;
}

/// A string of `length` bytes, some of them not ASCII (or not UTF-8).
std::string text(std::mt19937_64& random, std::size_t length) {
  std::string s(length, 'a');
  for (char& c : s) c = static_cast<char>(1 + random() % 255);  // no zero: the writer ends strings with one
  return s;
}

/// Polygons (quads), vertices and lines with cell, point and field arrays of several types,
/// strings of many lengths (empty ones, and with `long_string` one longer than two blocks).
vtkSmartPointer<vtkPolyData> make_polydata(vtkIdType quads, vtkIdType verts, vtkIdType lines,
                                           std::uint64_t seed, bool long_string) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> coordinate(-1e4, 1e4);
  const vtkIdType point_count = 4 * quads + verts + 2 * lines;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(point_count);
  for (vtkIdType p = 0; p < point_count; ++p)
    points->SetPoint(p, coordinate(random), coordinate(random), std::floor(coordinate(random)));
  auto cells = [](vtkIdType count, vtkIdType size, vtkIdType first) {
    vtkNew<vtkCellArray> array;
    for (vtkIdType c = 0; c < count; ++c) {
      array->InsertNextCell(static_cast<int>(size));
      for (vtkIdType i = 0; i < size; ++i) array->InsertCellPoint(first + c * size + i);
    }
    return vtkSmartPointer<vtkCellArray>(array);
  };
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetVerts(cells(verts, 1, 4 * quads));
  poly->SetLines(cells(lines, 2, 4 * quads + verts));
  poly->SetPolys(cells(quads, 4, 0));

  const vtkIdType cell_count = quads + verts + lines;
  vtkNew<vtkTypeInt32Array> lit;
  lit->SetName("lit");
  vtkNew<vtkTypeInt64Array> face_id;
  face_id->SetName("face_id");
  vtkNew<vtkDoubleArray> area;
  area->SetName("area");
  vtkNew<vtkDoubleArray> normal;
  normal->SetName("normal");
  normal->SetNumberOfComponents(3);
  vtkNew<vtkStringArray> name;
  name->SetName("name");
  lit->SetNumberOfValues(cell_count);
  face_id->SetNumberOfValues(cell_count);
  area->SetNumberOfValues(cell_count);
  normal->SetNumberOfTuples(cell_count);
  name->SetNumberOfValues(cell_count);
  for (vtkIdType c = 0; c < cell_count; ++c) {
    lit->SetValue(c, static_cast<std::int32_t>(random() % 3));
    face_id->SetValue(c, static_cast<std::int64_t>(c * 7 + 3));
    area->SetValue(c, c % 5 == 0 ? std::nan("") : coordinate(random) / 3.0);
    normal->SetTuple3(c, coordinate(random), -0.0, 1.0 / (1.0 + static_cast<double>(c)));
    name->SetValue(c, c % 4 == 0 ? std::string() : text(random, random() % 90));
  }
  if (long_string && cell_count > 1) name->SetValue(1, text(random, 70000));
  poly->GetCellData()->AddArray(lit);
  poly->GetCellData()->AddArray(face_id);
  poly->GetCellData()->AddArray(area);
  poly->GetCellData()->AddArray(normal);
  poly->GetCellData()->AddArray(name);

  vtkNew<vtkDoubleArray> irradiance;
  irradiance->SetName("irradiance");
  irradiance->SetNumberOfValues(point_count);
  vtkNew<vtkFloatArray> single;
  single->SetName("single");
  single->SetNumberOfValues(point_count);
  for (vtkIdType p = 0; p < point_count; ++p) {
    irradiance->SetValue(p, coordinate(random));
    single->SetValue(p, static_cast<float>(coordinate(random)));
  }
  poly->GetPointData()->AddArray(irradiance);
  poly->GetPointData()->AddArray(single);

  vtkNew<vtkDoubleArray> origin;
  origin->SetName("origin");
  origin->SetNumberOfComponents(3);
  origin->InsertNextTuple3(85000.5, 446000.25, -3.0);
  vtkNew<vtkStringArray> notes;
  notes->SetName("notes");
  notes->InsertNextValue("made by a test");
  notes->InsertNextValue("");
  poly->GetFieldData()->AddArray(origin);
  poly->GetFieldData()->AddArray(notes);
  return poly;
}

/// The number of zlib blocks of 32,768 bytes VTK makes of `poly`, counted from the arrays' sizes
/// (strings: each with a terminating zero; cells: connectivity and offsets without the first).
std::size_t expected_blocks(vtkPolyData* poly) {
  auto blocks = [](std::size_t bytes) { return (bytes + 32767) / 32768; };
  std::size_t count = 0;
  for (vtkFieldData* group : {poly->GetFieldData(), static_cast<vtkFieldData*>(poly->GetPointData()),
                              static_cast<vtkFieldData*>(poly->GetCellData())}) {
    for (int i = 0; i < group->GetNumberOfArrays(); ++i) {
      std::size_t bytes = 0;
      if (auto* strings = vtkStringArray::SafeDownCast(group->GetAbstractArray(i))) {
        for (vtkIdType s = 0; s < strings->GetNumberOfValues(); ++s) bytes += strings->GetValue(s).size() + 1;
      } else if (auto* bits = vtkBitArray::SafeDownCast(group->GetAbstractArray(i))) {
        bytes = static_cast<std::size_t>(bits->GetNumberOfValues() + 7) / 8;
      } else {
        auto* numbers = group->GetArray(i);
        bytes = static_cast<std::size_t>(numbers->GetNumberOfValues() * numbers->GetDataTypeSize());
      }
      count += blocks(bytes);
    }
  }
  if (poly->GetPoints() != nullptr) count += blocks(static_cast<std::size_t>(poly->GetNumberOfPoints()) * 24);
  for (vtkCellArray* cells : {poly->GetVerts(), poly->GetLines(), poly->GetStrips(), poly->GetPolys()}) {
    count += blocks(static_cast<std::size_t>(cells->GetNumberOfConnectivityIds()) * 8);
    count += blocks(static_cast<std::size_t>(cells->GetNumberOfCells()) * 8);
  }
  return count;
}

void expect_same_array(vtkAbstractArray* expected, vtkAbstractArray* read, const std::string& where) {
  ASSERT_NE(read, nullptr) << where;
  EXPECT_EQ(read->GetDataType(), expected->GetDataType()) << where;
  EXPECT_EQ(read->GetNumberOfComponents(), expected->GetNumberOfComponents()) << where;
  ASSERT_EQ(read->GetNumberOfValues(), expected->GetNumberOfValues()) << where;
  if (auto* strings = vtkStringArray::SafeDownCast(expected)) {
    auto* read_strings = vtkStringArray::SafeDownCast(read);
    ASSERT_NE(read_strings, nullptr) << where;
    for (vtkIdType i = 0; i < strings->GetNumberOfValues(); ++i)
      ASSERT_EQ(read_strings->GetValue(i), strings->GetValue(i)) << where << " value " << i;
    return;
  }
  auto* numbers = vtkDataArray::SafeDownCast(expected);
  auto* read_numbers = vtkDataArray::SafeDownCast(read);
  ASSERT_NE(read_numbers, nullptr) << where;
  for (vtkIdType t = 0; t < numbers->GetNumberOfTuples(); ++t) {
    for (int c = 0; c < numbers->GetNumberOfComponents(); ++c) {
      const double a = numbers->GetComponent(t, c), b = read_numbers->GetComponent(t, c);
      // Bit for bit (NaN too): the file holds the values' bytes.
      ASSERT_EQ(std::memcmp(&a, &b, sizeof a), 0) << where << " tuple " << t << " component " << c;
    }
  }
}

/// vtkXMLPolyDataReader gives back every point, cell and array of `poly` from `path`.
void expect_reads_back(vtkPolyData* poly, const fs::path& path) {
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(path.string().c_str());
  reader->Update();
  vtkPolyData* read = reader->GetOutput();
  ASSERT_EQ(read->GetNumberOfPoints(), poly->GetNumberOfPoints());
  if (poly->GetNumberOfPoints() > 0)
    expect_same_array(poly->GetPoints()->GetData(), read->GetPoints()->GetData(), "points");
  const std::pair<vtkCellArray*, vtkCellArray*> cells[] = {{poly->GetVerts(), read->GetVerts()},
                                                           {poly->GetLines(), read->GetLines()},
                                                           {poly->GetPolys(), read->GetPolys()}};
  for (const auto& [expected, got] : cells) {
    ASSERT_EQ(got->GetNumberOfCells(), expected->GetNumberOfCells());
    if (expected->GetNumberOfCells() == 0) continue;
    expect_same_array(expected->GetOffsetsArray(), got->GetOffsetsArray(), "offsets");
    expect_same_array(expected->GetConnectivityArray(), got->GetConnectivityArray(), "connectivity");
  }
  const std::pair<vtkFieldData*, vtkFieldData*> groups[] = {{poly->GetPointData(), read->GetPointData()},
                                                            {poly->GetCellData(), read->GetCellData()},
                                                            {poly->GetFieldData(), read->GetFieldData()}};
  for (const auto& [expected, got] : groups) {
    ASSERT_EQ(got->GetNumberOfArrays(), expected->GetNumberOfArrays());
    for (int i = 0; i < expected->GetNumberOfArrays(); ++i) {
      vtkAbstractArray* array = expected->GetAbstractArray(i);
      expect_same_array(array, got->GetAbstractArray(array->GetName()), array->GetName());
    }
  }
}

/// Writes the dataset that `make` makes at 1, 2 and 4 threads: VTK's XML and arrays each time
/// (inflated), the same bytes at every thread count, and at 2 and 4 threads every block comes
/// from those compressed ahead. Returns how many blocks the writer asked for. A fresh dataset
/// for every file: writing one caches the arrays' ranges in their information, which the next
/// writer of the same arrays writes into the file too.
std::size_t expect_vtk_arrays(const std::function<vtkSmartPointer<vtkPolyData>()>& make, const std::string& label) {
  const fs::path dir = temp_dir();
  const std::string vtk_file = vtk_bytes(make(), dir / "vtk.vtp");
  EXPECT_NE(vtk_file.find("compressor=\"vtkZLibDataCompressor\""), std::string::npos) << label;
  const Inflated reference = inflate_file(vtk_file);
  std::string one_thread;
  std::size_t blocks = 0;
  for (const unsigned threads : {1u, 2u, 4u}) {
    const fs::path path = dir / ("threads" + std::to_string(threads) + ".vtp");
    ZLibBlockStats stats;
    shadow::detail::VtpWriteOptions options;
    options.threads = threads;
    options.stats = &stats;
    shadow::detail::write_polydata(make(), path, {}, options);
    const std::string file = read_bytes(path);
    EXPECT_TRUE(inflate_file(file) == reference) << label << ", " << threads << " threads";
    if (threads == 1) {
      one_thread = file;
      EXPECT_EQ(stats.foreseen, 0u) << label;
      EXPECT_EQ(stats.served, 0u) << label;
      blocks = stats.direct;
    } else {
      EXPECT_TRUE(file == one_thread) << label << ", " << threads << " threads: not one thread's bytes";
      EXPECT_EQ(stats.direct, 0u) << label << ", " << threads << " threads: blocks not foreseen";
      EXPECT_EQ(stats.served, stats.foreseen) << label << ", " << threads << " threads";
      EXPECT_EQ(stats.served, blocks) << label << ", " << threads << " threads";
      EXPECT_EQ(stats.windows, blocks == 0 ? 0u : 1u) << label << ": one window of 32 MiB";
    }
    // (A dataset without points has no Points element: the reader refuses it.)
    if (auto poly = make(); poly->GetPoints() != nullptr) expect_reads_back(poly, path);
  }
  fs::remove_all(dir);
  return blocks;
}

}  // namespace

/// A maker of make_polydata(quads, verts, lines, seed, long_string) datasets.
std::function<vtkSmartPointer<vtkPolyData>()> maker(vtkIdType quads, vtkIdType verts, vtkIdType lines,
                                                    std::uint64_t seed, bool long_string) {
  return [=] { return make_polydata(quads, verts, lines, seed, long_string); };
}

TEST(VtpZlib, EmptyArraysGiveVtksArrays) {
  // The two field arrays hold a block each; every other array is empty.
  EXPECT_EQ(expect_vtk_arrays(maker(0, 0, 0, 1, false), "empty"), 2u);
  EXPECT_EQ(expected_blocks(make_polydata(0, 0, 0, 1, false)), 2u);
  EXPECT_EQ(expect_vtk_arrays([] { return vtkSmartPointer<vtkPolyData>::New(); }, "no points"), 0u);
}

TEST(VtpZlib, OneCellGivesVtksArrays) {
  EXPECT_EQ(expect_vtk_arrays(maker(1, 0, 0, 2, false), "one quad"), expected_blocks(make_polydata(1, 0, 0, 2, false)));
}

TEST(VtpZlib, ArraysOfExactlyOneBlockGiveVtksArrays) {
  // 4,096 cells: their Float64 and Int64 arrays are 32,768 bytes, VTK's block size exactly; the
  // offsets too. The quads' 16,384 points are 12 blocks of Float64 triples exactly.
  EXPECT_EQ(expect_vtk_arrays(maker(4096, 0, 0, 3, false), "one block"),
            expected_blocks(make_polydata(4096, 0, 0, 3, false)));
  // One more cell: a second, short block in each array of cells.
  EXPECT_EQ(expect_vtk_arrays(maker(4097, 0, 0, 4, false), "one block and one word"),
            expected_blocks(make_polydata(4097, 0, 0, 4, false)));
}

TEST(VtpZlib, ManyBlocksAndEveryKindOfCellGiveVtksArrays) {
  // 12,000 quads, 1,000 vertices and 1,000 lines; a string longer than two blocks.
  const std::size_t blocks = expect_vtk_arrays(maker(12000, 1000, 1000, 5, true), "many blocks");
  EXPECT_EQ(blocks, expected_blocks(make_polydata(12000, 1000, 1000, 5, true)));
  EXPECT_GT(blocks, 100u);
}

TEST(VtpZlib, StringArraysPackedInSeveralBlocksGiveVtksArrays) {
  // 40,000 cells: the cells' strings (a quarter of them empty, one longer than two zlib blocks)
  // are packed for the compressor in three blocks of values on every thread (packed_strings).
  const std::size_t blocks = expect_vtk_arrays(maker(40000, 0, 0, 6, true), "strings in several blocks");
  EXPECT_EQ(blocks, expected_blocks(make_polydata(40000, 0, 0, 6, true)));
}

TEST(VtpZlib, BlocksThatHardlyCompressGiveTheSameBytesOnEveryThreadCount) {
  // Random doubles in short arrays and in the last, short block of longer ones: their streams
  // come within a few bytes of zlib's bound, the room the writer gives a block. Compressed when
  // asked (one thread) and ahead (two, three) alike: libdeflate's bytes wherever they fit that
  // room, zlib's where they do not, never one on one thread and the other on two.
  for (const vtkIdType values : {vtkIdType{1}, vtkIdType{8}, vtkIdType{16}, vtkIdType{50}, vtkIdType{128},
                                 vtkIdType{3000}, vtkIdType{4096 + 9}}) {
    std::mt19937_64 random(static_cast<std::uint64_t>(values));
    auto make = [&, seed = random()] {
      std::mt19937_64 bits(seed);
      auto poly = make_polydata(20, 0, 0, 10, false);
      vtkNew<vtkDoubleArray> noise;
      noise->SetName("noise");
      noise->SetNumberOfValues(values);
      for (vtkIdType i = 0; i < values; ++i) {
        const std::uint64_t word = bits() & ~(std::uint64_t{1} << 62);  // (never infinite or NaN)
        double x;
        std::memcpy(&x, &word, sizeof x);  // 63 random bits: nothing for deflate to find
        noise->SetValue(i, x);
      }
      poly->GetFieldData()->AddArray(noise);
      return poly;
    };
    const std::string label = std::to_string(values) + " random doubles";
    expect_vtk_arrays(make, label);
    const fs::path dir = temp_dir();
    shadow::detail::write_polydata(make(), dir / "one.vtp");
    for (const unsigned threads : {2u, 3u}) {
      shadow::detail::VtpWriteOptions options;
      options.threads = threads;
      shadow::detail::write_polydata(make(), dir / "more.vtp", {}, options);
      EXPECT_TRUE(read_bytes(dir / "more.vtp") == read_bytes(dir / "one.vtp")) << label << ", " << threads << " threads";
    }
    fs::remove_all(dir);
  }
}

TEST(VtpZlib, ArraysTheWriterCopiesAreCompressedWhenAskedWithTheSameBytes) {
  // A bit array and an array of structures of arrays: the writer copies them into blocks of its
  // own; those are compressed when asked (not ahead), the arrays are still VTK's.
  auto make = [] {
    auto poly = make_polydata(3000, 0, 0, 6, false);
    vtkNew<vtkBitArray> bits;
    bits->SetName("bits");
    vtkNew<vtkSOADataArrayTemplate<double>> soa;
    soa->SetName("soa");
    soa->SetNumberOfComponents(2);
    soa->SetNumberOfTuples(3000);
    for (vtkIdType c = 0; c < 3000; ++c) {
      bits->InsertNextValue(static_cast<int>(c % 3 == 0));
      soa->SetTuple2(c, 0.5 * static_cast<double>(c), -static_cast<double>(c));
    }
    poly->GetCellData()->AddArray(bits);
    poly->GetCellData()->AddArray(soa);
    return poly;
  };
  const fs::path dir = temp_dir();
  const Inflated reference = inflate_file(vtk_bytes(make(), dir / "vtk.vtp"));
  shadow::detail::write_polydata(make(), dir / "one.vtp");
  ZLibBlockStats stats;
  shadow::detail::VtpWriteOptions options;
  options.threads = 2;
  options.stats = &stats;
  shadow::detail::write_polydata(make(), dir / "two.vtp", {}, options);
  EXPECT_TRUE(inflate_file(read_bytes(dir / "two.vtp")) == reference);
  EXPECT_TRUE(read_bytes(dir / "two.vtp") == read_bytes(dir / "one.vtp"));
  expect_reads_back(make(), dir / "two.vtp");
  EXPECT_EQ(stats.direct, 3u);  // bits: 375 bytes, one block; soa: 48,000 bytes, two blocks
  EXPECT_EQ(stats.served, stats.foreseen);
  EXPECT_EQ(stats.served + stats.direct, expected_blocks(make()));
  fs::remove_all(dir);
}

TEST(VtpZlib, FacesOfAResultGiveVtksArrays) {
  const std::function<vtkSmartPointer<vtkPolyData>()> make = [] {
  // faces.vtp's dataset for 5,000 faces with names, kinds and sources, two lights.
  shadow::Scene scene;
  scene.meshes = {shadow::Mesh{"blocks", "blocks.obj", 0, 0, true}};
  for (std::size_t f = 0; f < 5000; ++f) {
    shadow::Face face;
    const double x = 3.0 * static_cast<double>(f) + 1.0 / 3.0;
    face.vertices = {{x, 0.1, 0.0}, {x + 2.0, 0.1, 0.0}, {x + 2.0, 0.1, 3.0}, {x, 0.1, 3.0}};
    face.source = {"blocks.obj", "line " + std::to_string(f + 1)};
    if (f % 5 == 0) face.name = "wall " + std::to_string(f / 5);
    if (f % 3 == 0) face.kind = "WallSurface";
    scene.faces.push_back(face);
  }
  for (const char* name : {"sun", "lamp"}) {
    shadow::Light light;
    light.name = name;
    light.to_light = {0.4, 0.3, 0.85};
    scene.lights.push_back(light);
  }
  shadow::ShadowResult result;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    for (std::size_t l = 0; l < 2; ++l) {
      shadow::FaceLighting e;
      e.face_id = f;
      e.light_id = l;
      e.area = 6.0;
      e.lit_area = 6.0 * static_cast<double>((f * 7 + l) % 13) / 13.0;
      e.lit_fraction = e.lit_area / e.area;
      result.lighting.push_back(e);
    }
  }
  return shadow::detail::make_faces_polydata(scene, result);
  };
  EXPECT_EQ(expect_vtk_arrays(make, "faces"), expected_blocks(make()));
}

TEST(VtpZlib, FacesMadeOnSeveralThreadsAreTheSameDataset) {
  // 10,000 faces (three ranges of 4,096) of different shapes, names, kinds, sources and meshes,
  // one of them unknown: the dataset made on 2 and 4 threads, written on as many, is VTK's file
  // of the dataset made on one.
  shadow::Scene scene;
  scene.meshes = {shadow::Mesh{"blocks", "blocks.obj", 0, 0, true}, shadow::Mesh{"trees", "", 0, 0, false}};
  for (std::size_t f = 0; f < 10000; ++f) {
    shadow::Face face;
    const double x = 3.0 * static_cast<double>(f) + 1.0 / 3.0;
    face.vertices = {{x, 0.1, 0.0}, {x + 2.0, 0.1 * static_cast<double>(f % 7), 0.5}, {x + 2.0, 0.1, 3.0}};
    if (f % 4 == 1) face.vertices.push_back({x, 0.1, 3.0 + static_cast<double>(f % 3)});
    face.source = {"blocks.obj", "line " + std::to_string(f + 1)};
    if (f % 5 == 0) face.name = "wall " + std::to_string(f / 5);
    if (f % 3 == 0) face.kind = "WallSurface";
    face.mesh = f % 11 == 0 ? 1 : f % 13 == 0 ? 5 : 0;
    scene.faces.push_back(face);
  }
  shadow::Light sun;
  sun.name = "sun";
  sun.to_light = {0.4, 0.3, 0.85};
  scene.lights.push_back(sun);
  shadow::ShadowResult result;
  for (std::size_t f = 0; f < scene.faces.size(); f += 2) {
    shadow::FaceLighting e;
    e.face_id = f;
    e.area = 1.0 + static_cast<double>(f);
    e.lit_area = e.area / 3.0;
    e.lit_fraction = 1.0 / 3.0;
    result.lighting.push_back(e);
  }
  const fs::path dir = temp_dir();
  const Inflated reference = inflate_file(vtk_bytes(shadow::detail::make_faces_polydata(scene, result, 1), dir / "vtk.vtp"));
  shadow::detail::write_polydata(shadow::detail::make_faces_polydata(scene, result, 1), dir / "one.vtp");
  const std::string one_thread = read_bytes(dir / "one.vtp");
  EXPECT_TRUE(inflate_file(one_thread) == reference);
  for (const unsigned threads : {2u, 4u}) {
    shadow::detail::VtpWriteOptions options;
    options.threads = threads;
    shadow::detail::write_polydata(shadow::detail::make_faces_polydata(scene, result, threads), dir / "faces.vtp", {},
                                   options);
    EXPECT_TRUE(read_bytes(dir / "faces.vtp") == one_thread) << threads << " threads";
  }
  fs::remove_all(dir);
}

TEST(VtpZlib, SmallWindowsInTheWritersOrderGiveTheSameFile) {
  // Windows of three blocks: compressed in the order the writer asks for them, each window
  // holds three blocks of 32 KiB or more shorter ones (never a block asked out of order).
  const auto make = maker(12000, 1000, 1000, 7, true);
  const fs::path dir = temp_dir();
  shadow::detail::write_polydata(make(), dir / "one.vtp");
  const std::string reference = read_bytes(dir / "one.vtp");
  for (const unsigned threads : {2u, 3u}) {
    ZLibBlockStats stats;
    shadow::detail::VtpWriteOptions options;
    options.threads = threads;
    options.window_bytes = 3 * 32768;
    options.stats = &stats;
    shadow::detail::write_polydata(make(), dir / "windows.vtp", {}, options);
    EXPECT_TRUE(read_bytes(dir / "windows.vtp") == reference) << threads << " threads";
    EXPECT_EQ(stats.direct, 0u);
    EXPECT_EQ(stats.served, stats.foreseen);
    EXPECT_LE(stats.windows, (stats.foreseen + 2) / 3);
    EXPECT_GT(stats.windows, stats.foreseen / 6);
  }
  fs::remove_all(dir);
}

/// vtkZLibDataCompressor as it is when zlib runs out of memory: every block fails.
class FailingZLib : public vtkZLibDataCompressor {
 public:
  static FailingZLib* New() {
    auto* compressor = new FailingZLib;
    compressor->InitializeObjectBase();
    return compressor;
  }

 protected:
  size_t CompressBuffer(unsigned char const*, size_t, unsigned char*, size_t) override { return 0; }
};

TEST(VtpZlibDeathTest, VtksWriterCrashesWhenZlibFails) {
  // Why a failed block must never reach the writer: VTK 9.1's vtkXMLWriter uses the array
  // vtkDataCompressor::Compress returns without looking, and that is null when zlib failed.
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  // The "threadsafe" style runs this body again in a child process, which dies inside Write():
  // a directory named by the process id would be the child's own and stay behind, so this one
  // has a fixed name that the parent removes.
  const fs::path dir = fs::temp_directory_path() / "libshadow-test_vtp_zlib-death";
  fs::create_directories(dir);
  EXPECT_DEATH(
      {
        vtkNew<vtkXMLPolyDataWriter> writer;
        writer->SetFileName((dir / "crash.vtp").string().c_str());
        writer->SetInputData(make_polydata(10, 0, 0, 9, false));
        writer->SetDataModeToAppended();
        writer->EncodeAppendedDataOff();
        vtkNew<FailingZLib> failing;
        vtkNew<vtkCallbackCommand> quiet;  // the compressor's error message kept off stderr
        failing->AddObserver(vtkCommand::ErrorEvent, quiet);
        writer->SetCompressor(failing);
        writer->Write();
      },
      "");
  fs::remove_all(dir);
}

TEST(VtpZlib, ZlibOutOfMemoryIsBadAllocNeverACrash) {
  // The compressor out of memory on the threads (the first block of the first and of a later
  // window), on a block already compressed ahead, and on the writer's thread (one thread: VTK
  // 9.1 would dereference the null array a failed vtkZLibDataCompressor gives). Each time
  // std::bad_alloc after the writer has finished, and a file that is not the whole one.
  const auto make = maker(12000, 0, 0, 8, false);
  const fs::path dir = temp_dir();
  shadow::detail::write_polydata(make(), dir / "whole.vtp");
  const std::string whole = read_bytes(dir / "whole.vtp");
  struct Case {
    unsigned threads;
    std::size_t block;
  };
  for (const Case c : {Case{2, 0}, Case{2, 9}, Case{2, 10}, Case{1, 5}, Case{4, 30}}) {
    ZLibBlockStats stats;
    shadow::detail::VtpWriteOptions options;
    options.threads = c.threads;
    options.window_bytes = 3 * 32768;
    options.fail_at_block = c.block;
    options.stats = &stats;
    const fs::path path = dir / "failed.vtp";
    EXPECT_THROW(shadow::detail::write_polydata(make(), path, {}, options), std::bad_alloc)
        << c.threads << " threads, block " << c.block;
    EXPECT_FALSE(read_bytes(path) == whole);
    EXPECT_EQ(stats.served + stats.direct, c.block) << "the blocks before the failed one";
  }
  fs::remove_all(dir);
}
