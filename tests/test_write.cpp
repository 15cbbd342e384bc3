// STL writing: every fixture read -> written (binary and ASCII) -> read again gives the
// same arrays, bit for bit; chunking, sink failure, names, colours and refused meshes.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "stl_gen.h"
#include "stltopo.h"

#ifndef STLTOPO_FIXTURES
#error "STLTOPO_FIXTURES must name the tests/fixtures directory"
#endif

namespace {

using gen::sameArray;
using stltopo::Code;
using stltopo::Format;
using stltopo::Mesh;
using stltopo::WriteColors;
using stltopo::WriteOptions;

struct Output {
  std::string bytes;
  std::vector<size_t> chunks;
  size_t refuseAt = SIZE_MAX;  // the sink refuses its chunk number refuseAt
};

bool collect(void* user, const uint8_t* data, size_t size) {
  Output& o = *static_cast<Output*>(user);
  if (o.chunks.size() == o.refuseAt) return false;
  o.chunks.push_back(size);
  o.bytes.append(reinterpret_cast<const char*>(data), size);
  return true;
}

std::string write(const Mesh& m, const WriteOptions& o = {}) {
  Output out;
  stltopo::Status s = stltopo::writeStl(m, collect, &out, o);
  EXPECT_TRUE(s.ok()) << s.message;
  return out.bytes;
}

WriteOptions asciiOptions() {
  WriteOptions o;
  o.format = Format::Ascii;
  return o;
}

// The fixtures that read without an error (the others have nothing to write).
std::vector<std::string> readableFixtures() {
  std::vector<std::string> out;
  for (const std::string& path : gen::fixtureFiles()) {
    Mesh m;
    if (gen::read(gen::readFile(path), m).ok()) out.push_back(path);
  }
  return out;
}

// A name as ASCII carries it: cut before the first control byte other than tab, VT, FF.
std::string asciiName(const std::string& s) {
  size_t n = 0;
  while (n < s.size() && !(static_cast<unsigned char>(s[n]) < 0x20 && s[n] != '\t' && s[n] != '\v' && s[n] != '\f'))
    ++n;
  while (n > 0 && (s[n - 1] == ' ' || s[n - 1] == '\t' || s[n - 1] == '\v' || s[n - 1] == '\f')) --n;
  return s.substr(0, n);
}

// Float arrays equal bit for bit, except that NaN equals NaN (ASCII keeps no payload).
bool sameFloats(const stltopo::Array<float>& a, const stltopo::Array<float>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (std::isnan(a[i]) && std::isnan(b[i])) continue;
    if (std::memcmp(&a[i], &b[i], 4) != 0) return false;
  }
  return true;
}

// Everything reading gives, compared array by array. carriesColor: the output format
// holds attribute words and colours (binary); sameNames: the names are expected as is.
void expectSameMesh(const Mesh& a, const Mesh& b, bool carriesColor, const std::string& what) {
  SCOPED_TRACE(what);
  EXPECT_TRUE(sameArray(a.positions, b.positions)) << "positions";
  EXPECT_TRUE(sameArray(a.triangles, b.triangles)) << "triangles";
  EXPECT_TRUE(sameFloats(a.normals, b.normals)) << "normals";
  if (carriesColor) {
    EXPECT_TRUE(sameArray(a.attributes, b.attributes)) << "attributes";
    EXPECT_EQ(a.colorConvention, b.colorConvention);
    EXPECT_TRUE(sameArray(a.colors, b.colors)) << "colors";
    EXPECT_TRUE(sameArray(a.colorValid, b.colorValid)) << "colorValid";
  } else {
    EXPECT_EQ(b.colorConvention, stltopo::ColorConvention::None);
    EXPECT_TRUE(std::all_of(b.attributes.begin(), b.attributes.end(), [](uint16_t w) { return w == 0; }));
  }
  ASSERT_EQ(a.solids.size(), b.solids.size());
  for (size_t s = 0; s < a.solids.size(); ++s) {
    EXPECT_EQ(carriesColor ? a.solids[s].name : asciiName(a.solids[s].name), b.solids[s].name) << "solid " << s;
    EXPECT_EQ(a.solids[s].firstTriangle, b.solids[s].firstTriangle) << "solid " << s;
    EXPECT_EQ(a.solids[s].triangleCount, b.solids[s].triangleCount) << "solid " << s;
  }
  EXPECT_TRUE(b.warnings.empty()) << b.warnings[0].message;
}

