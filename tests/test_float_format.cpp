// The shortest round-trip decimals of the report and the ASCII writer: the exact integer
// path gives the same text as printing at increasing precision (the C library's printf
// and strtof, the definition), and every text reads back as the same float bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>

#include "float_format.h"

namespace {

using stltopo::detail::formatShortest;
using stltopo::detail::kMaxFloatChars;
using stltopo::detail::shortestByPrinting;

float fromBits(uint32_t b) {
  float f;
  std::memcpy(&f, &b, 4);
  return f;
}
uint32_t bitsOf(float f) {
  uint32_t b;
  std::memcpy(&b, &f, 4);
  return b;
}

// Checks one bit pattern; returns false (once reported) on a difference.
bool same(uint32_t b) {
  float f = fromBits(b);
  if (!std::isfinite(f)) return true;
  char buf[kMaxFloatChars];
  std::string fast(buf, formatShortest(f, buf));
  std::string ref = shortestByPrinting(double(f), true);
  EXPECT_EQ(fast, ref) << "bits 0x" << std::hex << b;
  EXPECT_EQ(bitsOf(std::strtof(fast.c_str(), nullptr)), b) << fast;
  return fast == ref;
}

TEST(FloatFormat, MatchesPrintingNearPowersOfTenAndTwo) {
  for (int p = -45; p <= 38; ++p) {
    uint32_t b = bitsOf(std::strtof(("1e" + std::to_string(p)).c_str(), nullptr));
    for (int d = -64; d <= 64; ++d)
      if (!same(b + uint32_t(d))) return;
  }
  for (uint32_t e = 0; e < 255; ++e)
    for (int d = -8; d <= 8; ++d)
      if (!same((e << 23) + uint32_t(d))) return;
}

TEST(FloatFormat, MatchesPrintingOnRandomFloatsAndTheEnds) {
  std::mt19937 rng(12345);
  for (int i = 0; i < 100000; ++i)
    if (!same(rng())) return;
  for (uint32_t b = 0; b < 5000; ++b)
    if (!same(b) || !same(0x7f7fffffu - b) || !same(0x80000000u | (0x3f800000u + b))) return;
}

TEST(FloatFormat, TypicalCoordinatesAndSpecialValues) {
  char buf[kMaxFloatChars];
  auto text = [&](float f) { return std::string(buf, formatShortest(f, buf)); };
  EXPECT_EQ(text(0.1f), "0.1");
  EXPECT_EQ(text(-12.5f), "-12.5");
  EXPECT_EQ(text(1e20f), "100000000000000000000");
  EXPECT_EQ(text(1e21f), "1e+21");
  EXPECT_EQ(text(1.5e-7f), "0.00000015");
  EXPECT_EQ(text(1.5e-8f), "1.5e-8");
  EXPECT_EQ(text(3.4028235e38f), "3.4028235e+38");
  EXPECT_EQ(text(1e-45f), "1e-45");
  EXPECT_EQ(text(-0.0f), "-0");
  EXPECT_EQ(text(0.0f), "0");
  EXPECT_EQ(text(INFINITY), "inf");
  EXPECT_EQ(text(-INFINITY), "-inf");
  EXPECT_EQ(text(NAN), "nan");
  EXPECT_LE(text(-1.00000012e-38f).size(), kMaxFloatChars);
  EXPECT_LE(text(-1.17549435e-7f).size(), kMaxFloatChars);
}

}  // namespace
