// In-process stage timings through the C++ API.
//   stltopo_stages FILE [REPS] [--json] [--threads N] [--tolerance D]
// --threads N: ReadOptions/TopologyOptions::threads (default 1; 0 = the machine's cores).
// --tolerance D: TopologyOptions::tolerance (the tolerance weld runs inside the topology
// stage; bench/weld.mjs compares it with the exact weld of the read stage).
// Stages: read (readStl: parse + exact weld), topology (buildTopology: pairing, boundary
// loops, vertex loops, shells), report (infoJson: the stats; with --threads other than 1, after
// checkTriangles on the threads, as the CLI does). The file is read into memory
// first, so no disk I/O is timed. Repetition 1 is the "first" call (fresh allocations, page
// faults); "warm" is the median of repetitions 2..REPS; the plain fields are the median of
// all repetitions. cpuMs: process CPU time of read + topology + report (unaffected by
// waiting for a busy core). rssKiB: peak RSS before the first call and after it (getrusage).
//   stltopo_stages FILE --streamed-peak
// instead streams FILE through a Reader in 1 MiB chunks, builds the full topology (prev
// and face included) and the report once, and prints the peak RSS above the RSS before
// the read, as JSON: the memory of the full topology with the input streamed.
//   stltopo_stages FILE --weld D [REPS]
// instead times the tolerance weld (tolerance D) against the exact weld, interleaved (see
// weldSpeed), and prints JSON with the median ratio: what bench/weld.mjs reports.
//   stltopo_stages FILE --intersections THREADS [REPS]
// instead times the intersection pass on one thread against THREADS threads, alternated in
// one process (see intersectionSpeed), and prints JSON with the median speed-up.
//   stltopo_stages FILE --paired THREADS [PAIRS]
// instead times the whole pipeline above on one thread against THREADS threads, alternated
// call by call in one process (PAIRS pairs, default 9; see pairedSpeed), and prints JSON with
// the median of the pairs' ratios: the threads' speed-up that bench/threads.mjs reports.
//   stltopo_stages FILE --write [REPS]
// instead reads FILE once and writes the mesh as binary and as ASCII STL through writeStl
// REPS times (default 5) into a sink that only counts the bytes, and prints the median
// times and speeds (MB/s of output, 1 MB = 10^6 bytes) as JSON.
#include <sys/resource.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "stltopo/stltopo.h"

using Clock = std::chrono::steady_clock;

// Milliseconds from a to b.
static double msBetween(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// The whole file at path into bytes; false (the message printed) when it cannot be opened.
static bool readBytes(const char* path, std::vector<uint8_t>& bytes) {
  std::ifstream f(path, std::ios::binary);
  if (!f) {
    std::fprintf(stderr, "cannot open %s\n", path);
    return false;
  }
  bytes.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  return true;
}

static double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  if (v.empty()) return 0;
  size_t n = v.size();
  return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

static double cpuMs() {  // CPU time of the process: immune to waiting for a busy core
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

static long maxRssKiB() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_maxrss;
}

struct Times {
  std::vector<double> read, topo, report, total, cpu;
  void add(double a, double b, double c, double cpuMs) {
    cpu.push_back(cpuMs);
    read.push_back(a);
    topo.push_back(b);
    report.push_back(c);
    total.push_back(a + b + c);
  }
};

// Medians over repetitions [from, to).
static std::string jsonStages(const Times& t, size_t from, size_t to, uint32_t nt) {
  auto slice = [&](const std::vector<double>& v) {
    return std::vector<double>(v.begin() + long(from), v.begin() + long(to));
  };
  double total = median(slice(t.total));
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "{\"readMs\":%.3f,\"topologyMs\":%.3f,\"reportMs\":%.3f,\"totalMs\":%.3f,\"cpuMs\":%.3f,"
                "\"trianglesPerSecond\":%.0f}",
                median(slice(t.read)), median(slice(t.topo)), median(slice(t.report)), total, median(slice(t.cpu)),
                total > 0 ? nt / (total / 1000) : 0.0);
  return buf;
}