TEST(WriteStl, EveryFixtureRoundTripsInBothFormats) {
  std::vector<std::string> files = readableFixtures();
  ASSERT_GE(files.size(), 50u);
  stltopo::ReadOptions keep;
  keep.keepNormals = true;
  for (const std::string& f : files) {
    Mesh m;
    ASSERT_TRUE(gen::read(gen::readFile(f), m, keep).ok()) << f;
    std::string bin = write(m);
    std::string asc = write(m, asciiOptions());
    Mesh fromBin, fromAsc;
    stltopo::Status sb = gen::read(bin, fromBin, keep), sa = gen::read(asc, fromAsc, keep);
    ASSERT_TRUE(sb.ok()) << f << ": " << sb.message;
    ASSERT_TRUE(sa.ok()) << f << ": " << sa.message;
    EXPECT_EQ(fromBin.format, Format::Binary);
    EXPECT_EQ(fromAsc.format, Format::Ascii);
    expectSameMesh(m, fromBin, true, f + " (binary)");
    // ASCII keeps no attribute words or colours: an ASCII fixture keeps everything.
    expectSameMesh(m, fromAsc, m.format == Format::Ascii, f + " (ascii)");
    EXPECT_EQ(bin.size(), 84 * m.solids.size() + 50 * size_t(m.nTriangles())) << f;
    // Writing what was read back gives the same bytes again.
    EXPECT_EQ(write(fromBin), bin) << f;
    EXPECT_EQ(write(fromAsc, asciiOptions()), asc) << f;
  }
}

TEST(WriteStl, BinaryToAsciiToBinaryKeepsPositionsAndTriangles) {
  for (const std::string& f : readableFixtures()) {
    Mesh m, viaAscii, back;
    ASSERT_TRUE(gen::read(gen::readFile(f), m).ok());
    ASSERT_TRUE(gen::read(write(m, asciiOptions()), viaAscii).ok()) << f;
    ASSERT_TRUE(gen::read(write(viaAscii), back).ok()) << f;
    EXPECT_TRUE(sameArray(m.positions, back.positions)) << f;
    EXPECT_TRUE(sameArray(m.triangles, back.triangles)) << f;
    EXPECT_EQ(back.format, Format::Binary);
  }
}

TEST(WriteStl, ComputedNormalsAreUnitLengthFromTheWindingAndZeroWhenDegenerate) {
  gen::Soup s = gen::cube();
  s.v.push_back({5, 5, 5});
  s.f.push_back({0, 1, 1});  // two corners the same vertex
  s.f.push_back({8, 8, 8});
  Mesh m;
  ASSERT_TRUE(gen::read(gen::binary(s), m).ok());
  WriteOptions o;
  o.storedNormals = false;
  std::string bin = write(m, o);
  stltopo::ReadOptions keep;
  keep.keepNormals = true;
  Mesh back;
  ASSERT_TRUE(gen::read(bin, back, keep).ok());
  EXPECT_EQ(back.normalMismatches, 0u);
  for (uint32_t t = 0; t < 12; ++t) {
    auto expected = gen::normalOf(s, t);  // double cross product, normalised, as floats
    for (int k = 0; k < 3; ++k) EXPECT_EQ(back.normals[3 * t + k], expected[k]) << t;
  }
  for (uint32_t t = 12; t < 14; ++t)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(back.normals[3 * t + k], 0.0f);
  // Stored normals are written as they are, even when they disagree with the winding.
  Mesh stored;
  ASSERT_TRUE(gen::read(gen::binary(s), stored, keep).ok());
  stored.normals[0] = -7.5f;
  Mesh again;
  ASSERT_TRUE(gen::read(write(stored), again, keep).ok());
  EXPECT_EQ(again.normals[0], -7.5f);
}

