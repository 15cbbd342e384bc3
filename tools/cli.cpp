// stltopo command-line tool: `stltopo info [--json] FILE...`, `stltopo convert IN OUT`
// The only part of the project that does file I/O and printing.
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "stltopo/stltopo.h"

namespace {

const char* kUsage =
    "usage: stltopo info [--json] [--shells] [--defects] [--max-defects N] [--intersections] [--max-pairs N]\n"
    "                    [--no-topology] [--tolerance D] [--max-triangles N] [--max-bytes N] [--threads N] FILE...\n"
    "  Reads STL files (binary or ASCII; '-' reads standard input in chunks) and reports\n"
    "  their mesh and topology. --json prints one JSON object per file, one per line.\n"
    "  --shells adds a report per shell, --defects every defect with its location (the\n"
    "  first N of each kind, default 1000; the text report always lists the first 5).\n"
    "  --intersections finds every self-intersecting pair (exact), how shells nest and\n"
    "  whether the mesh is solid; --max-pairs N is its work limit (default 4000000).\n"
    "  --threads N uses N threads (default: the machine's cores; 1: one thread); the output\n"
    "  is the same for every N.\n"
    "  Exit status: 0 when every file was read, 1 when a file failed, 2 on usage errors.\n"
    "usage: stltopo convert IN OUT [--ascii|--binary] [--colors viscam|magics|none] [--name NAME]\n"
    "  Writes IN as STL to OUT ('-': standard input/output), in IN's format unless told.\n"
    "  OUT appears only when complete. A failure prints the error JSON on stderr (exit 1).\n"
    "usage: stltopo split IN OUTDIR [--ascii|--binary]\n"
    "  Writes each shell of IN to OUTDIR/<stem>-shell-<k>.stl (OUTDIR is created when\n"
    "  missing), in IN's format unless told, and prints a JSON line per file with its shell\n"
    "  report. A failure prints the error JSON on stderr (exit 1).\n";

struct Args {
  bool json = false, topology = true, shells = false, defects = false, intersections = false;
  uint64_t maxPairs = 4000000;
  int64_t maxDefects = -1;  // -1: the default (1000 in JSON, 5 in the text report)
  double tolerance = 0;
  uint32_t maxTriangles = 1u << 28;
  uint64_t maxBytes = 0;
  unsigned threads = 0;  // 0: the machine's cores
  std::vector<std::string> files;
};

// Reads one file (or stdin) through the streaming reader: a regular file is mapped
// (no copy through a buffer), anything else is read 1 MiB at a time.
stltopo::Status readFile(const std::string& path, const stltopo::ReadOptions& base, stltopo::Mesh& mesh) {
  FILE* f = path == "-" ? stdin : std::fopen(path.c_str(), "rb");
  if (!f) return stltopo::Status::error(stltopo::Code::InvalidArgument, "cannot open " + path + ": " + std::strerror(errno));
  stltopo::ReadOptions opt = base;
  struct stat st;
  if (fstat(fileno(f), &st) == 0 && S_ISREG(st.st_mode)) opt.sizeHint = uint64_t(st.st_size);
  stltopo::Reader reader(opt);
  stltopo::Status s;
  void* map = MAP_FAILED;
  size_t mapped = size_t(opt.sizeHint);
  if (mapped > 0 && f != stdin) map = mmap(nullptr, mapped, PROT_READ, MAP_PRIVATE, fileno(f), 0);
  if (map != MAP_FAILED) {
    (void)madvise(map, mapped, MADV_SEQUENTIAL);
    const uint8_t* p = static_cast<const uint8_t*>(map);
    constexpr size_t kChunk = size_t(8) << 20;  // the reader's maxBytes check sees each chunk
    for (size_t off = 0; off < mapped && s.ok(); off += kChunk) {
      size_t n = std::min(kChunk, mapped - off);
      s = reader.feed(p + off, n);
      // Streamed: a chunk the reader has consumed leaves the process (the page cache keeps
      // it), so the input never adds more than one chunk to the peak memory.
      (void)madvise(const_cast<uint8_t*>(p) + off, n, MADV_DONTNEED);
    }
    munmap(map, mapped);
  } else {
    std::vector<uint8_t> buf(1 << 20);
    for (;;) {
      size_t n = std::fread(buf.data(), 1, buf.size(), f);
      if (n > 0) {
        s = reader.feed(buf.data(), n);
        if (!s.ok()) break;
      }
      if (n < buf.size()) {
        if (std::ferror(f))
          s = stltopo::Status::error(stltopo::Code::InvalidArgument, "read error on " + path + ": " + std::strerror(errno));
        break;
      }
    }
  }
  if (f != stdin) std::fclose(f);
  if (s.ok()) s = reader.finish(mesh);
  return s;
}

// The output of `convert`: standard output, or a temporary file next to OUT that is
// renamed over OUT only once the whole file is written (and removed otherwise).
struct Output {
  std::string path, temp;
  int fd = -1;

