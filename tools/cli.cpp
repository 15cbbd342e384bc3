// stltopo command-line tool: `stltopo info [--json] [--jobs N] [--list LIST] FILE|DIR...`,
// `stltopo convert IN OUT`, `stltopo split IN OUTDIR`.
// The only part of the project that does file I/O and printing.
#include <dirent.h>
#include <fcntl.h>
#include <strings.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>
#include <string>
#include <thread>
#include <vector>

#include "stltopo/stltopo.h"

namespace {

const char* kUsage =
    "usage: stltopo info [--json] [--shells] [--defects] [--max-defects N] [--intersections] [--max-pairs N]\n"
    "                    [--no-topology] [--tolerance D] [--max-triangles N] [--max-bytes N] [--threads N]\n"
    "                    [--jobs N] [--max-memory N] [--list LIST]... FILE|DIR...\n"
    "  Reads STL files (binary or ASCII; '-' reads standard input in chunks) and reports\n"
    "  their mesh and topology. --json prints one JSON object per file, one per line.\n"
    "  A DIR is searched recursively for *.stl files (any case), sorted bytewise by path\n"
    "  (links to directories are not followed); --list LIST reads FILE and DIR arguments\n"
    "  from LIST, one per line ('-': standard input). Files are reported in the order\n"
    "  given, DIRs and LISTs expanded in place; a failed file never stops the others.\n"
    "  --jobs N reads N files at a time (1 to 256, default 1); the output is the same.\n"
    "  Files start in order, each only while the files being read fit in --max-memory N\n"
    "  bytes (default: half the machine's memory), a file counted at 8 times its size (48\n"
    "  with --shells); a larger one, or one of unknown size ('-', a pipe), is read alone.\n"
    "  --shells adds a report per shell, --defects every defect with its location (the\n"
    "  first N of each kind, default 1000; the text report always lists the first 5).\n"
    "  --intersections finds every self-intersecting pair (exact), how shells nest and\n"
    "  whether the mesh is solid; --max-pairs N is its work limit (default 4000000).\n"
    "  --threads N uses N threads per file (0, the default: the machine's cores; the npm\n"
    "  CLI's default is 1, and N > 1 runs its threaded wasm module); the output is the same.\n"
    "  Exit status: 0 when every file was read, 1 when a file failed, 2 on usage errors.\n"
    "usage: stltopo convert IN OUT [--ascii|--binary] [--colors viscam|magics|none] [--name NAME]\n"
    "  Writes IN as STL to OUT ('-': standard input/output), in IN's format unless told.\n"
    "  OUT appears only when complete. A failure prints the error JSON on stderr (exit 1).\n"
    "usage: stltopo split IN OUTDIR [--ascii|--binary]\n"
    "  Writes each shell of IN to OUTDIR/<stem>-shell-<k>.stl (OUTDIR is created when\n"
    "  missing), in IN's format unless told, and prints a JSON line per file with its shell\n"
    "  report. A failure prints the error JSON on stderr (exit 1).\n"
    "usage: stltopo repair IN OUT [--plan] [--steps a,b,...] [--stitch-tolerance D] [--max-hole-edges N]\n"
    "                      [--max-hole-area A] [--max-hole-perimeter P] [--fill refine,fair|none]\n"
    "                      [--min-shell-triangles N] [--min-shell-volume V] [--remove-walls]\n"
    "                      [--exclude step:item,...] [--no-intersections] [--max-pairs N] [--threads N]\n"
    "                      [--ascii|--binary]\n"
    "  Plans the chosen repair steps (default duplicates,zero-area,stitch,orient,fill-holes; also\n"
    "  split-nonmanifold, small-shells) and prints the plan as JSON (--plan: nothing is written),\n"
    "  or carries it out, writes OUT and prints the change log as JSON. OUT appears only when\n"
    "  complete. Exit status: 0 when the result is watertight, manifold and solid, 3 when it\n"
    "  is not (the JSON says which), 1 on failure (error JSON on stderr), 2 on usage errors.\n";

struct Args {
  bool json = false, topology = true, shells = false, defects = false, intersections = false;
  uint64_t maxPairs = 4000000;
  int64_t maxDefects = -1;  // -1: the default (1000 in JSON, 5 in the text report)
  double tolerance = 0;
  uint32_t maxTriangles = 1u << 28;
  uint64_t maxBytes = 0;
  unsigned jobs = 1;
  uint64_t maxMemory = 0;  // --max-memory; 0: half the machine's memory
  bool jobsLog = false;    // the hidden --test-jobs-log
  unsigned threads = 0;    // per file; 0 (the default): the machine's cores
  // The inputs in the order given: a FILE or DIR argument, or (list true) a --list LIST.
  struct Arg {
    std::string path;
    bool list;
  };
  std::vector<Arg> inputs;
};

// Huge pages for the heap that a file's arrays are about to take (Linux, glibc): a block of
// `bytes` (at most 512 MiB) is taken from the heap, advised (the library's adviseHugePages),
// and given back. main() keeps large blocks in the heap and does not trim it below 1 GiB, so
// the advice stays on that stretch, and the arrays that reuse it fault in 2 MiB at a time.
// The library advises its own arrays of 4 MiB and more, but only their whole 2 MiB-aligned
// stretches; this also covers the smaller arrays and the arrays' ends. On this VM it made
// `info` of the 100k tori 1.4-1.6x faster as a whole process (page faults 1,960 -> about 300)
// and of the 1M tori 1.2-1.5x, for about 1 MiB more peak memory (bench/PROFILE.md, *Stop 53*).
// Nothing is touched: a block the heap cannot give, or that glibc maps apart, changes nothing.
// The block stays below half the trim threshold, so that freeing it never trims the heap.
constexpr int kHeapTrimThreshold = 1 << 30;  // main()'s M_TRIM_THRESHOLD
void* volatile heapPad = nullptr;            // adviseHeap's pad, kept (volatile: an unused malloc is elided)
void adviseHeap(uint64_t bytes) {
#if defined(__GLIBC__)
  static std::mutex m;
  static uint64_t advised = 0;  // the largest block advised so far
  const std::lock_guard<std::mutex> lock(m);
  // Only whole 2 MiB stretches can be huge pages: the block is a number of them, and starts
  // at a boundary. It starts where the heap's free end does, so the first arrays took the 4 kB
  // pages below its first 2 MiB boundary (up to 2 MiB: the 100k tori's weld faulted 100-270
  // times there). Once, a pad is kept up to that boundary and the block taken again from it;
  // the pad is address space, never touched.
  constexpr uintptr_t kHuge = uintptr_t(2) << 20;
  bytes = std::min<uint64_t>((bytes + kHuge - 1) / kHuge * kHuge, kHeapTrimThreshold / 2);
  if (bytes <= advised) return;
  void* p = std::malloc(size_t(bytes));
  if (!p) return;
  const uintptr_t at = reinterpret_cast<uintptr_t>(p);
  const uintptr_t gap = (kHuge - at % kHuge) % kHuge;
  if (!heapPad && gap >= 4096) {
    std::free(p);
    heapPad = std::malloc(size_t(gap - 2 * sizeof(size_t)));  // less the next chunk's header
    p = std::malloc(size_t(bytes));
    if (!p) return;
  }
  stltopo::detail::adviseHugePages(p, size_t(bytes));
  std::free(p);
  advised = bytes;
#else
  (void)bytes;
#endif
}

// Reads one file (or stdin) through the streaming reader: a regular file is mapped
// (no copy through a buffer), anything else is read 1 MiB at a time.
stltopo::Status readFile(const std::string& path, const stltopo::ReadOptions& base, stltopo::Mesh& mesh) {
  FILE* f = path == "-" ? stdin : std::fopen(path.c_str(), "rb");
  if (!f)
    return stltopo::Status::error(stltopo::Code::InvalidArgument, "cannot open " + path + ": " + std::strerror(errno));
  stltopo::ReadOptions opt = base;
  struct stat st;
  if (fstat(fileno(f), &st) == 0 && S_ISREG(st.st_mode)) opt.sizeHint = uint64_t(st.st_size);
  adviseHeap(2 * opt.sizeHint);  // a binary file's arrays take up to ~1.9x its size
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
          s = stltopo::Status::error(stltopo::Code::InvalidArgument,
                                     "read error on " + path + ": " + std::strerror(errno));
        break;
      }
    }
  }
  if (f != stdin) std::fclose(f);
  if (s.ok()) s = reader.finish(mesh);
  return s;
}