TEST(WriteStl, ChunksAreBoundedAndJoinToTheSameFile) {
  Mesh m;
  ASSERT_TRUE(
      gen::read(gen::readFile(gen::fixturePath("wolph_numpy-stl/tests/stl_binary/rear_case.stl")), m)
          .ok());
  for (Format f : {Format::Binary, Format::Ascii}) {
    WriteOptions big;
    big.format = f;
    big.chunkBytes = size_t(64) << 20;
    Output whole;
    ASSERT_TRUE(stltopo::writeStl(m, collect, &whole, big).ok());
    ASSERT_EQ(whole.chunks.size(), 1u);
    for (size_t chunk : {size_t(1), stltopo::kMinChunkBytes, size_t(100000), size_t(1) << 20}) {
      WriteOptions o = big;
      o.chunkBytes = chunk;
      Output parts;
      ASSERT_TRUE(stltopo::writeStl(m, collect, &parts, o).ok());
      EXPECT_EQ(parts.bytes, whole.bytes) << chunk;
      size_t limit = std::max(chunk, stltopo::kMinChunkBytes);
      EXPECT_GE(parts.chunks.size(), whole.bytes.size() / limit);
      for (size_t c : parts.chunks) EXPECT_LE(c, limit);
    }
    // The pull interface hands out the same bytes and counts them.
    stltopo::StlWriter w(m, big);
    std::string pulled;
    for (;;) {
      const uint8_t* data;
      size_t size;
      ASSERT_TRUE(w.next(data, size).ok());
      if (size == 0) break;
      pulled.append(reinterpret_cast<const char*>(data), size);
    }
    EXPECT_EQ(pulled, whole.bytes);
    EXPECT_EQ(w.bytesWritten(), whole.bytes.size());
  }
}

TEST(WriteStl, ASinkThatRefusesStopsTheWriteWithWriteFailed) {
  Mesh m;
  ASSERT_TRUE(gen::read(gen::binary(gen::torus(60, 60)), m).ok());  // 7200 triangles
  WriteOptions o;
  o.chunkBytes = stltopo::kMinChunkBytes;
  Output out;
  out.refuseAt = 3;
  stltopo::Status s = stltopo::writeStl(m, collect, &out, o);
  EXPECT_EQ(s.code, Code::WriteFailed);
  EXPECT_EQ(out.chunks.size(), 3u);  // nothing after the refused chunk
  EXPECT_EQ(s.offset, out.bytes.size());
  EXPECT_NE(s.message.find("write-failed: "), std::string::npos);
}

Mesh cubeMesh() {
  Mesh m;
  EXPECT_TRUE(gen::read(gen::binary(gen::cube()), m).ok());
  return m;
}

stltopo::Status writeStatus(const Mesh& m, const WriteOptions& o = {}) {
  Output out;
  stltopo::Status s = stltopo::writeStl(m, collect, &out, o);
  if (!s.ok()) EXPECT_TRUE(out.bytes.empty()) << "bytes handed out before the error";
  return s;
}

TEST(WriteStl, RefusesBrokenMeshesWithCodedErrorsBeforeAnyByte) {
  Mesh m = cubeMesh();
  m.triangles[3 * 5 + 2] = 8;  // 8 vertices: ids 0..7
  stltopo::Status s = writeStatus(m);
  EXPECT_EQ(s.code, Code::InvalidIndex);
  EXPECT_EQ(s.triangle, 5u);

  m = cubeMesh();
  (void)m.positions.resize(m.positions.size() - 1);
  EXPECT_EQ(writeStatus(m).code, Code::InvalidArgument);

  m = cubeMesh();
  (void)m.attributes.resize(3);
  EXPECT_EQ(writeStatus(m).code, Code::InvalidArgument);

  m = cubeMesh();
  m.solids[0].triangleCount = 13;  // past the end
  s = writeStatus(m);
  EXPECT_EQ(s.code, Code::InvalidArgument);
  EXPECT_NE(s.message.find("runs past"), std::string::npos) << s.message;

  m = cubeMesh();
  m.solids[0].triangleCount = 6;
  m.solids.push_back(stltopo::Solid{"b", 4, 8});  // overlaps the first
  s = writeStatus(m);
  EXPECT_EQ(s.code, Code::InvalidArgument);
  EXPECT_NE(s.message.find("overlaps"), std::string::npos) << s.message;

  m = cubeMesh();
  m.colorConvention = stltopo::ColorConvention::VisCam;  // without colour arrays
  EXPECT_EQ(writeStatus(m).code, Code::InvalidArgument);

  // The writer keeps its error.
  m = cubeMesh();
  m.triangles[0] = 100;
  stltopo::StlWriter w(m);
  const uint8_t* d;
  size_t n;
  EXPECT_EQ(w.next(d, n).code, Code::InvalidIndex);
  EXPECT_EQ(w.next(d, n).code, Code::InvalidIndex);
  EXPECT_EQ(n, 0u);
}

