// SHA-256 (FIPS 180-4 vectors), the lists and manifest formats, and scanning a user's folder.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <opencv2/imgcodecs.hpp>

#include "build.hpp"
#include "scan.hpp"
#include "sha256.hpp"
#include "sources.hpp"

namespace test_corpus {

namespace fs = std::filesystem;
using namespace tagbench::corpus;

TEST(Sha256, Fips180Vectors) {
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  const std::string million(1000000, 'a');
  EXPECT_EQ(sha256_hex(million), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  const fs::path f = fs::path(::testing::TempDir()) / ("sha_" + std::to_string(::getpid()));
  std::ofstream(f, std::ios::binary) << million;
  EXPECT_EQ(sha256_file(f), sha256_hex(million));  // streamed in chunks, same digest
  fs::remove(f);
  EXPECT_THROW(sha256_file(f), std::runtime_error);
}

TEST(Sources, ShippedListsParse) {
  const auto s = load_sources(default_lists_dir());
  std::size_t stills = 0, videos = 0, rcc = 0;
  for (const auto& x : s) {
    (x.is_video() ? videos : stills)++;
    rcc += x.path.rfind("/_rcc/", 0) == 0;
  }
  EXPECT_EQ(stills, 872u);
  EXPECT_EQ(videos, 11u);
  EXPECT_GT(rcc, 200u);
}

TEST(Sources, BadRowsAreNamed) {
  const std::string h = "group\tdebian_package\tversion\tpath_in_package\tframe_step\tlicense\n";
  EXPECT_EQ(parse_sources(h + "g\tp\t1:2.0-1\t/a/b.avi\t5\tMIT\n", "v.tsv").at(0).frame_step, 5);
  for (const std::string row : {"g\tp\t1\t/a.avi\t0\tMIT", "g\tp\t1\t/a.avi\tx\tMIT", "g\tp\t1\ta.avi\t3\tMIT",
                                "g\tp\t1\t/a.avi\t3", "g\tp\t1\t/x/../../a.avi\t3\tMIT"}) {
    try {
      parse_sources(h + row + "\n", "v.tsv");
      ADD_FAILURE() << row;
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("v.tsv:2: ", 0), 0u) << e.what();
    }
  }
  EXPECT_EQ(deb_file_prefix("kalzium-data", "4:22.12.3-1"), "kalzium-data_4%3a22.12.3-1_");
}

TEST(Manifest, RoundTrip) {
  const std::vector<ManifestRow> rows = {
      {"stills/g/a.png", "g", "pkg", "1:2.0-1", "/usr/share/a.jpg", "CC0 (x; y)", std::string(64, 'a'), "still", -1},
      {"video/v/c_f000010.png", "v", "pkg2", "3", "/usr/c.avi", "MIT", std::string(63, '0') + "f", "video-frame", 10},
      {"video/v/c_f000000.png", "v", "pkg2", "3", "/usr/c.avi", "", std::string(64, 'b'), "video-frame", 0},
  };
  const std::string text = manifest_tsv(rows);
  EXPECT_EQ(text.substr(0, text.find('\n')), "file\tgroup\tpackage\tversion\tpath\tlicence\tsha256\tkind\tframe");
  EXPECT_EQ(parse_manifest(text, "m.tsv"), rows);
  EXPECT_NE(text.find("\tstill\t\n"), std::string::npos);  // a still's frame is empty
  // Damaged manifests are refused with the line named.
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"\tstill\t\n", "\tstill\t3\n"}, {"video-frame\t10", "video-frame\t"}, {std::string(64, 'a'), "xyz"},
           {"stills/g/a.png", "../a.png"}}) {
    std::string bad = text;
    bad.replace(bad.find(from), from.size(), to);
    EXPECT_THROW(parse_manifest(bad, "m.tsv"), std::runtime_error) << from;
  }
  // A file listed twice (it would be scored twice).
  const std::string twice = text + text.substr(text.find('\n') + 1, text.find('\n', text.find('\n') + 1) - text.find('\n'));
  try {
    parse_manifest(twice, "m.tsv");
    ADD_FAILURE() << "a file listed twice was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "m.tsv:5: file 'stills/g/a.png' is already on line 2");
  }
  auto tabbed = rows;
  tabbed[0].licence = "a\tb";
  EXPECT_THROW(manifest_tsv(tabbed), std::runtime_error);
}

TEST(ScanFolder, GoodCorruptAndOtherFiles) {
  const fs::path d = fs::path(::testing::TempDir()) / ("scan_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d / "sub" / "deeper");
  cv::imwrite((d / "a.png").string(), cv::Mat(30, 40, CV_8UC3, cv::Scalar(1, 2, 3)));
  cv::imwrite((d / "sub" / "deeper" / "b.jpg").string(), cv::Mat(50, 20, CV_8UC1, cv::Scalar(9)));
  // A PNG without its extension is still found by its signature.
  fs::copy_file(d / "a.png", d / "sub" / "noext");
  std::ofstream(d / "sub" / "broken.jpg") << "this is not a jpeg";
  {
    // A truncated PNG: header intact, body cut.
    std::ifstream in(d / "a.png", std::ios::binary);
    std::string s((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(d / "sub" / "cut.png", std::ios::binary) << s.substr(0, 40);
  }
  std::ofstream(d / "notes.txt") << "hello";
  const auto s = scan_folder(d);
  ASSERT_EQ(s.images.size(), 3u);
  EXPECT_EQ(s.images[0].file, d / "a.png");
  EXPECT_EQ(s.images[0].width, 40);
  EXPECT_EQ(s.images[0].height, 30);
  EXPECT_EQ(s.images[1].file, d / "sub" / "deeper" / "b.jpg");
  EXPECT_EQ(s.images[1].width, 20);
  EXPECT_EQ(s.images[2].file, d / "sub" / "noext");
  ASSERT_EQ(s.unreadable.size(), 2u);
  EXPECT_EQ(s.unreadable[0].file, d / "sub" / "broken.jpg");
  EXPECT_EQ(s.unreadable[1].file, d / "sub" / "cut.png");
  EXPECT_FALSE(s.unreadable[0].reason.empty());
  EXPECT_EQ(s.other_files, 1u);
  EXPECT_THROW(scan_folder(d / "missing"), std::runtime_error);
  fs::remove_all(d);
}

}  // namespace test_corpus
