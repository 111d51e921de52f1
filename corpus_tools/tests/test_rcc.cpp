// The Qt resource bundle reader against bundles made by a small writer: both node sizes, nested
// directories, stored/zlib/zstd entries, UTF-16 names, and corrupt or truncated input.
#include <gtest/gtest.h>

#include <map>
#include <random>

#include "rcc.hpp"
#include "rcc_writer.hpp"

namespace test_rcc {

using namespace tagbench::corpus;
using rcctest::Pack;

namespace {

std::string noise(std::size_t n, unsigned seed) {
  std::mt19937 g(seed);
  std::string s(n, '\0');
  for (auto& c : s) c = static_cast<char>(g());
  return s;
}

rcctest::Writer sample() {
  rcctest::Writer w;
  w.add("top.txt", "hello");
  w.add("gcompris/src/activities/categorization/resource/fish1.webp", noise(3000, 1), Pack::zlib);
  w.add("gcompris/src/activities/categorization/resource/fish2.webp", std::string(5000, 'x'), Pack::zstd);
  w.add("gcompris/src/activities/categorization/resource/deep/er/file.bin", noise(17, 2));
  w.add("gcompris/src/other/caf\xc3\xa9.txt", "utf16 name");  // "café"
  w.add("gcompris/empty.bin", "");
  return w;
}

std::map<std::string, std::string> as_map(const std::vector<RccEntry>& e) {
  std::map<std::string, std::string> m;
  for (const auto& x : e) m[x.path] = x.data;
  return m;
}

}  // namespace

TEST(Rcc, ReadsEveryVersionAndEntryKind) {
  for (const std::uint32_t version : {1u, 2u, 3u}) {
    const auto bytes = sample().bytes(version);
    RccArchive a(bytes, "sample.rcc");
    EXPECT_EQ(a.version(), version);
    const auto m = as_map(a.entries());
    ASSERT_EQ(m.size(), 6u) << "version " << version;
    EXPECT_EQ(m.at("/top.txt"), "hello");
    EXPECT_EQ(m.at("/gcompris/src/activities/categorization/resource/fish1.webp"), noise(3000, 1));
    EXPECT_EQ(m.at("/gcompris/src/activities/categorization/resource/fish2.webp"), std::string(5000, 'x'));
    EXPECT_EQ(m.at("/gcompris/src/activities/categorization/resource/deep/er/file.bin"), noise(17, 2));
    EXPECT_EQ(m.at("/gcompris/src/other/caf\xc3\xa9.txt"), "utf16 name");
    EXPECT_EQ(m.at("/gcompris/empty.bin"), "");
    EXPECT_EQ(a.read("/top.txt"), std::optional<std::string>("hello"));
    EXPECT_FALSE(a.read("/nope").has_value());
    EXPECT_FALSE(a.read("top.txt").has_value());  // paths carry the leading slash
  }
}

TEST(Rcc, NodeSizeMatters) {
  // A version 2 bundle relabelled as version 1 is read with 14-byte nodes: it must not come out right.
  auto bytes = sample().bytes(2);
  bytes[7] = 1;
  try {
    const auto m = as_map(RccArchive(bytes, "relabelled.rcc").entries());
    EXPECT_NE(m.count("/top.txt") ? m.at("/top.txt") : "", "hello");
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("relabelled.rcc"), std::string::npos);
  }
}

TEST(Rcc, CorruptInputIsAOneLineErrorNamingTheFile) {
  auto expect_error = [](const std::string& bytes, const std::string& fragment) {
    try {
      RccArchive a(bytes, "bad.rcc");
      a.entries();
      ADD_FAILURE() << "no error for: " << fragment;
    } catch (const std::runtime_error& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind("bad.rcc: ", 0), 0u) << m;
      EXPECT_NE(m.find(fragment), std::string::npos) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  };
  const auto good = sample().bytes(3);
  expect_error("", "magic");
  expect_error("qrex" + good.substr(4), "magic");
  expect_error(good.substr(0, 12), "header");
  auto v = good;
  v[7] = 9;
  expect_error(v, "version 9");
  // Every truncation fails cleanly (never a crash, never a silent short read).
  for (std::size_t n = 0; n < good.size(); n += 7) {
    try {
      RccArchive(good.substr(0, n), "bad.rcc").entries();
      ADD_FAILURE() << "truncated to " << n << " bytes was accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("bad.rcc: ", 0), 0u);
    }
  }
  // Offsets pointing outside the file.
  for (const std::size_t field : {8u, 12u, 16u}) {
    auto b = good;
    rcctest::set32(b, field, 0xFFFFFF00u);
    expect_error(b, "past the end");
  }
  // A directory that contains itself.
  {
    auto b = good;
    const std::uint32_t tree = (static_cast<unsigned char>(b[8]) << 24) | (static_cast<unsigned char>(b[9]) << 16) |
                               (static_cast<unsigned char>(b[10]) << 8) | static_cast<unsigned char>(b[11]);
    rcctest::set32(b, tree + 10, 0);  // root's first child = root
    expect_error(b, "cycle");
  }
  // Every single-byte corruption either reads or fails with the one-line error; never crashes.
  std::mt19937 g(7);
  for (int i = 0; i < 2000; ++i) {
    auto b = good;
    b[g() % b.size()] = static_cast<char>(g());
    try {
      RccArchive(b, "bad.rcc").entries();
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
  }
}

TEST(Rcc, CorruptCompressedData) {
  rcctest::Writer w;
  w.add("z.bin", noise(2000, 3), Pack::zlib);
  auto b = w.bytes(1);
  // The zlib stream starts at data offset + 8 (size field, uncompressed-size field); damage it.
  const std::size_t data = 20 + 8;
  for (std::size_t i = data + 2; i < data + 40; ++i) b[i] = static_cast<char>(~b[i]);
  try {
    RccArchive(b, "z.rcc").entries();
    ADD_FAILURE() << "corrupt zlib accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("z.bin"), std::string::npos) << e.what();
  }
  rcctest::Writer w2;
  w2.add("s.bin", noise(2000, 4), Pack::zstd);
  auto b2 = w2.bytes(2);
  b2[20 + 4] = 0;  // break the zstd magic
  try {
    RccArchive(b2, "s.rcc").entries();
    ADD_FAILURE() << "corrupt zstd accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("s.bin"), std::string::npos) << e.what();
  }
}

// A zlib entry's uncompressed size is a header field; a size its data cannot inflate to (deflate
// expands at most 1032:1) is refused before anything that size is allocated (fuzz finding: a
// 200-byte bundle stating 2 GB made the reader allocate and clear 2 GB first).
TEST(Rcc, ZlibStatedSizeBeyondItsData) {
  rcctest::Writer w;
  w.add("z.bin", std::string(200, 'z'), Pack::zlib);
  auto b = w.bytes(1);
  const std::size_t stated = 20 + 4;  // after the header (20 bytes) and the entry's u32 data size
  for (std::size_t i = 0; i < 4; ++i) b[stated + i] = static_cast<char>(i == 0 ? 0x7f : 0xff);
  try {
    RccArchive(b, "z.rcc").entries();
    ADD_FAILURE() << "a zlib entry stating 2 GB from a few bytes was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("z.bin: zlib entry claims 2147483647 bytes"), std::string::npos) << e.what();
  }
  // The largest size the data could hold is still read normally when true.
  rcctest::Writer ok;
  ok.add("big.bin", std::string(100000, '\0'), Pack::zlib);
  EXPECT_EQ(RccArchive(ok.bytes(1), "ok.rcc").read("/big.bin"), std::string(100000, '\0'));
}

}  // namespace test_rcc