TEST(WriteStl, TrianglesNoSolidCoversBecomeUnnamedSolids) {
  Mesh m = cubeMesh();
  m.solids[0] = stltopo::Solid{"middle", 4, 4};
  for (Format f : {Format::Binary, Format::Ascii}) {
    WriteOptions o;
    o.format = f;
    Mesh back;
    ASSERT_TRUE(gen::read(write(m, o), back).ok());
    ASSERT_EQ(back.solids.size(), 3u);
    EXPECT_EQ(back.solids[0].name, "");
    EXPECT_EQ(back.solids[0].triangleCount, 4u);
    EXPECT_EQ(back.solids[1].name, "middle");
    EXPECT_EQ(back.solids[1].triangleCount, 4u);
    EXPECT_EQ(back.solids[2].triangleCount, 4u);
    EXPECT_TRUE(sameArray(m.triangles, back.triangles));
  }
  m.solids.clear();  // no solids at all: one
  Mesh back;
  ASSERT_TRUE(gen::read(write(m, asciiOptions()), back).ok());
  ASSERT_EQ(back.solids.size(), 1u);
  EXPECT_EQ(back.solids[0].triangleCount, 12u);
}

TEST(WriteStl, NamesAreCutBeforeBytesTheFormatCannotCarry) {
  Mesh m = cubeMesh();
  auto nameAfter = [&](const std::string& name, Format f) {
    WriteOptions o;
    o.format = f;
    o.name = name;
    Mesh back;
    EXPECT_TRUE(gen::read(write(m, o), back).ok());
    EXPECT_TRUE(back.warnings.empty());
    return back.solids.at(0).name;
  };
  // A newline ends an ASCII name; binary headers hold it.
  EXPECT_EQ(nameAfter("part 1\nendsolid x\nsolid y", Format::Ascii), "part 1");
  EXPECT_EQ(nameAfter("part 1\nby tool", Format::Binary), "part 1\nby tool");
  // A NUL ends the name in both.
  EXPECT_EQ(nameAfter(std::string("ab\0cd", 5), Format::Ascii), "ab");
  EXPECT_EQ(nameAfter(std::string("ab\0cd", 5), Format::Binary), "ab");
  EXPECT_EQ(nameAfter("tab\tinside  ", Format::Ascii), "tab\tinside");
  // 80 bytes in a binary header, at a UTF-8 character boundary.
  std::string longName(79, 'x');
  longName += "\xC3\xA9yz";  // 'é' straddles byte 80
  EXPECT_EQ(nameAfter(longName, Format::Binary), std::string(79, 'x'));
  EXPECT_EQ(nameAfter(longName, Format::Ascii), longName);
  // kMaxNameBytes in ASCII: read back without a name-truncated warning.
  EXPECT_EQ(nameAfter(std::string(5000, 'n'), Format::Ascii), std::string(stltopo::kMaxNameBytes, 'n'));
  // A COLOR= in the name of a mesh without Magics colours would make the reader see them.
  EXPECT_EQ(nameAfter("export COLOR=abcd", Format::Binary), "export");
  // The solid's own name otherwise.
  m.solids[0].name = "own name";
  Mesh back;
  ASSERT_TRUE(gen::read(write(m, asciiOptions()), back).ok());
  EXPECT_EQ(back.solids[0].name, "own name");
}

// A binary cube whose attribute words are the given ones, with an optional COLOR= header.
Mesh colouredCube(const std::vector<uint16_t>& words, const char* header = "coloured") {
  gen::Soup s = gen::cube();
  s.attr = words;
  Mesh m;
  EXPECT_TRUE(gen::read(gen::binary(s, header), m).ok());
  return m;
}