// One file to report: a path ('-': standard input), or a directory that could not be
// searched (err: its errno), reported as a failed file under its own path.
struct Input {
  std::string path;
  int err = 0;
};

// A *.stl name, any case (bin/cli-corpus.mjs isStlName is the same rule).
bool isStlName(const char* name) {
  size_t n = std::strlen(name);
  return n >= 4 && strcasecmp(name + n - 4, ".stl") == 0;
}

// Appends the *.stl files under the directory `root` to `out`, sorted bytewise by path:
// regular files, and links to regular files or to nothing (a broken link is reported as a
// file that cannot be opened). Links to directories are not followed, so a link loop
// cannot make the walk endless; a directory that cannot be read is an Input with its errno.
// bin/cli-corpus.mjs walk() is the same walk.
void walk(const std::string& root, std::vector<Input>& out) {
  std::vector<Input> found;
  std::vector<std::string> dirs{root};
  while (!dirs.empty()) {
    std::string dir = std::move(dirs.back());
    dirs.pop_back();
    DIR* d = opendir(dir.c_str());
    if (!d) {
      found.push_back({dir, errno ? errno : EIO});
      continue;
    }
    const std::string prefix = dir.back() == '/' ? dir : dir + "/";
    while (const dirent* e = readdir(d)) {
      if (std::strcmp(e->d_name, ".") == 0 || std::strcmp(e->d_name, "..") == 0) continue;
      std::string p = prefix + e->d_name;
      unsigned char type = e->d_type;
      struct stat st;
      if (type == DT_UNKNOWN) {
        if (lstat(p.c_str(), &st) != 0) continue;  // gone since readdir
        type = S_ISDIR(st.st_mode) ? DT_DIR : S_ISLNK(st.st_mode) ? DT_LNK : S_ISREG(st.st_mode) ? DT_REG : DT_UNKNOWN;
      }
      if (type == DT_DIR) {
        dirs.push_back(std::move(p));
      } else if (isStlName(e->d_name)) {
        if (type == DT_REG || (type == DT_LNK && (stat(p.c_str(), &st) != 0 || S_ISREG(st.st_mode))))
          found.push_back({std::move(p), 0});
      }
    }
    closedir(d);
  }
  std::sort(found.begin(), found.end(), [](const Input& x, const Input& y) { return x.path < y.path; });
  for (Input& f : found) out.push_back(std::move(f));
}

