// Benchmark mesh generator: a torus grid as binary or ASCII STL.
//   genmesh TRIANGLES OUT.stl [--shuffle] [--holes] [--hole-count K] [--flip-percent P] [--ascii] [--seed S]
// The torus has n x m quads (2 triangles each) with n ~ 2m. --holes removes one quad in
// every 97 (separate holes); --hole-count K removes K quads spread evenly (K separate
// holes); --flip-percent P reverses P% of the triangles (every 100/P-th, deterministic);
// --shuffle permutes the triangle order (and rotates corners).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: genmesh TRIANGLES OUT.stl [--shuffle] [--holes] [--ascii] [--seed S]\n");
    return 2;
  }
  long long want = std::atoll(argv[1]);
  const char* out = argv[2];
  bool shuffle = false, holes = false, ascii = false;
  long long holeCount = 0;
  double flipPercent = 0;
  unsigned seed = 1;
  for (int i = 3; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--shuffle"))
      shuffle = true;
    else if (!std::strcmp(argv[i], "--holes"))
      holes = true;
    else if (!std::strcmp(argv[i], "--ascii"))
      ascii = true;
    else if (!std::strcmp(argv[i], "--hole-count") && i + 1 < argc)
      holeCount = std::atoll(argv[++i]);
    else if (!std::strcmp(argv[i], "--flip-percent") && i + 1 < argc)
      flipPercent = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--seed") && i + 1 < argc)
      seed = unsigned(std::atoi(argv[++i]));
  }
  int m = std::max(3, int(std::sqrt(double(want) / 4)));
  int n = std::max(3, int(want / 2 / m));
  const double pi = 3.14159265358979323846;
  std::vector<float> v(size_t(n) * m * 3);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      double u = 2 * pi * i / n, w = 2 * pi * j / m;
      float* p = &v[(size_t(i) * m + j) * 3];
      p[0] = float((3 + std::cos(w)) * std::cos(u));
      p[1] = float((3 + std::cos(w)) * std::sin(u));
      p[2] = float(std::sin(w));
    }
  std::vector<uint32_t> f;
  f.reserve(size_t(n) * m * 6);
  auto id = [&](int i, int j) { return uint32_t(((i + n) % n) * m + (j + m) % m); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      if (holes && (i * m + j) % 97 == 13 && i % 2 == 0) continue;
      // K holes: the quads at rows spread evenly over n, a column that moves along.
      if (holeCount > 0 && i % std::max(1, int(n / holeCount)) == 0 &&
          i / std::max(1, int(n / holeCount)) < holeCount && j == (i * 7) % m)
        continue;
      uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      f.insert(f.end(), {a, b, c, a, c, d});
    }
  size_t nt = f.size() / 3;
  if (flipPercent > 0) {
    size_t every = size_t(std::max(1.0, 100.0 / flipPercent));
    for (size_t t = every / 2; t < nt; t += every) std::swap(f[3 * t + 1], f[3 * t + 2]);
  }
  std::mt19937 rng(seed);
  if (shuffle) {
    for (size_t t = nt - 1; t > 0; --t) {
      size_t k = rng() % (t + 1);
      for (int c = 0; c < 3; ++c) std::swap(f[3 * t + c], f[3 * k + c]);
    }
    for (size_t t = 0; t < nt; ++t) {  // rotate corners: same triangle, other start
      int r = int(rng() % 3);
      uint32_t a = f[3 * t], b = f[3 * t + 1], c = f[3 * t + 2];
      if (r == 1) {
        f[3 * t] = b;
        f[3 * t + 1] = c;
        f[3 * t + 2] = a;
      }
      if (r == 2) {
        f[3 * t] = c;
        f[3 * t + 1] = a;
        f[3 * t + 2] = b;
      }
    }
  }
  FILE* o = std::fopen(out, "wb");
  if (!o) {
    std::perror(out);
    return 1;
  }
  if (ascii) {
    std::fprintf(o, "solid torus\n");
    for (size_t t = 0; t < nt; ++t) {
      std::fprintf(o, " facet normal 0 0 0\n  outer loop\n");
      for (int c = 0; c < 3; ++c) {
        const float* p = &v[size_t(f[3 * t + c]) * 3];
        std::fprintf(o, "   vertex %.9g %.9g %.9g\n", p[0], p[1], p[2]);
      }
      std::fprintf(o, "  endloop\n endfacet\n");
    }
    std::fprintf(o, "endsolid torus\n");
  } else {
    char header[80] = {0};
    std::snprintf(header, sizeof header, "stltopo benchmark torus %zu", nt);
    std::fwrite(header, 1, 80, o);
    uint32_t count = uint32_t(nt);
    std::fwrite(&count, 4, 1, o);
    std::vector<char> buf;
    buf.reserve(50 * 4096);
    for (size_t t = 0; t < nt; ++t) {
      char rec[50] = {0};
      for (int c = 0; c < 3; ++c) std::memcpy(rec + 12 + 12 * c, &v[size_t(f[3 * t + c]) * 3], 12);
      buf.insert(buf.end(), rec, rec + 50);
      if (buf.size() >= 50 * 4096) {
        std::fwrite(buf.data(), 1, buf.size(), o);
        buf.clear();
      }
    }
    std::fwrite(buf.data(), 1, buf.size(), o);
  }
  std::fclose(o);
  std::printf("%s: %zu triangles, %zu vertices\n", out, nt, v.size() / 3);
  return 0;
}
