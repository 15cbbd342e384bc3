// In-process stage timings through the C++ API (median of repetitions).
//   stltopo_stages FILE [REPS] [--json]
// Stages: read (parse + exact weld), topology (pairing + boundary loops + vertex loops),
// report (infoJson). The file is read into memory first, so no disk I/O is timed.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "stltopo.h"

using Clock = std::chrono::steady_clock;

static double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: stltopo_stages FILE [REPS] [--json]\n");
    return 2;
  }
  int reps = argc > 2 && argv[2][0] != '-' ? std::max(1, std::atoi(argv[2])) : 5;
  bool json = argc > 2 && !std::strcmp(argv[argc - 1], "--json");
  std::ifstream f(argv[1], std::ios::binary);
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  std::vector<double> tRead, tTopo, tReport, tTotal;
  uint32_t nt = 0;
  for (int r = 0; r < reps; ++r) {
    auto t0 = Clock::now();
    stltopo::Mesh mesh;
    stltopo::Status s = stltopo::readStl(bytes.data(), bytes.size(), mesh);
    auto t1 = Clock::now();
    if (!s.ok()) { std::fprintf(stderr, "%s\n", s.message.c_str()); return 1; }
    stltopo::Topology topo;
    s = stltopo::buildTopology(mesh, topo);
    auto t2 = Clock::now();
    if (!s.ok()) { std::fprintf(stderr, "%s\n", s.message.c_str()); return 1; }
    std::string j = stltopo::infoJson(argv[1], mesh, &topo);
    auto t3 = Clock::now();
    nt = mesh.nTriangles();
    auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
    tRead.push_back(ms(t0, t1));
    tTopo.push_back(ms(t1, t2));
    tReport.push_back(ms(t2, t3));
    tTotal.push_back(ms(t0, t3));
  }
  double total = median(tTotal);
  if (json) {
    std::printf("{\"triangles\":%u,\"readMs\":%.3f,\"topologyMs\":%.3f,\"reportMs\":%.3f,\"totalMs\":%.3f,\"trianglesPerSecond\":%.0f}\n",
                nt, median(tRead), median(tTopo), median(tReport), total, nt / (total / 1000));
  } else {
    std::printf("%s: %u triangles; read %.1f ms, topology %.1f ms, report %.2f ms, total %.1f ms (%.1f M tri/s)\n",
                argv[1], nt, median(tRead), median(tTopo), median(tReport), total, nt / total / 1000);
  }
  return 0;
}