TEST(WriteStl, VisCamAndMagicsColoursRoundTripAndConvert) {
  // Every 5-bit value on each channel, VisCAM layout (bit 15 = coloured), some uncoloured.
  std::vector<uint16_t> vis;
  for (unsigned t = 0; t < 12; ++t)
    vis.push_back(t == 3 ? 0x1234 : uint16_t(0x8000u | (t * 2) << 10 | (31 - t) << 5 | (t + 19)));
  Mesh m = colouredCube(vis);
  ASSERT_EQ(m.colorConvention, stltopo::ColorConvention::VisCam);

  WriteOptions toMagics;
  toMagics.colors = WriteColors::Magics;
  toMagics.defaultColor[0] = 10, toMagics.defaultColor[1] = 20, toMagics.defaultColor[2] = 30;
  Mesh magics;
  ASSERT_TRUE(gen::read(write(m, toMagics), magics).ok());
  ASSERT_EQ(magics.colorConvention, stltopo::ColorConvention::Magics);
  for (uint32_t t = 0; t < 12; ++t) {
    EXPECT_EQ(magics.colorValid[t], 1);
    for (int c = 0; c < 3; ++c) {
      uint8_t want = t == 3 ? toMagics.defaultColor[c] : m.colors[3 * t + c];
      EXPECT_EQ(magics.colors[3 * t + c], want) << t << " " << c;
    }
  }
  EXPECT_EQ(magics.attributes[3], 0x8000u);  // the default colour
  // Magics as it is: the same words, the same colours, the same default colour.
  Mesh again;
  ASSERT_TRUE(gen::read(write(magics), again).ok());
  expectSameMesh(magics, again, true, "magics as is");
  // And back to VisCAM: the words of the coloured triangles come back exactly.
  WriteOptions toVis;
  toVis.colors = WriteColors::VisCam;
  Mesh back;
  ASSERT_TRUE(gen::read(write(magics, toVis), back).ok());
  ASSERT_EQ(back.colorConvention, stltopo::ColorConvention::VisCam);
  for (uint32_t t = 0; t < 12; ++t)
    if (t != 3) EXPECT_EQ(back.attributes[t], vis[t]) << t;
  // None: zero words, no colours.
  WriteOptions none;
  none.colors = WriteColors::None;
  Mesh plain;
  ASSERT_TRUE(gen::read(write(m, none), plain).ok());
  EXPECT_EQ(plain.colorConvention, stltopo::ColorConvention::None);
  for (uint32_t t = 0; t < 12; ++t) EXPECT_EQ(plain.attributes[t], 0u);
}

TEST(WriteStl, MagicsPartsKeepTheirDefaultColourAndUncolouredPartsStayUncoloured) {
  // Part 1: COLOR= (1, 2, 3), triangles with and without their own colour; part 2: no
  // COLOR= header, so uncoloured in a Magics file.
  gen::Soup s = gen::cube();
  for (unsigned t = 0; t < 12; ++t) s.attr.push_back(t % 2 ? 0x8000u : uint16_t(t | t << 5 | t << 10));
  std::string header = std::string("first\0", 6) + "COLOR=" + std::string("\x01\x02\x03\xff", 4);
  gen::Soup s2 = gen::cube(3, 0, 0);
  s2.attr.assign(12, 0x0421);
  Mesh m;
  ASSERT_TRUE(gen::read(gen::binary(s, header) + gen::binary(s2, "second"), m).ok());
  ASSERT_EQ(m.colorConvention, stltopo::ColorConvention::Magics);
  ASSERT_EQ(m.colors[3], 1);
  ASSERT_EQ(m.colorValid[12], 0);
  Mesh back;
  ASSERT_TRUE(gen::read(write(m), back).ok());
  expectSameMesh(m, back, true, "two magics parts");
  EXPECT_EQ(back.solids[0].name, "first");
}

TEST(WriteStl, WritingTwiceGivesTheSameBytesAndAsciiIsPlainText) {
  Mesh m;
  ASSERT_TRUE(gen::read(gen::ascii(gen::torus(8, 6), "torus"), m).ok());
  std::string a = write(m, asciiOptions());
  EXPECT_EQ(a, write(m, asciiOptions()));
  EXPECT_EQ(a.rfind("solid torus\n  facet normal ", 0), 0u);
  EXPECT_EQ(a.substr(a.size() - 15), "endsolid torus\n");
  for (char c : a) EXPECT_TRUE(c == '\n' || (c >= 0x20 && c < 0x7f));
}

}  // namespace