static long currentRssKiB() {
  long pages = 0, resident = 0;
  FILE* f = std::fopen("/proc/self/statm", "r");
  if (!f) return 0;
  if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
  std::fclose(f);
  return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

static int streamedPeak(const char* path) {
  FILE* f = std::fopen(path, "rb");
  if (!f) {
    std::fprintf(stderr, "cannot open %s\n", path);
    return 1;
  }
  std::vector<uint8_t> buf(1 << 20);
  long before = currentRssKiB();
  stltopo::Reader reader;
  stltopo::Status s;
  for (size_t n; s.ok() && (n = std::fread(buf.data(), 1, buf.size(), f)) > 0;) s = reader.feed(buf.data(), n);
  std::fclose(f);
  stltopo::Mesh mesh;
  if (s.ok()) s = reader.finish(mesh);
  stltopo::Topology topo;
  if (s.ok()) s = stltopo::buildTopology(mesh, topo);  // prevAndFace = true: the full topology
  if (!s.ok()) {
    std::fprintf(stderr, "%s\n", s.message.c_str());
    return 1;
  }
  std::string j = stltopo::infoJson(path, mesh, &topo);
  long peak = maxRssKiB();
  std::printf("{\"triangles\":%u,\"rssBeforeKiB\":%ld,\"peakRssKiB\":%ld,\"halfedges\":%u,\"reportBytes\":%zu}\n",
              mesh.nTriangles(), before, peak, topo.nHalfedges(), j.size());
  return 0;
}

static int writeSpeed(const char* path, int reps) {
  std::vector<uint8_t> bytes;
  if (!readBytes(path, bytes)) return 1;
  stltopo::Mesh mesh;
  stltopo::Status s = stltopo::readStl(bytes.data(), bytes.size(), mesh);
  if (!s.ok()) {
    std::fprintf(stderr, "%s\n", s.message.c_str());
    return 1;
  }
  std::string out = "{\"triangles\":" + std::to_string(mesh.nTriangles());
  for (stltopo::Format format : {stltopo::Format::Binary, stltopo::Format::Ascii}) {
    stltopo::WriteOptions o;
    o.format = format;
    std::vector<double> ms;
    uint64_t written = 0;
    for (int r = 0; r < reps; ++r) {
      written = 0;
      auto t0 = Clock::now();
      s = stltopo::writeStl(
          mesh,
          [](void* user, const uint8_t*, size_t n) {
            *static_cast<uint64_t*>(user) += n;
            return true;
          },
          &written, o);
      ms.push_back(msBetween(t0, Clock::now()));
      if (!s.ok()) {
        std::fprintf(stderr, "%s\n", s.message.c_str());
        return 1;
      }
    }
    double m = median(ms);
    char buf[200];
    std::snprintf(buf, sizeof buf, ",\"%s\":{\"bytes\":%llu,\"ms\":%.3f,\"mbPerSecond\":%.1f}",
                  format == stltopo::Format::Binary ? "binary" : "ascii", (unsigned long long)written, m,
                  m > 0 ? written / 1e3 / m : 0.0);
    out += buf;
  }
  std::printf("%s,\"reps\":%d}\n", out.c_str(), reps);
  return 0;
}

// The tolerance weld against the exact weld (issue 24): per repetition, in this order, the
// read (parse + exact weld; a binary file's parse is a copy of floats, so this is the exact
// weld's time), the topology with the exact weld, and the topology with `--tolerance D`:
// the tolerance weld costs the difference of the two topologies. Interleaved in one process,
// so that a machine's drift moves both; prints the medians and the median ratio as JSON.
static int weldSpeed(const char* path, double tol, int reps) {
  std::vector<uint8_t> bytes;
  if (!readBytes(path, bytes)) return 1;
  std::vector<double> read, topo, topoTol, weld, ratio;
  uint32_t nt = 0, nv = 0, welded = 0;
  for (int r = 0; r < reps + 1; ++r) {  // repetition 0 warms up, not counted
    auto t0 = Clock::now();
    stltopo::Mesh mesh;
    stltopo::Status s = stltopo::readStl(bytes.data(), bytes.size(), mesh);
    auto t1 = Clock::now();
    stltopo::Topology exact, tolerant;
    if (s.ok()) s = stltopo::buildTopology(mesh, exact);
    auto t2 = Clock::now();
    stltopo::TopologyOptions to;
    to.tolerance = tol;
    if (s.ok()) s = stltopo::buildTopology(mesh, tolerant, to);
    auto t3 = Clock::now();
    if (!s.ok()) {
      std::fprintf(stderr, "%s\n", s.message.c_str());
      return 1;
    }
    nt = mesh.nTriangles();
    nv = mesh.nVertices();
    welded = tolerant.nWeldedVertices;
    if (r == 0) continue;
    read.push_back(msBetween(t0, t1));
    topo.push_back(msBetween(t1, t2));
    topoTol.push_back(msBetween(t2, t3));
    weld.push_back(msBetween(t2, t3) - msBetween(t1, t2));
    ratio.push_back(weld.back() / read.back());
  }
  std::printf(
      "{\"file\":\"%s\",\"triangles\":%u,\"vertices\":%u,\"weldedVertices\":%u,\"tolerance\":%g,\"reps\":%d,"
      "\"readMs\":%.2f,\"topologyMs\":%.2f,\"topologyToleranceMs\":%.2f,\"toleranceWeldMs\":%.2f,"
      "\"toleranceWeldOverExactWeld\":%.3f}\n",
      path, nt, nv, welded, tol, reps, median(read), median(topo), median(topoTol), median(weld), median(ratio));
  return 0;
}

// Times of one thread against several, taken in pairs: each pair's ratio (one / several).
struct PairedTimes {
  std::vector<double> one, many, ratio;
  void add(double a, double b) {
    one.push_back(a);
    many.push_back(b);
    ratio.push_back(a / b);
  }
};

// The intersection pass (findIntersections) on 1 thread against `threads` threads,
// alternated in one process after one warm-up call of each; prints JSON with the medians (and
// the first one-thread call, passFirstMs: the fresh pages a single call in a process pays),
// the median of the per-repetition ratios and the pass against the read + topology it
// follows (info's own work, one thread).
static int intersectionSpeed(const char* path, unsigned threads, int reps) {
  std::vector<uint8_t> bytes;
  if (!readBytes(path, bytes)) return 1;
  std::vector<double> load;
  PairedTimes p;
  double firstCall = 0;  // the process's first call (one thread): fresh pages, as CGAL's one call
  uint64_t pairs = 0;
  uint32_t nt = 0;
  for (int r = 0; r < reps + 1; ++r) {  // repetition 0 warms up, not counted
    auto t0 = Clock::now();
    stltopo::Mesh mesh;
    stltopo::Status s = stltopo::readStl(bytes.data(), bytes.size(), mesh);
    stltopo::Topology topo;
    if (s.ok()) s = stltopo::buildTopology(mesh, topo);
    stltopo::TriangleChecks checks;
    if (s.ok()) s = stltopo::checkTriangles(mesh, &topo, checks, 1);
    auto t1 = Clock::now();
    double t[2] = {0, 0};
    for (int k = 0; k < 2 && s.ok(); ++k) {
      const bool first = (r + k) % 2 == 0;  // alternate which goes first
      stltopo::IntersectionOptions io;
      io.threads = first ? 1 : threads;
      stltopo::Intersections found;
      auto a = Clock::now();
      s = stltopo::findIntersections(mesh, topo, checks, found, io);
      t[first ? 0 : 1] = msBetween(a, Clock::now());
      pairs = found.nPairs();
    }
    if (!s.ok()) {
      std::fprintf(stderr, "%s\n", s.message.c_str());
      return 1;
    }
    nt = mesh.nTriangles();
    if (r == 0) firstCall = t[0];
    if (r == 0) continue;
    load.push_back(msBetween(t0, t1));
    p.add(t[0], t[1]);
  }
  std::printf(
      "{\"file\":\"%s\",\"triangles\":%u,\"pairs\":%llu,\"threads\":%u,\"reps\":%d,\"loadMs\":%.2f,"
      "\"passOneThreadMs\":%.2f,\"passFirstMs\":%.2f,\"passThreadsMs\":%.2f,\"speedup\":%.3f}\n",
      path, nt, (unsigned long long)pairs, threads, reps, median(load), median(p.one), firstCall, median(p.many),
      median(p.ratio));
  return 0;
}

// What a pipeline call found (the JSON's counts).
struct Counts {
  uint32_t nt = 0, nv = 0, holes = 0, edges = 0, boundaryEdges = 0, shells = 0;
};

// One call of the pipeline the stages time: readStl, buildTopology, and the report as the CLI
// makes it (with threads, the triangle checks on the threads first, as tools/cli.cpp does; on
// one thread, inside infoJson). The stages' times (ms) to ms[0..2], the counts to *c; false
// (the message printed) on a failure.
static bool pipeline(const std::vector<uint8_t>& bytes, const char* path, unsigned threads, double tolerance,
                     double ms[3], Counts* c) {
  stltopo::ReadOptions ro;
  ro.threads = threads;
  stltopo::TopologyOptions to;
  to.threads = threads;
  to.tolerance = tolerance;
  auto t0 = Clock::now();
  stltopo::Mesh mesh;
  stltopo::Status s = stltopo::readStl(bytes.data(), bytes.size(), mesh, ro);
  auto t1 = Clock::now();
  stltopo::Topology topo;
  if (s.ok()) s = stltopo::buildTopology(mesh, topo, to);
  auto t2 = Clock::now();
  if (!s.ok()) {
    std::fprintf(stderr, "%s\n", s.message.c_str());
    return false;
  }
  std::string j;
  if (threads != 1) {
    stltopo::TriangleChecks checks;
    stltopo::ReportExtras extras;
    if (stltopo::checkTriangles(mesh, &topo, checks, threads).ok()) extras.checks = &checks;
    j = stltopo::infoJson(path, mesh, &topo, extras);
  } else {
    j = stltopo::infoJson(path, mesh, &topo);
  }
  auto t3 = Clock::now();
  ms[0] = msBetween(t0, t1);
  ms[1] = msBetween(t1, t2);
  ms[2] = msBetween(t2, t3);
  *c = Counts{mesh.nTriangles(), mesh.nVertices(), topo.nHoles, topo.nEdges, topo.nBoundaryEdges, topo.nShells};
  return true;
}

// The pipeline on one thread against `threads` threads, alternated call by call in one
// process (which goes first alternates too), after one call of each not counted. Prints JSON
// with the medians of the two and of the pairs' ratios (one thread / threads), and the ratios'
// range. On a machine whose speed drifts from one process to the next, the pairs' ratio is
// the figure to trust for the threads' speed-up (bench/threads.mjs reports it).
static int pairedSpeed(const char* path, unsigned threads, int pairs) {
  std::vector<uint8_t> bytes;
  if (!readBytes(path, bytes)) return 1;
  PairedTimes p;
  Counts c;
  for (int r = 0; r < pairs + 1; ++r) {  // pair 0 warms up, not counted
    double t[2] = {0, 0};
    for (int k = 0; k < 2; ++k) {
      const bool single = (r + k) % 2 == 0;
      double ms[3];
      if (!pipeline(bytes, path, single ? 1 : threads, 0, ms, &c)) return 1;
      t[single ? 0 : 1] = ms[0] + ms[1] + ms[2];
    }
    if (r > 0) p.add(t[0], t[1]);
  }
  std::printf(
      "{\"file\":\"%s\",\"triangles\":%u,\"threads\":%u,\"reps\":%d,\"oneThreadMs\":%.2f,\"threadsMs\":%.2f,"
      "\"speedup\":%.3f,\"speedupMin\":%.3f,\"speedupMax\":%.3f}\n",
      path, c.nt, threads, pairs, median(p.one), median(p.many), median(p.ratio),
      *std::min_element(p.ratio.begin(), p.ratio.end()), *std::max_element(p.ratio.begin(), p.ratio.end()));
  return 0;
}

int main(int argc, char** argv) {
  // With the C library's default allocation (each large array mapped and unmapped on its
  // own), the peak is that of the live arrays.
  if (argc > 2 && !std::strcmp(argv[2], "--streamed-peak")) return streamedPeak(argv[1]);
  if (argc > 2 && !std::strcmp(argv[2], "--write"))
    return writeSpeed(argv[1], argc > 3 ? std::max(1, std::atoi(argv[3])) : 5);
  if (argc > 3 && !std::strcmp(argv[2], "--intersections"))
    return intersectionSpeed(argv[1], unsigned(std::atoi(argv[3])), argc > 4 ? std::max(1, std::atoi(argv[4])) : 7);
  if (argc > 3 && !std::strcmp(argv[2], "--weld"))
    return weldSpeed(argv[1], std::atof(argv[3]), argc > 4 ? std::max(1, std::atoi(argv[4])) : 7);
#if defined(__GLIBC__)
  // Warm calls reuse the memory of the calls before them, as the wasm heap does (linear
  // memory is never given back) and as the CLI does: glibc would otherwise unmap every
  // large array when it is freed and map fresh, zeroed pages for the next call, and on a
  // VM with free page reporting each of those first touches costs a host page fault
  // (seen here: +/-50 % on the shuffled topology from one call to the next).
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
  if (argc > 3 && !std::strcmp(argv[2], "--paired"))
    return pairedSpeed(argv[1], unsigned(std::atoi(argv[3])), argc > 4 ? std::max(1, std::atoi(argv[4])) : 9);
  if (argc < 2) {
    std::fprintf(stderr, "usage: stltopo_stages FILE [REPS] [--json]\n");
    return 2;
  }
  int reps = argc > 2 && argv[2][0] != '-' ? std::max(1, std::atoi(argv[2])) : 5;
  bool json = false;
  unsigned threads = 1;
  double tolerance = 0;
  for (int i = 2; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--json")) json = true;
    if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) threads = unsigned(std::atoi(argv[++i]));
    if (!std::strcmp(argv[i], "--tolerance") && i + 1 < argc) tolerance = std::atof(argv[++i]);
  }
  std::vector<uint8_t> bytes;
  if (!readBytes(argv[1], bytes)) return 1;
  Times t;
  Counts c;
  long rssBefore = maxRssKiB(), rssAfterFirst = 0;
  for (int r = 0; r < reps; ++r) {
    double c0 = cpuMs(), ms[3];
    if (!pipeline(bytes, argv[1], threads, tolerance, ms, &c)) return 1;
    double c1 = cpuMs();
    if (r == 0) rssAfterFirst = maxRssKiB();
    t.add(ms[0], ms[1], ms[2], c1 - c0);
  }
  if (json) {
    size_t n = t.total.size();
    std::string all = jsonStages(t, 0, n, c.nt);
    all.pop_back();  // merge the all-repetitions medians into the top-level object
    std::printf(
        "%s,\"triangles\":%u,\"vertices\":%u,\"edges\":%u,\"boundaryEdges\":%u,\"holes\":%u,\"shells\":%u,"
        "\"reps\":%d,\"first\":%s,\"warm\":%s,\"rssKiB\":{\"beforeFirst\":%ld,\"afterFirst\":%ld},"
        "\"inputBytes\":%zu}\n",
        all.c_str(), c.nt, c.nv, c.edges, c.boundaryEdges, c.holes, c.shells, reps, jsonStages(t, 0, 1, c.nt).c_str(),
        reps > 1 ? jsonStages(t, 1, n, c.nt).c_str() : "null", rssBefore, rssAfterFirst, bytes.size());
  } else {
    double total = median(t.total);
    std::printf("%s: %u triangles; read %.1f ms, topology %.1f ms, report %.2f ms, total %.1f ms (%.1f M tri/s)\n",
                argv[1], c.nt, median(t.read), median(t.topo), median(t.report), total, c.nt / total / 1000);
  }
  return 0;
}