// A FILE or DIR argument (or a line of a list): a directory is walked, anything else
// (standard input, a file, a path that does not exist) is one input.
void expand(const std::string& arg, std::vector<Input>& out) {
  struct stat st;
  if (arg != "-" && stat(arg.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
    walk(arg, out);
  else
    out.push_back({arg, 0});
}

// Reads a --list: one FILE or DIR per line, '\r\n' or '\n', empty lines skipped.
// Empty string on success, else the usage error to print.
std::string readList(const std::string& list, std::vector<Input>& out) {
  FILE* f = list == "-" ? stdin : std::fopen(list.c_str(), "rb");
  if (!f) return "stltopo: cannot read the list " + list + ": " + std::strerror(errno) + "\n";
  std::string text;
  char buf[1 << 16];
  int err = 0;
  for (;;) {
    size_t n = std::fread(buf, 1, sizeof buf, f);
    text.append(buf, n);
    if (n < sizeof buf) {
      if (std::ferror(f)) err = errno ? errno : EIO;
      break;
    }
  }
  if (f != stdin) std::fclose(f);
  if (err) return "stltopo: cannot read the list " + list + ": " + std::strerror(err) + "\n";
  size_t line = 0;
  for (size_t at = 0; at < text.size();) {
    size_t end = text.find('\n', at);
    if (end == std::string::npos) end = text.size();
    std::string path = text.substr(at, end - at);
    at = end + 1;
    ++line;
    if (!path.empty() && path.back() == '\r') path.pop_back();
    if (path.find('\0') != std::string::npos)
      return "stltopo: the list " + list + " has a NUL byte on line " + std::to_string(line) + "\n";
    if (!path.empty()) expand(path, out);
  }
  return "";
}

// What `info` does to every file (from the options of the command line).
struct InfoConfig {
  bool json, topology, shells, defects, intersections;
  unsigned threads;
  stltopo::ReadOptions ro;
  stltopo::TopologyOptions to;
  stltopo::IntersectionOptions io;
  uint32_t maxDefects;
};

// The report of one input: what goes to standard output and to standard error.
struct Result {
  bool ok = true;
  std::string out, err;
};

// `direct`: the report goes there in pieces as it is written (stltopo::infoJson and infoText
// with a sink), not into the result: a report of millions of shells is never held whole.
Result reportOneOrThrow(const Input& in, const InfoConfig& c, FILE* direct, bool& wrote);

// reportOne, with an exhausted heap (the core's arrays say so by a status; the report's
// strings and the repair's plan are std::string and std::vector) as that file's
// out-of-memory error: the other files are still reported.
Result reportOne(const Input& in, const InfoConfig& c, FILE* direct = nullptr) {
  bool wrote = false;  // a part of the report went to `direct`
  try {
    return reportOneOrThrow(in, c, direct, wrote);
  } catch (const std::bad_alloc&) {
    Result r;
    r.ok = false;
    const stltopo::Status s =
        stltopo::Status::error(stltopo::Code::OutOfMemory, "out of memory while reporting " + in.path);
    if (c.json)
      r.out = (wrote ? "\n" : "") + stltopo::errorJson(in.path, s) + "\n";
    else
      r.err = in.path + ": " + s.message + "\n";
    return r;
  }
}

Result reportOneOrThrow(const Input& in, const InfoConfig& c, FILE* direct, bool& wrote) {
  Result r;
  const std::string& file = in.path;
  stltopo::Mesh mesh;
  stltopo::Topology topo;
  stltopo::Status s = in.err ? stltopo::Status::error(stltopo::Code::InvalidArgument,
                                                      "cannot open " + file + ": " + std::strerror(in.err))
                             : readFile(file, c.ro, mesh);
  if (s.ok() && c.topology) s = stltopo::buildTopology(mesh, topo, c.to);
  stltopo::Array<stltopo::Shell> shells;
  stltopo::Defects found;
  stltopo::GeometryReport geo;
  // With --intersections, analyzeGeometry builds the shell list: it is not built twice.
  if (s.ok() && c.topology && c.to.triangleShell && (c.defects || (c.shells && !c.intersections)))
    s = stltopo::findShellsAndDefects(mesh, topo, c.shells && !c.intersections ? &shells : nullptr,
                                      c.defects ? &found : nullptr);
  if (s.ok() && c.topology && c.intersections) {
    if (c.shells || c.defects) {
      s = stltopo::analyzeGeometry(mesh, topo, geo, c.io, c.shells);
    } else {
      // The report prints of the topology only its counts and loops after this: the arrays
      // only the triangle checks read go before the pass, which then reuses their memory
      // (the 1M torus: 18 MB, of the pass's 45 MB of new pages).
      s = stltopo::checkTriangles(mesh, &topo, geo.checks, c.io.threads);
      topo.next.release(), topo.prev.release(), topo.face.release();
      topo.triangleHalfedge.release(), topo.vertexHalfedge.release();
      if (s.ok()) s = stltopo::analyzeGeometryAfterChecks(mesh, topo, geo, c.io, false);
    }
  }
  if (!s.ok()) {
    r.ok = false;
    if (c.json)
      r.out = stltopo::errorJson(file, s) + "\n";
    else
      r.err = file + ": " + s.message + "\n";
    return r;
  }
  const stltopo::Topology* t = c.topology ? &topo : nullptr;
  stltopo::ReportExtras extras;
  extras.maxDefects = c.maxDefects;
  extras.shells = c.shells && t ? (c.intersections ? &geo.shells : &shells) : nullptr;
  extras.defects = c.defects && t ? &found : nullptr;
  // The report's triangle checks, on the threads (analyzeGeometry has them with --intersections).
  stltopo::TriangleChecks checks;
  const bool ownChecks =
      t && !c.intersections && c.threads != 1 && stltopo::checkTriangles(mesh, &topo, checks, c.threads).ok();
  extras.checks = !t ? nullptr : c.intersections ? &geo.checks : ownChecks ? &checks : nullptr;
  extras.intersections = c.intersections && t ? &geo.intersections : nullptr;
  extras.nesting = c.intersections && t ? &geo.nesting : nullptr;
  extras.solid = geo.solid;
  if (direct) {
    const stltopo::ReportSink sink = [direct, &wrote](const char* d, size_t n) {
      std::fwrite(d, 1, n, direct);
      wrote = true;
    };
    if (c.json) {
      stltopo::infoJson(sink, file, mesh, t, extras);
      std::fputc('\n', direct);
    } else {
      stltopo::infoText(sink, file, mesh, t, extras);
    }
  } else {
    r.out = c.json ? stltopo::infoJson(file, mesh, t, extras) + "\n" : stltopo::infoText(file, mesh, t, extras);
  }
  return r;
}

// Prints one report; false when the file failed.
bool print(const Result& r) {
  if (!r.out.empty()) std::fwrite(r.out.data(), 1, r.out.size(), stdout);
  if (!r.err.empty()) {
    std::fflush(stdout);
    std::fwrite(r.err.data(), 1, r.err.size(), stderr);
  }
  return r.ok;
}

// What reading an input may take at its peak, for the memory gate of `info --jobs N`: a
// multiple of a regular file's size, from the worst cases measured (peak RSS of `info --json`
// over the file's size; the npm CLI's in brackets, Node included): a welded mesh 1.6-2.4
// (2.6), the 1M torus with every flag; a triangle soup, no corner shared, 6.5-7.5 (7.5), its 3
// vertices a triangle in every array and in the weld's table; and with --shells a soup's
// report is a shell a triangle, 400 bytes of JSON each: 30-35 (47). So 8 times the size, 48
// with --shells. Standard input, a pipe or a device has no size to go by: it counts as the
// whole budget, so it is read alone. An input that cannot be looked at counts as nothing: it
// fails when it is opened.
uint64_t peakEstimate(const Input& in, uint64_t budget, uint64_t factor) {
  if (in.err) return 0;
  if (in.path == "-") return budget;
  struct stat st;
  if (stat(in.path.c_str(), &st) != 0) return 0;
  if (!S_ISREG(st.st_mode)) return budget;
  const uint64_t size = uint64_t(st.st_size);
  return size > UINT64_MAX / factor ? UINT64_MAX : size * factor;
}

// Half the machine's memory: the default of --max-memory (no limit when it is unknown).
uint64_t defaultMemoryBudget() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return UINT64_MAX;
  return uint64_t(pages) / 2 * uint64_t(page);
}

// Reports every input in order with `jobs` threads: each takes the next index, and the
// main thread prints the reports in input order. A thread starts input i only when it is
// fewer than `window` inputs after the first one not yet printed, so a slow file holds at
// most `window` finished reports in memory, and only when the memory gate lets it:
// inputs are let in in input order, each while the peak estimates of the inputs being
// read, its own included, stay within `budget`, or when no other input is being read (so
// a larger one is read alone, and never waits for ever). Without the gate, eight 40M-triangle
// files on `--jobs 8` would ask for some 23 GB at once, and the kernel's OOM killer would
// stop every report, not one. `log` (the hidden --test-jobs-log) prints, after the reports,
// each start and end in the order they happened, for the tests. 0 when every file was read,
// else 1.
int reportAll(const std::vector<Input>& inputs, const InfoConfig& c, unsigned jobs, uint64_t budget, bool log) {
  const size_t n = inputs.size();
  int rc = 0;
  if (jobs > n) jobs = unsigned(n);
  if (jobs <= 1) {
    for (const Input& in : inputs)
      if (!print(reportOne(in, c, stdout))) rc = 1;
    return rc;
  }
  const size_t window = size_t(jobs) * 4;
  std::vector<Result> slots(window);
  std::vector<char> ready(window, 0);
  std::atomic<size_t> next{0};
  // Under mu: the first input not yet printed; the gate's count of inputs let in, of inputs
  // being read and the sum of their estimates; the log.
  size_t head = 0, admitted = 0;
  unsigned reading = 0;
  uint64_t inFlight = 0;
  std::string events;
  std::mutex mu;
  std::condition_variable space, done;  // space: head, admitted or reading changed
  auto work = [&] {
    for (;;) {
      const size_t i = next.fetch_add(1);
      if (i >= n) return;
      const uint64_t estimate = peakEstimate(inputs[i], budget, c.shells ? 48 : 8);
      {
        std::unique_lock<std::mutex> lock(mu);
        space.wait(lock, [&] {
          return i < head + window && admitted == i &&
                 (reading == 0 || (inFlight <= budget && estimate <= budget - inFlight));
        });
        if (log)
          events += "jobs-log: start " + std::to_string(i) + " " + std::to_string(estimate) + " " +
                    std::to_string(reading) + " " + std::to_string(inFlight) + "\n";
        ++admitted, ++reading;
        inFlight = estimate > UINT64_MAX - inFlight ? UINT64_MAX : inFlight + estimate;
      }
      space.notify_all();  // input i + 1 may start now
      Result r = reportOne(inputs[i], c);
      {
        std::lock_guard<std::mutex> lock(mu);
        slots[i % window] = std::move(r);
        ready[i % window] = 1;
        --reading;
        inFlight = reading == 0 ? 0 : inFlight - std::min(inFlight, estimate);
        if (log) events += "jobs-log: end " + std::to_string(i) + "\n";
      }
      done.notify_one();
      space.notify_all();
    }
  };
  std::vector<std::thread> threads;
  for (unsigned k = 0; k < jobs; ++k) {
    try {
      threads.emplace_back(work);
    } catch (const std::system_error&) {
      break;  // fewer threads than asked: the ones running do the work
    }
  }
  if (threads.empty()) {  // no thread could start: this one does everything, in order
    for (const Input& in : inputs)
      if (!print(reportOne(in, c, stdout))) rc = 1;
    return rc;
  }
  for (size_t k = 0; k < n; ++k) {
    Result r;
    {
      std::unique_lock<std::mutex> lock(mu);
      done.wait(lock, [&] { return ready[k % window] != 0; });
      r = std::move(slots[k % window]);
      ready[k % window] = 0;
      head = k + 1;
    }
    space.notify_all();
    if (!print(r)) rc = 1;
  }
  for (std::thread& t : threads) t.join();
  if (log) std::fputs(events.c_str(), stderr);
  return rc;
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
      return stltopo::Status::error(stltopo::Code::WriteFailed,
                                    "cannot create a file next to " + out + ": " + std::strerror(errno));
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
    if (s.ok() && err)
      s = stltopo::Status::error(stltopo::Code::WriteFailed, "cannot write " + path + ": " + std::strerror(err));
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
    if (takesValue && i + 1 >= argc) {
      std::fprintf(stderr, "stltopo: %s needs a value\n", s.c_str());
      return 2;
    }
    std::string v = takesValue ? argv[++i] : "";
    if (s == "--ascii" || s == "--binary") {
      wo.format = s == "--ascii" ? stltopo::Format::Ascii : stltopo::Format::Binary;
      formatGiven = true;
    } else if (takesValue && s == "--name") {
      wo.name = v;
    } else if (takesValue && (v == "viscam" || v == "magics" || v == "none")) {
      wo.colors = v == "viscam"   ? stltopo::WriteColors::VisCam
                  : v == "magics" ? stltopo::WriteColors::Magics
                                  : stltopo::WriteColors::None;
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
  if (files.size() != 2) {
    std::fprintf(stderr, "stltopo: convert needs IN and OUT\n%s", kUsage);
    return 2;
  }
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

// Prints the error JSON of split or repair to standard error: exit status 1.
int fail(const std::string& file, const stltopo::Status& s) {
  std::fprintf(stderr, "%s\n", stltopo::errorJson(file, s).c_str());
  return 1;
}

int split(int argc, char** argv) {
  std::vector<std::string> files;
  stltopo::WriteOptions wo;
  bool formatGiven;
  if (int rc = writeArgs(argc, argv, false, files, wo, formatGiven)) return rc;
  if (files.size() != 2) {
    std::fprintf(stderr, "stltopo: split needs IN and OUTDIR\n%s", kUsage);
    return 2;
  }
  const std::string& in = files[0];
  const std::string& dir = files[1];
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
    return fail(dir, stltopo::Status::error(stltopo::Code::WriteFailed,
                                            "cannot create the folder " + dir + ": " + std::strerror(errno)));
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

// --threads N (N <= 1024) and the hidden --test-parallel-grain N: a whole number written
// in decimal, no sign. Prints "stltopo: bad OPTION 'v'" when it is not.
bool countArg(const char* option, const char* v, unsigned long long max, unsigned long long& out) {
  char* end;
  out = std::strtoull(v, &end, 10);
  if (*end || !*v || *v == '-' || out > max) {
    std::fprintf(stderr, "stltopo: bad %s '%s'\n", option, v);
    return false;
  }
  return true;
}

// Parses a number option's value: a finite double >= 0 (integer: a whole number <= max).
bool numberArg(const std::string& v, double& out, bool integer, double max) {
  char* end = nullptr;
  errno = 0;
  double d = std::strtod(v.c_str(), &end);
  if (v.empty() || *end || errno || !(d >= 0) || d > max || (integer && d != std::floor(d))) return false;
  out = d;
  return true;
}

std::vector<std::string> splitList(const std::string& v) {
  std::vector<std::string> out;
  size_t i = 0;
  for (;;) {
    size_t j = v.find(',', i);
    out.push_back(v.substr(i, j == std::string::npos ? std::string::npos : j - i));
    if (j == std::string::npos) return out;
    i = j + 1;
  }
}

// repair of `in` into `outFile` ("" with --plan: the plan only), past the command line.
int repairFile(const std::string& in, const std::string& outFile, const stltopo::RepairOptions& ro,
               stltopo::WriteOptions wo, bool formatGiven) {
  stltopo::Mesh mesh;
  stltopo::ReadOptions rdo;
  rdo.threads = ro.threads;
  stltopo::Status s = readFile(in, rdo, mesh);
  if (!s.ok()) return fail(in, s);
  stltopo::RepairPlan plan;
  s = stltopo::planRepair(mesh, ro, plan);
  if (!s.ok()) return fail(in, s);
  auto verdict = [](const stltopo::RepairFigures& f) {
    return f.stats.watertight && f.stats.manifold && f.selfIntersections != stltopo::kInvalid && f.solid ? 0 : 3;
  };
  // Prints the plan's or log's JSON with "file" (and "out") as its first keys, and a newline:
  // written as it is, not copied (a 1M-triangle soup's plan has 320 MB of JSON).
  auto printWithFile = [&](const std::string& json, const std::string& out) {
    std::string head = "{\"file\":" + stltopo::jsonString(in);
    if (!out.empty()) head += ",\"out\":" + stltopo::jsonString(out);
    head += json.size() > 2 ? "," : "}";
    std::fwrite(head.data(), 1, head.size(), stdout);
    if (json.size() > 2) std::fwrite(json.data() + 1, 1, json.size() - 1, stdout);
    std::fputc('\n', stdout);
  };
  if (outFile.empty()) {
    printWithFile(stltopo::repairPlanJson(plan), "");
    return verdict(plan.steps.empty() ? plan.before : plan.steps.back().after);
  }
  stltopo::TopologyOptions to;
  to.threads = ro.threads;
  stltopo::RepairLog log;
  stltopo::Mesh result;
  s = stltopo::applyRepair(mesh, plan, result, log, to);  // takes the plan's result (no second build)
  if (!s.ok()) return fail(in, s);
  if (!formatGiven) wo.format = mesh.format;
  std::signal(SIGXFSZ, SIG_IGN);
  Output out;
  s = out.open(outFile);
  if (s.ok()) s = out.close(stltopo::writeStl(result, Output::sink, &out, wo));
  if (!s.ok()) return fail(outFile, s);
  printWithFile(stltopo::repairLogJson(log), outFile);
  return verdict(log.after);
}

int repair(int argc, char** argv) {
  std::vector<std::string> files;
  stltopo::RepairOptions ro;
  ro.threads = 0;  // the default: the machine's cores (--threads)
  stltopo::WriteOptions wo;
  bool formatGiven = false, planOnly = false;
  auto usage = [](const std::string& msg) {
    std::fprintf(stderr, "stltopo: %s\n%s", msg.c_str(), kUsage);
    return 2;
  };
  for (int i = 2; i < argc; ++i) {
    std::string s = argv[i];
    if (s == "--") {
      files.insert(files.end(), argv + i + 1, argv + argc);
      break;
    }
    if (s.size() < 2 || s[0] != '-') {
      files.push_back(s);
      continue;
    }
    if (s == "--plan") {
      planOnly = true;
      continue;
    }
    if (s == "--remove-walls") {
      ro.removeOppositeDuplicates = true;
      continue;
    }
    if (s == "--no-intersections") {
      ro.intersections = false;
      continue;
    }
    if (s == "--ascii" || s == "--binary") {
      wo.format = s == "--ascii" ? stltopo::Format::Ascii : stltopo::Format::Binary;
      formatGiven = true;
      continue;
    }
    const bool takes = s == "--steps" || s == "--stitch-tolerance" || s == "--max-hole-edges" ||
                       s == "--max-hole-area" || s == "--max-hole-perimeter" || s == "--fill" ||
                       s == "--min-shell-triangles" || s == "--min-shell-volume" || s == "--exclude" ||
                       s == "--max-pairs" || s == "--threads" || s == "--test-parallel-grain";
    if (!takes) return usage("unknown option '" + s + "'");
    if (i + 1 >= argc) return usage(s + " needs a value");
    std::string v = argv[++i];
    double d = 0;
    unsigned long long n = 0;
    if (s == "--threads") {
      if (!countArg("--threads", v.c_str(), 1024, n)) return 2;
      ro.threads = unsigned(n);
    } else if (s == "--test-parallel-grain") {  // not in the usage, as for info
      if (!countArg("--test-parallel-grain", v.c_str(), ~0ull, n)) return 2;
      stltopo::setParallelGrainForTesting(size_t(n));
    } else if (s == "--steps") {
      ro.steps = 0;
      for (const std::string& n : splitList(v)) {
        stltopo::RepairStepKind k;
        if (!stltopo::repairStepFromName(n, k)) return usage("unknown repair step '" + n + "'");
        ro.steps |= stltopo::repairStepBit(k);
      }
    } else if (s == "--fill") {
      ro.fillRefine = ro.fillFair = false;
      for (const std::string& n : splitList(v)) {
        if (n == "refine")
          ro.fillRefine = true;
        else if (n == "fair")
          ro.fillFair = true;
        else if (n != "none")
          return usage("bad --fill '" + n + "' (refine, fair or none)");
      }
    } else if (s == "--exclude") {
      for (const std::string& n : splitList(v)) {
        size_t colon = n.rfind(':');
        stltopo::RepairStepKind k;
        if (colon == std::string::npos || !stltopo::repairStepFromName(n.substr(0, colon), k) ||
            !numberArg(n.substr(colon + 1), d, true, 4294967295.0))
          return usage("bad --exclude '" + n + "' (step:item, e.g. fill-holes:2)");
        ro.exclude.push_back({k, uint32_t(d)});
      }
    } else if (s == "--max-hole-edges" || s == "--min-shell-triangles") {
      if (!numberArg(v, d, true, 4294967295.0)) return usage("bad " + s + " '" + v + "' (a whole number)");
      (s == "--max-hole-edges" ? ro.maxHoleEdges : ro.minShellTriangles) = uint32_t(d);
    } else if (s == "--max-pairs") {
      if (!numberArg(v, d, true, 1099511627776.0) || d < 1) return usage("bad --max-pairs '" + v + "' (1 to 2^40)");
      ro.maxPairs = uint64_t(d);
    } else {
      if (!numberArg(v, d, false, 1e300)) return usage("bad " + s + " '" + v + "' (a number >= 0)");
      if (s == "--stitch-tolerance")
        ro.stitchTolerance = d;
      else if (s == "--max-hole-area")
        ro.maxHoleArea = d;
      else if (s == "--max-hole-perimeter")
        ro.maxHolePerimeter = d;
      else
        ro.minShellVolume = d;
    }
  }
  if (files.size() != (planOnly ? 1u : 2u) && files.size() != 2)
    return usage(planOnly ? "repair --plan needs IN" : "repair needs IN and OUT");
  const std::string& in = files[0];
  try {
    return repairFile(in, planOnly ? "" : files[1], ro, wo, formatGiven);
  } catch (const std::bad_alloc&) {
    // The plan's items and JSON are std::vector and std::string: a plan of millions of items
    // (a soup's holes) can exhaust the heap there.
    return fail(in, stltopo::Status::error(stltopo::Code::OutOfMemory, "out of memory while repairing " + in));
  }
}

// One malloc arena for the process. A stage's threads allocate little and seldom, but with an
// arena each (glibc's default) the blocks they free stay in their own arenas, away from the
// later arrays of the rest: `info --intersections` of the 1M shuffled torus peaked at 104.3 B a
// triangle on 2 threads and 120.5 on 16, against 100.1 and 107.5 with one arena, in the same
// time (bench/PROFILE.md, *Stop 58*). Called before any thread starts; not for `info --jobs N`,
// whose jobs allocate all the time and would queue for the one arena's lock.
void oneMallocArena() {
#if defined(__GLIBC__)
  mallopt(M_ARENA_MAX, 1);
#endif
}

int main(int argc, char** argv) {
#if defined(__GLIBC__)
  // Large arrays from the heap, and freed blocks kept there: a later array then reuses
  // pages that are already mapped (the weld table's for the topology's) instead of faulting
  // in fresh zeroed ones (bench/PROFILE.md has the measurement). glibc
  // still maps memory when the heap cannot grow.
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, kHeapTrimThreshold);
#endif
  Args a;
  if (argc < 2) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  std::string cmd = argv[1];
  if (cmd == "--help" || cmd == "-h" || cmd == "help") {
    std::fputs(kUsage, stdout);
    return 0;
  }
  if (cmd == "--version") {
    std::puts("stltopo 0.1.0");
    return 0;
  }
  if (cmd != "info") oneMallocArena();
  if (cmd == "convert") return convert(argc, argv);
  if (cmd == "split") return split(argc, argv);
  if (cmd == "repair") return repair(argc, argv);
  if (cmd != "info") {
    std::fprintf(stderr, "stltopo: unknown command '%s'\n%s", cmd.c_str(), kUsage);
    return 2;
  }
  bool endOfOptions = false;
  for (int i = 2; i < argc; ++i) {
    std::string s = argv[i];
    auto value = [&](const char* name) -> const char* {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "stltopo: %s needs a value\n", name);
        std::exit(2);
      }
      return argv[++i];
    };
    if (!endOfOptions && s == "--")
      endOfOptions = true;
    else if (!endOfOptions && s == "--json")
      a.json = true;
    else if (!endOfOptions && s == "--no-topology")
      a.topology = false;
    else if (!endOfOptions && s == "--shells")
      a.shells = true;
    else if (!endOfOptions && s == "--defects")
      a.defects = true;
    else if (!endOfOptions && s == "--intersections")
      a.intersections = true;
    else if (!endOfOptions && s == "--max-pairs") {
      const char* v = value("--max-pairs");
      if (!v) return 2;
      char* end = nullptr;
      unsigned long long n = std::strtoull(v, &end, 10);
      if (*end || !*v || *v == '-' || n == 0 || n > (1ull << 40)) {
        std::fprintf(stderr, "stltopo: bad --max-pairs '%s'\n", v);
        return 2;
      }
      a.maxPairs = n;
    } else if (!endOfOptions && s == "--max-defects") {
      const char* v = value("--max-defects");
      char* end;
      unsigned long long n = std::strtoull(v, &end, 10);
      if (*end || !*v || *v == '-' || n > 0xFFFFFFFFull) {
        std::fprintf(stderr, "stltopo: bad --max-defects '%s'\n", v);
        return 2;
      }
      a.maxDefects = int64_t(n);
    } else if (!endOfOptions && s == "--tolerance") {
      const char* v = value("--tolerance");
      char* end;
      a.tolerance = std::strtod(v, &end);
      if (*end || !(a.tolerance >= 0)) {
        std::fprintf(stderr, "stltopo: bad --tolerance '%s'\n", v);
        return 2;
      }
    } else if (!endOfOptions && s == "--max-triangles") {
      const char* v = value("--max-triangles");
      char* end;
      unsigned long long n = std::strtoull(v, &end, 10);
      if (*end || n == 0 || n > 0xFFFFFFFFull) {
        std::fprintf(stderr, "stltopo: bad --max-triangles '%s'\n", v);
        return 2;
      }
      a.maxTriangles = uint32_t(n);
    } else if (!endOfOptions && s == "--max-bytes") {
      const char* v = value("--max-bytes");
      char* end;
      unsigned long long n = std::strtoull(v, &end, 10);
      if (*end || n == 0) {
        std::fprintf(stderr, "stltopo: bad --max-bytes '%s'\n", v);
        return 2;
      }
      a.maxBytes = n;
    } else if (!endOfOptions && s == "--jobs") {
      const char* v = value("--jobs");
      char* end;
      unsigned long long n = std::strtoull(v, &end, 10);
      if (*end || !*v || *v == '-' || n == 0 || n > 256) {
        std::fprintf(stderr, "stltopo: bad --jobs '%s' (1 to 256)\n", v);
        return 2;
      }
      a.jobs = unsigned(n);
    } else if (!endOfOptions && s == "--max-memory") {
      const char* v = value("--max-memory");
      char* end;
      unsigned long long n = std::strtoull(v, &end, 10);  // past 2^64 - 1: that (no limit)
      if (*end || !*v || *v == '-' || n == 0) {
        std::fprintf(stderr, "stltopo: bad --max-memory '%s'\n", v);
        return 2;
      }
      a.maxMemory = n;
    } else if (!endOfOptions && s == "--test-jobs-log") {  // not in the usage: the tests' view of the gate
      a.jobsLog = true;
    } else if (!endOfOptions && s == "--list") {
      a.inputs.push_back({value("--list"), true});
    } else if (!endOfOptions && s == "--threads") {
      const char* v = value("--threads");
      unsigned long long n;
      if (!countArg("--threads", v, 1024, n)) return 2;
      a.threads = unsigned(n);
    } else if (!endOfOptions && s == "--test-parallel-grain") {
      // Not in the usage: the tests make every threaded stage split small files with it.
      const char* v = value("--test-parallel-grain");
      unsigned long long n;
      if (!countArg("--test-parallel-grain", v, ~0ull, n)) return 2;
      stltopo::setParallelGrainForTesting(size_t(n));
    } else if (!endOfOptions && s.size() > 1 && s[0] == '-') {
      std::fprintf(stderr, "stltopo: unknown option '%s'\n%s", s.c_str(), kUsage);
      return 2;
    } else {
      a.inputs.push_back({s, false});
    }
  }
  if (a.inputs.empty()) {
    std::fprintf(stderr, "stltopo: no input files\n%s", kUsage);
    return 2;
  }
  if (!a.topology && (a.shells || a.defects || a.intersections)) {
    std::fprintf(stderr, "stltopo: --shells, --defects and --intersections need the topology (not --no-topology)\n");
    return 2;
  }

  // The text report always lists the first few defects of each kind.
  const bool defects = a.defects || !a.json;

  // Standard input is read once: by one --list, or as one file, not both.
  size_t stdinLists = 0;
  bool stdinFile = false;
  for (const Args::Arg& in : a.inputs)
    if (in.path == "-") (in.list ? void(++stdinLists) : void(stdinFile = true));
  if (stdinLists > 1 || (stdinLists > 0 && stdinFile)) {
    std::fprintf(stderr, "stltopo: '--list -' reads standard input: no other input can\n");
    return 2;
  }
  std::vector<Input> inputs;
  for (const Args::Arg& in : a.inputs) {
    if (!in.list) {
      expand(in.path, inputs);
      continue;
    }
    std::string error = readList(in.path, inputs);
    if (!error.empty()) {
      std::fputs(error.c_str(), stderr);
      return 2;
    }
  }
  // '-' more than once: each reads what the one before left, so in order, on one thread.
  unsigned jobs = a.jobs;
  if (std::count_if(inputs.begin(), inputs.end(), [](const Input& in) { return in.path == "-"; }) > 1) jobs = 1;

  InfoConfig c;
  c.json = a.json;
  c.topology = a.topology;
  c.shells = a.shells;
  c.defects = defects;
  c.intersections = a.intersections;
  c.threads = a.threads;
  c.ro.maxTriangles = a.maxTriangles;
  c.ro.maxBytes = a.maxBytes;
  c.ro.threads = a.threads;
  c.to.threads = a.threads;
  c.io.threads = a.threads;
  c.to.tolerance = a.tolerance;
  c.to.prevAndFace = false;  // the report needs neither: 24 fewer bytes per triangle
  c.to.triangleShell = a.topology && (a.shells || defects || a.intersections);
  c.io.maxPairs = a.maxPairs;
  c.maxDefects = a.maxDefects >= 0 ? uint32_t(a.maxDefects) : a.json ? 1000 : 5;
  if (jobs <= 1 || inputs.size() <= 1) oneMallocArena();
  return reportAll(inputs, c, jobs, a.maxMemory ? a.maxMemory : defaultMemoryBudget(), a.jobsLog);
}