// ---------------------------------------------------------------------------
// The CLI: stltopo convert.
#if defined(STLTOPO_CLI) && !defined(STLTOPO_WASM_TESTS)  // the CLI runs as a subprocess: not in wasm
namespace {

struct Ran {
  int status;
  std::string out, err;
};

// Runs a shell command line; stdout and stderr are captured in files.
Ran shell(const std::string& cmd) {
  // Named after the test: ctest runs tests in parallel processes.
  std::string stem = testing::TempDir() + "/" + testing::UnitTest::GetInstance()->current_test_info()->name();
  std::string o = stem + ".out", e = stem + ".err";
  int rc = std::system((cmd + " >'" + o + "' 2>'" + e + "'").c_str());
  Ran r{WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, gen::readFile(o), gen::readFile(e)};
  std::remove(o.c_str());
  std::remove(e.c_str());
  return r;
}

std::string cli() { return std::string("'") + STLTOPO_CLI + "'"; }

// A fresh empty folder for one test.
std::string freshDir(const std::string& name) {
  std::filesystem::path p = std::filesystem::path(testing::TempDir()) / ("stltopo-" + name);
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p.string();
}

size_t entries(const std::string& dir) {
  return size_t(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()));
}

TEST(ConvertCli, WritesWhatTheLibraryWritesFromFilesAndPipes) {
  std::string dir = freshDir("convert");
  std::string in = gen::fixturePath("mikedh_trimesh/models/multibody.stl");  // ASCII, 2 solids
  Mesh m;
  ASSERT_TRUE(gen::read(gen::readFile(in), m).ok());
  Ran r = shell(cli() + " convert '" + in + "' '" + dir + "/a.stl' --binary");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(gen::readFile(dir + "/a.stl"), write(m));
  // The input's format by default; '-' for standard input and output.
  r = shell("cat '" + in + "' | " + cli() + " convert - -");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, write(m, asciiOptions()));
  // Colours and names.
  WriteOptions o;
  o.colors = WriteColors::Magics;
  o.name = "renamed";
  Mesh colored = colouredCube({0x8000u | 31u << 10, 0x8000u | 5u});
  std::string src = dir + "/colored.stl";
  {
    std::ofstream f(src, std::ios::binary);
    f << write(colored);
  }
  r = shell(cli() + " convert '" + src + "' '" + dir + "/b.stl' --colors magics --name renamed");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(gen::readFile(dir + "/b.stl"), write(colored, o));
  EXPECT_EQ(entries(dir), 3u);  // a.stl, colored.stl, b.stl: no temporary file left
}

TEST(ConvertCli, AFailedConversionLeavesNoOutputBehind) {
  std::string dir = freshDir("convert-fail");
  std::string out = dir + "/out.stl";
  // An input that does not read: exit 1, the error JSON on stderr, no OUT.
  Ran r =
      shell(cli() + " convert '" + gen::fixturePath("regress/stream-long-number.stl' '") + out + "'");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("\"code\":\"ascii-syntax\""), std::string::npos) << r.err;
  EXPECT_EQ(entries(dir), 0u);
  // A write that fails part-way (a 100 KiB file size limit, a 950 KB output): write-failed,
  // and an OUT that was there before keeps its old bytes.
  {
    std::ofstream f(out);
    f << "old";
  }
  std::string in = gen::fixturePath("wolph_numpy-stl/tests/stl_binary/rear_case.stl");
  r = shell("ulimit -f 100; " + cli() + " convert '" + in + "' '" + out + "'");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("\"code\":\"write-failed\""), std::string::npos) << r.err;
  EXPECT_EQ(gen::readFile(out), "old");
  EXPECT_EQ(entries(dir), 1u);
  // Without the limit the same conversion replaces OUT.
  r = shell(cli() + " convert '" + in + "' '" + out + "'");
  EXPECT_EQ(r.status, 0) << r.err;
  Mesh a, b;
  ASSERT_TRUE(gen::read(gen::readFile(in), a).ok());
  ASSERT_TRUE(gen::read(gen::readFile(out), b).ok());
  EXPECT_TRUE(sameArray(a.positions, b.positions));
  // Usage errors: exit 2.
  EXPECT_EQ(shell(cli() + " convert '" + in + "'").status, 2);
  EXPECT_EQ(shell(cli() + " convert '" + in + "' x.stl --colors rainbow").status, 2);
  EXPECT_EQ(entries(dir), 1u);
}

}  // namespace
#endif
