// The Radiance .hdr reader (host/image/hdr_image.h): values decoded as the
// format defines them, flat and run-length rows alike; every cut-short file,
// every file that is not one and every absurd size refused in one line before
// anything large is allocated; the bytes charged to the memory budget; and
// the built-in neutral environment's shape.
#include <catch2/catch.hpp>

#include "host/image/hdr_image.h"
#include "tests/support/test_support.h"

#include <cmath>
#include <string>
#include <vector>

using namespace rast;

namespace {

std::vector<uint8_t> header(int w, int h, const std::string& format = "32-bit_rle_rgbe") {
  const std::string s = "#?RADIANCE\n# made by a test\nFORMAT=" + format + "\nEXPOSURE=1.0\n\n-Y " +
                        std::to_string(h) + " +X " + std::to_string(w) + "\n";
  return std::vector<uint8_t>(s.begin(), s.end());
}

// RGBE pixel x, y of a test pattern: varied mantissas, exponents 120..135.
std::vector<uint8_t> rgbe(int x, int y) {
  return {uint8_t(128 + (x * 7 + y) % 128), uint8_t(x < 4 ? 200 : 128 + y), uint8_t(128 + (x * y) % 100),
          uint8_t(120 + (x + y) % 16)};
}

std::vector<uint8_t> flatFile(int w, int h) {
  std::vector<uint8_t> f = header(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (uint8_t b : rgbe(x, y)) f.push_back(b);
  return f;
}

// The same pixels, each row run-length encoded by plane: runs where a value
// repeats (green's first four), literals elsewhere.
std::vector<uint8_t> rleFile(int w, int h) {
  std::vector<uint8_t> f = header(w, h);
  for (int y = 0; y < h; ++y) {
    f.insert(f.end(), {2, 2, uint8_t(w >> 8), uint8_t(w & 0xff)});
    for (int c = 0; c < 4; ++c) {
      std::vector<uint8_t> plane;
      for (int x = 0; x < w; ++x) plane.push_back(rgbe(x, y)[c]);
      int x = 0;
      while (x < w) {
        int run = 1;
        while (x + run < w && run < 127 && plane[x + run] == plane[x]) ++run;
        if (run >= 3) {
          f.push_back(uint8_t(128 + run));
          f.push_back(plane[x]);
          x += run;
        } else {
          int lit = 1;
          while (x + lit < w && lit < 128 && !(x + lit + 2 < w && plane[x + lit] == plane[x + lit + 1] &&
                                               plane[x + lit] == plane[x + lit + 2]))
            ++lit;
          f.push_back(uint8_t(lit));
          for (int k = 0; k < lit; ++k) f.push_back(plane[x + k]);
          x += lit;
        }
      }
    }
  }
  return f;
}

HdrImage decode(const std::vector<uint8_t>& f, MemoryLedger& ledger) { return decodeHdr(f.data(), f.size(), "t.hdr", ledger); }

std::string refusal(const std::vector<uint8_t>& f, uint64_t budget = uint64_t(1) << 30) {
  MemoryLedger ledger(budget);
  try {
    decode(f, ledger);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("hdr: flat and run-length rows decode to RGBE's values", "[hdr]") {
  const int w = 12, h = 3;
  MemoryLedger ledger;
  const HdrImage a = decode(flatFile(w, h), ledger);
  REQUIRE(a.width == w);
  REQUIRE(a.height == h);
  CHECK(ledger.used() == uint64_t(w) * h * 3 * sizeof(float));  // the decoded floats are charged
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::vector<uint8_t> p = rgbe(x, y);
      for (int c = 0; c < 3; ++c)  // mantissa * 2^(exponent - 136)
        CHECK(a.rgb[(size_t(y) * w + x) * 3 + c] == float(std::ldexp(double(p[c]), int(p[3]) - 136)));
    }
  MemoryLedger ledger2;
  const HdrImage b = decode(rleFile(w, h), ledger2);
  CHECK(b.rgb == a.rgb);
  // (128, 64, 32) at exponent 129: 1, 0.5, 0.25; exponent 0 is black.
  std::vector<uint8_t> f = header(2, 1);
  f.insert(f.end(), {128, 64, 32, 129, 255, 255, 255, 0});
  const HdrImage c = decode(f, ledger);
  CHECK(c.rgb == std::vector<float>{1.0f, 0.5f, 0.25f, 0.0f, 0.0f, 0.0f});
}

TEST_CASE("hdr: every cut-short file is refused in one line", "[hdr]") {
  for (const std::vector<uint8_t>& full : {flatFile(9, 4), rleFile(9, 4)}) {
    const size_t headerEnd = header(9, 4).size();
    for (size_t n = 0; n < full.size(); ++n) {
      const std::vector<uint8_t> cut(full.begin(), full.begin() + n);
      const std::string e = refusal(cut);
      INFO("first " << n << " bytes of " << full.size());
      REQUIRE(!e.empty());
      CHECK(e.find('\n') == std::string::npos);
      CHECK(e.find("t.hdr") != std::string::npos);
      if (n >= headerEnd) CHECK(e.find("truncated") != std::string::npos);
    }
  }
}

TEST_CASE("hdr: files that are not Radiance .hdr, or absurdly large, are refused before allocating", "[hdr]") {
  const std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13};
  CHECK(refusal(png).find("not a Radiance .hdr") != std::string::npos);
  CHECK(refusal({}).find("empty") != std::string::npos);
  CHECK(refusal(header(4, 4, "32-bit_rle_xyze")).find("32-bit_rle_xyze") != std::string::npos);
  std::string rot = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n+X 4 -Y 4\n";
  CHECK(refusal(std::vector<uint8_t>(rot.begin(), rot.end())).find("resolution") != std::string::npos);
  std::string noEnd = "#?RADIANCE\n" + std::string(70000, 'x');
  CHECK(refusal(std::vector<uint8_t>(noEnd.begin(), noEnd.end())).find("64 KiB") != std::string::npos);
  // Over the caps: refused from the header, with nothing charged.
  const std::vector<std::pair<int, int>> sizes = {{20000, 10}, {10, 20000}, {16384, 16384}, {0, 5}};
  for (const auto& wh : sizes) {
    MemoryLedger ledger;
    const std::vector<uint8_t> f = header(wh.first, wh.second);
    REQUIRE_THROWS_AS(decode(f, ledger), Error);
    CHECK(ledger.used() == 0);
    CHECK(refusal(f).find("texels") != std::string::npos);
  }
  // Within the caps but over the budget: BudgetExceeded, before decoding.
  const std::vector<uint8_t> big = header(8192, 4096);
  MemoryLedger small(64 << 20);
  CHECK_THROWS_AS(decode(big, small), BudgetExceeded);
  CHECK(small.used() == 0);
  // A run that overflows its row is corrupt, not a crash.
  std::vector<uint8_t> bad = header(8, 1);
  bad.insert(bad.end(), {2, 2, 0, 8, 128 + 9, 7});
  CHECK(refusal(bad).find("corrupt") != std::string::npos);
}

TEST_CASE("hdr: files on disk, and the shared environments", "[hdr]") {
  MemoryLedger ledger;
  CHECK_THROWS_AS(readHdr("/nonexistent/env.hdr", ledger), Error);
  CHECK_THROWS_AS(readHdr("/tmp", ledger), Error);
  const std::string sh = test::sharedDir();
  if (sh.empty()) return test::skipTest("../shared absent: the shared .hdr environments not read");
  for (const char* name : {"chinese_garden_1k.hdr", "qwantani_afternoon_puresky_1k.hdr"}) {
    MemoryLedger l;
    const HdrImage img = readHdr(sh + "/envs/" + name, l);
    CHECK(img.width == 1024);
    CHECK(img.height == 512);
    CHECK(l.used() == img.bytes());  // the file's bytes released, the floats kept
    float mx = 0.0f;
    for (float v : img.rgb) {
      REQUIRE(std::isfinite(v));
      mx = std::fmax(mx, v);
    }
    CHECK(mx > 1.0f);  // high dynamic range: the sun or sky is brighter than white
  }
}

TEST_CASE("hdr: the built-in neutral environment", "[hdr]") {
  const HdrImage e = neutralEnvironment();
  REQUIRE(e.width == 256);
  REQUIRE(e.height == 128);
  CHECK(e.name == kNeutralEnvironmentName);
  auto at = [&](int x, int y) { return e.rgb[(size_t(y) * e.width + x) * 3]; };
  float mx = 0.0f;
  for (size_t i = 0; i < e.rgb.size(); i += 3) {
    CHECK(e.rgb[i] == e.rgb[i + 1]);  // grey: no colour cast
    CHECK(e.rgb[i] == e.rgb[i + 2]);
    mx = std::fmax(mx, e.rgb[i]);
  }
  CHECK(at(0, 0) == Approx(0.5).margin(0.01));     // zenith
  CHECK(at(0, 60) == Approx(0.866).margin(0.01));  // just above the horizon
  CHECK(at(0, 127) == Approx(0.2).margin(0.001));  // floor
  CHECK(mx > 5.0f);                                 // the key light
}

TEST_CASE("hdr: damaged files decode or are refused, never more", "[hdr]") {
  // A fixed sequence of byte changes to a run-length file (the reader's
  // hardest path): each either decodes to the header's size or throws Error,
  // whose message is one line; none reads out of bounds (sanitizer builds)
  // or charges more than the header's texels.
  const std::vector<uint8_t> good = rleFile(40, 6);
  uint32_t seed = 12345;
  auto next = [&] { return seed = seed * 1664525u + 1013904223u; };
  int refused = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    std::vector<uint8_t> f = good;
    const int edits = 1 + int(next() % 4);
    for (int e = 0; e < edits; ++e) f[next() % f.size()] = uint8_t(next() >> 24);
    if (next() % 4 == 0) f.resize(next() % f.size());
    MemoryLedger ledger(uint64_t(1) << 30);
    try {
      const HdrImage img = decode(f, ledger);
      CHECK(img.rgb.size() == size_t(img.width) * img.height * 3);
      CHECK(ledger.used() == img.bytes());
    } catch (const Error& e) {
      ++refused;
      CHECK(std::string(e.what()).find('\n') == std::string::npos);
    }
  }
  CHECK(refused > 0);
}