  stltopo::Status open(const std::string& out) {
    path = out;
    if (out == "-") {
      fd = STDOUT_FILENO;
      return {};
    }
    size_t slash = out.rfind('/');
    std::string dir = slash == std::string::npos ? "" : out.substr(0, slash + 1);
    std::string base = slash == std::string::npos ? out : out.substr(slash + 1);
    std::string pattern = dir + "." + base + ".tmp-XXXXXX";
    std::vector<char> name(pattern.begin(), pattern.end());
    name.push_back('\0');
    fd = mkstemp(name.data());
    if (fd < 0)
      return stltopo::Status::error(stltopo::Code::WriteFailed, "cannot create a file next to " + out + ": " + std::strerror(errno));
    temp = name.data();
    mode_t mask = umask(0);
    umask(mask);
    (void)fchmod(fd, 0666 & ~mask);  // what open() would have given OUT
    return {};
  }

  static bool sink(void* user, const uint8_t* data, size_t size) {
    int fd = static_cast<Output*>(user)->fd;
    while (size > 0) {
      ssize_t n = ::write(fd, data, size);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return false;
      data += n;
      size -= size_t(n);
    }
    return true;
  }

  // Renames the temporary file over OUT (ok) or removes it.
  stltopo::Status close(stltopo::Status s) {
    if (temp.empty()) return s;
    int err = 0;
    if (s.ok() && fsync(fd) != 0) err = errno;
    if (::close(fd) != 0 && s.ok() && !err) err = errno;
    if (s.ok() && !err && std::rename(temp.c_str(), path.c_str()) != 0) err = errno;
    if (s.ok() && err) s = stltopo::Status::error(stltopo::Code::WriteFailed, "cannot write " + path + ": " + std::strerror(err));
    if (!s.ok()) std::remove(temp.c_str());
    return s;
  }
};

// The arguments of convert and split: two file names and the write options; split takes
// only --ascii/--binary (colorsAndName false). 0, or the exit status of a usage error.
int writeArgs(int argc, char** argv, bool colorsAndName, std::vector<std::string>& files, stltopo::WriteOptions& wo,
              bool& formatGiven) {
  formatGiven = false;
  for (int i = 2; i < argc; ++i) {
    std::string s = argv[i];
    if (s == "--") {  // the rest are file names
      files.insert(files.end(), argv + i + 1, argv + argc);
      break;
    }
    if (s.size() < 2 || s[0] != '-') {
      files.push_back(s);
      continue;
    }
    bool takesValue = colorsAndName && (s == "--colors" || s == "--name");
    if (takesValue && i + 1 >= argc) { std::fprintf(stderr, "stltopo: %s needs a value\n", s.c_str()); return 2; }
    std::string v = takesValue ? argv[++i] : "";
    if (s == "--ascii" || s == "--binary") {
      wo.format = s == "--ascii" ? stltopo::Format::Ascii : stltopo::Format::Binary;
      formatGiven = true;
    } else if (takesValue && s == "--name") {
      wo.name = v;
    } else if (takesValue && (v == "viscam" || v == "magics" || v == "none")) {
      wo.colors = v == "viscam" ? stltopo::WriteColors::VisCam : v == "magics" ? stltopo::WriteColors::Magics : stltopo::WriteColors::None;
    } else if (takesValue) {
      std::fprintf(stderr, "stltopo: bad --colors '%s' (viscam, magics or none)\n", v.c_str());
      return 2;
    } else {
      std::fprintf(stderr, "stltopo: unknown option '%s'\n%s", s.c_str(), kUsage);
      return 2;
    }
  }
  return 0;
}

int convert(int argc, char** argv) {
  std::vector<std::string> files;
  stltopo::WriteOptions wo;
  bool formatGiven;
  if (int rc = writeArgs(argc, argv, true, files, wo, formatGiven)) return rc;
  if (files.size() != 2) { std::fprintf(stderr, "stltopo: convert needs IN and OUT\n%s", kUsage); return 2; }
  stltopo::Mesh mesh;
  stltopo::Status s = readFile(files[0], stltopo::ReadOptions{}, mesh);
  if (!s.ok()) {
    std::fprintf(stderr, "%s\n", stltopo::errorJson(files[0], s).c_str());
    return 1;
  }
  if (!formatGiven) wo.format = mesh.format;
  std::signal(SIGXFSZ, SIG_IGN);  // over a file size limit, write() fails instead (write-failed)
  Output out;
  s = out.open(files[1]);
  if (s.ok()) s = out.close(stltopo::writeStl(mesh, Output::sink, &out, wo));
  if (!s.ok()) {
    std::fprintf(stderr, "%s\n", stltopo::errorJson(files[1], s).c_str());
    return 1;
  }
  return 0;
}

// The file of shell k: OUTDIR/<stem>-shell-<k>.stl, the stem being IN's file name without
// its last extension ("stdin" for '-'). bin/stltopo.mjs splitPath() is the same rule.
std::string splitPath(const std::string& in, std::string dir, uint32_t k) {
  std::string base = in == "-" ? "stdin" : in.substr(in.rfind('/') == std::string::npos ? 0 : in.rfind('/') + 1);
  size_t dot = base.rfind('.');
  if (in != "-" && dot != std::string::npos && dot > 0) base.resize(dot);
  while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
  return (dir == "/" ? dir : dir + "/") + base + "-shell-" + std::to_string(k) + ".stl";
}

int split(int argc, char** argv) {
  std::vector<std::string> files;
  stltopo::WriteOptions wo;
  bool formatGiven;
  if (int rc = writeArgs(argc, argv, false, files, wo, formatGiven)) return rc;
  if (files.size() != 2) { std::fprintf(stderr, "stltopo: split needs IN and OUTDIR\n%s", kUsage); return 2; }
  const std::string& in = files[0];
  const std::string& dir = files[1];
  auto fail = [](const std::string& file, const stltopo::Status& s) {
    std::fprintf(stderr, "%s\n", stltopo::errorJson(file, s).c_str());
    return 1;
  };
  stltopo::Mesh mesh;
  stltopo::Status s = readFile(in, stltopo::ReadOptions{}, mesh);
  stltopo::Topology topo;
  stltopo::TopologyOptions to;
  to.prevAndFace = false;
  to.triangleShell = true;
  if (s.ok()) s = stltopo::buildTopology(mesh, topo, to);
  stltopo::Array<stltopo::Shell> shells;
  if (s.ok()) s = stltopo::findShellsAndDefects(mesh, topo, &shells, nullptr);
  if (!s.ok()) return fail(in, s);
  struct stat st;
  if (mkdir(dir.c_str(), 0777) != 0 && !(errno == EEXIST && stat(dir.c_str(), &st) == 0 && S_ISDIR(st.st_mode)))
    return fail(dir, stltopo::Status::error(stltopo::Code::WriteFailed, "cannot create the folder " + dir + ": " + std::strerror(errno)));
  if (!formatGiven) wo.format = mesh.format;
  std::signal(SIGXFSZ, SIG_IGN);  // over a file size limit, write() fails instead (write-failed)
  for (uint32_t k = 0; k < shells.size(); ++k) {
    const std::string path = splitPath(in, dir, k);
    stltopo::Mesh part;
    s = stltopo::extractShell(mesh, topo, k, part);
    Output out;
    if (s.ok()) s = out.open(path);
    if (s.ok()) s = out.close(stltopo::writeStl(part, Output::sink, &out, wo));
    if (!s.ok()) return fail(path, s);
    std::printf("%s\n", stltopo::splitLineJson(path, shells[k], k).c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
#if defined(__GLIBC__)
  // Large arrays from the heap, and freed blocks kept there: a later array then reuses
  // pages that are already mapped (the weld table's for the topology's) instead of faulting
  // in fresh zeroed ones (bench/PROFILE.md has the measurement). glibc
  // still maps memory when the heap cannot grow.
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
  Args a;
  if (argc < 2) { std::fputs(kUsage, stderr); return 2; }
  std::string cmd = argv[1];
  if (cmd == "--help" || cmd == "-h" || cmd == "help") { std::fputs(kUsage, stdout); return 0; }
  if (cmd == "--version") { std::puts("stltopo 0.1.0"); return 0; }
  if (cmd == "convert") return convert(argc, argv);
  if (cmd == "split") return split(argc, argv);
  if (cmd != "info") { std::fprintf(stderr, "stltopo: unknown command '%s'\n%s", cmd.c_str(), kUsage); return 2; }
  bool endOfOptions = false;
  for (int i = 2; i < argc; ++i) {
    std::string s = argv[i];
    auto value = [&](const char* name) -> const char* {
      if (i + 1 >= argc) { std::fprintf(stderr, "stltopo: %s needs a value\n", name); std::exit(2); }
      return argv[++i];
    };
    if (!endOfOptions && s == "--") endOfOptions = true;
    else if (!endOfOptions && s == "--json") a.json = true;
    else if (!endOfOptions && s == "--no-topology") a.topology = false;
    else if (!endOfOptions && s == "--shells") a.shells = true;
    else if (!endOfOptions && s == "--defects") a.defects = true;
    else if (!endOfOptions && s == "--intersections") a.intersections = true;
    else if (!endOfOptions && s == "--max-pairs") {
      const char* v = value("--max-pairs");
      if (!v) return 2;
      char* end = nullptr;
      unsigned long long n = std::strtoull(v, &end, 10);
      if (*end || !*v || *v == '-' || n == 0 || n > (1ull << 40)) { std::fprintf(stderr, "stltopo: bad --max-pairs '%s'\n", v); return 2; }
      a.maxPairs = n;
    }
    else if (!endOfOptions && s == "--max-defects") {
      const char* v = value("--max-defects");
      char* end;
      unsigned long long n = std::strtoull(v, &end, 10);
      if (*end || !*v || *v == '-' || n > 0xFFFFFFFFull) { std::fprintf(stderr, "stltopo: bad --max-defects '%s'\n", v); return 2; }
      a.maxDefects = int64_t(n);
    }
    else if (!endOfOptions && s == "--tolerance") {
      const char* v = value("--tolerance");
      char* end;
      a.tolerance = std::strtod(v, &end);
      if (*end || !(a.tolerance >= 0)) { std::fprintf(stderr, "stltopo: bad --tolerance '%s'\n", v); return 2; }
    } else if (!endOfOptions && s == "--max-triangles") {
      const char* v = value("--max-triangles");
      char* end;
      unsigned long long n = std::strtoull(v, &end, 10);
      if (*end || n == 0 || n > 0xFFFFFFFFull) { std::fprintf(stderr, "stltopo: bad --max-triangles '%s'\n", v); return 2; }
      a.maxTriangles = uint32_t(n);
    } else if (!endOfOptions && s == "--max-bytes") {
      const char* v = value("--max-bytes");
      char* end;
      unsigned long long n = std::strtoull(v, &end, 10);
      if (*end || n == 0) { std::fprintf(stderr, "stltopo: bad --max-bytes '%s'\n", v); return 2; }
      a.maxBytes = n;
    } else if (!endOfOptions && s == "--threads") {
      const char* v = value("--threads");
      char* end;
      unsigned long long n = std::strtoull(v, &end, 10);
      if (*end || !*v || *v == '-' || n == 0 || n > 1024) { std::fprintf(stderr, "stltopo: bad --threads '%s'\n", v); return 2; }
      a.threads = unsigned(n);
    } else if (!endOfOptions && s == "--test-parallel-grain") {
      // Not in the usage: the tests make every threaded stage split small files with it.
      const char* v = value("--test-parallel-grain");
      char* end;
      unsigned long long n = std::strtoull(v, &end, 10);
      if (*end || !*v || *v == '-') { std::fprintf(stderr, "stltopo: bad --test-parallel-grain '%s'\n", v); return 2; }
      stltopo::setParallelGrainForTesting(size_t(n));
    } else if (!endOfOptions && s.size() > 1 && s[0] == '-') {
      std::fprintf(stderr, "stltopo: unknown option '%s'\n%s", s.c_str(), kUsage);
      return 2;
    } else {
      a.files.push_back(s);
    }
  }
  if (a.files.empty()) { std::fprintf(stderr, "stltopo: no input files\n%s", kUsage); return 2; }
  if (!a.topology && (a.shells || a.defects || a.intersections)) {
    std::fprintf(stderr, "stltopo: --shells, --defects and --intersections need the topology (not --no-topology)\n");
    return 2;
  }

  // The text report always lists the first few defects of each kind.
  const bool defects = a.defects || !a.json;

  int rc = 0;
  stltopo::ReadOptions ro;
  ro.maxTriangles = a.maxTriangles;
  ro.maxBytes = a.maxBytes;
  ro.threads = a.threads;
  stltopo::TopologyOptions to;
  to.threads = a.threads;
  to.tolerance = a.tolerance;
  to.prevAndFace = false;  // the report needs neither: 24 fewer bytes per triangle
  to.triangleShell = a.topology && (a.shells || defects || a.intersections);
  stltopo::IntersectionOptions io;
  io.maxPairs = a.maxPairs;
  io.threads = a.threads;
  stltopo::ReportExtras extras;
  extras.maxDefects = a.maxDefects >= 0 ? uint32_t(a.maxDefects) : a.json ? 1000 : 5;
  for (const std::string& file : a.files) {
    stltopo::Mesh mesh;
    stltopo::Topology topo;
    stltopo::Status s = readFile(file, ro, mesh);
    if (s.ok() && a.topology) s = stltopo::buildTopology(mesh, topo, to);
    stltopo::Array<stltopo::Shell> shells;
    stltopo::Defects found;
    stltopo::GeometryReport geo;
    // With --intersections, analyzeGeometry builds the shell list: it is not built twice.
    if (s.ok() && a.topology && to.triangleShell && (defects || (a.shells && !a.intersections)))
      s = stltopo::findShellsAndDefects(mesh, topo, a.shells && !a.intersections ? &shells : nullptr,
                                        defects ? &found : nullptr);
    if (s.ok() && a.topology && a.intersections) s = stltopo::analyzeGeometry(mesh, topo, geo, io);
    // The report's triangle checks, on the threads (analyzeGeometry has them with --intersections).
    stltopo::TriangleChecks checks;
    const bool ownChecks = s.ok() && a.topology && !a.intersections && stltopo::checkTriangles(mesh, &topo, checks, a.threads).ok();
    if (!s.ok()) {
      rc = 1;
      if (a.json) std::printf("%s\n", stltopo::errorJson(file, s).c_str());
      else std::fprintf(stderr, "%s: %s\n", file.c_str(), s.message.c_str());
      continue;
    }
    const stltopo::Topology* t = a.topology ? &topo : nullptr;
    extras.shells = a.shells && t ? (a.intersections ? &geo.shells : &shells) : nullptr;
    extras.defects = defects && t ? &found : nullptr;
    extras.checks = !t ? nullptr : a.intersections ? &geo.checks : ownChecks ? &checks : nullptr;
    extras.intersections = a.intersections && t ? &geo.intersections : nullptr;
    extras.nesting = a.intersections && t ? &geo.nesting : nullptr;
    extras.solid = geo.solid;
    if (a.json) std::printf("%s\n", stltopo::infoJson(file, mesh, t, extras).c_str());
    else std::fputs(stltopo::infoText(file, mesh, t, extras).c_str(), stdout);
  }
  return rc;
}
