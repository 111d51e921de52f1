// `tagbench corpus build` end to end against a small local fake: a .deb made here with dpkg-deb
// (a large PNG, a Qt resource bundle holding a PNG, an MJPEG clip and a folder of frames), lists
// naming them, --debs instead of apt-get. Checks the outputs, the manifest, the no-op rebuild and
// the changed-file error; and `tagbench corpus list`.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "rcc_writer.hpp"
#include "sha256.hpp"
#include "sources.hpp"

#include "run_tagbench.hpp"

namespace fs = std::filesystem;
using namespace tagbench::corpus;

namespace {

using Result = tagbench::testing::CommandResult;

using tagbench::testing::slurp;

const fs::path& root() {
  static const fs::path d = [] {
    const fs::path p = fs::path(::testing::TempDir()) / ("tagbench_corpus_cli_" + std::to_string(::getpid()));
    fs::remove_all(p);
    fs::create_directories(p);
    return p;
  }();
  return d;
}

Result run(const std::string& args) { return tagbench::testing::run_tagbench(args, root()); }

std::string png_bytes(const cv::Mat& m) {
  std::vector<unsigned char> b;
  cv::imencode(".png", m, b);
  return std::string(b.begin(), b.end());
}

cv::Mat pattern(int w, int h, int seed) {
  cv::Mat m(h, w, CV_8UC3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      m.at<cv::Vec3b>(y, x) = cv::Vec3b(static_cast<uchar>((x * 7 + seed) & 255), static_cast<uchar>((y * 3) & 255),
                                        static_cast<uchar>((x ^ y) & 255));
  return m;
}

void put(const fs::path& p, const std::string& bytes) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << bytes;
}

// Builds fakepkg 2:1.0-1 into debs/ with the given big photo.
void make_deb(const cv::Mat& photo) {
  const fs::path pkg = root() / "pkgroot";
  fs::remove_all(pkg);
  put(pkg / "DEBIAN" / "control",
      "Package: fakepkg\nVersion: 2:1.0-1\nArchitecture: all\nMaintainer: t <t@example.org>\nDescription: test\n");
  put(pkg / "usr/share/fake/photo.png", png_bytes(photo));
  rcctest::Writer w;
  w.add("gcompris/src/activities/categorization/resource/fish.png", png_bytes(pattern(60, 40, 5)), rcctest::Pack::zlib);
  w.add("gcompris/src/activities/categorization/resource/other.txt", "not listed");
  put(pkg / "usr/share/gcompris-qt/rcc/categorization.rcc", w.bytes(3));
  for (int i = 0; i < 5; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%03d.png", i);
    put(pkg / "usr/share/fake/frames" / name, png_bytes(pattern(32, 24, 40 * i)));
  }
  const fs::path clip = pkg / "usr/share/fake/clip.avi";
  {
    cv::VideoWriter vw(clip.string(), cv::CAP_OPENCV_MJPEG, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10,
                       cv::Size(64, 48));
    ASSERT_TRUE(vw.isOpened());
    for (int i = 0; i < 7; ++i) vw.write(pattern(64, 48, 30 * i));
  }
  fs::create_directories(root() / "debs");
  const std::string cmd = "dpkg-deb --root-owner-group --build " + pkg.string() + " " +
                          (root() / "debs" / "fakepkg_2%3a1.0-1_all.deb").string() + " >/dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
}

void make_lists() {
  put(root() / "lists/photo_sources.tsv",
      "group\tdebian_package\tversion\tpath_in_package\tlicense\n"
      "big\tfakepkg\t2:1.0-1\t/usr/share/fake/photo.png\tCC0\n"
      "fish\tfakepkg\t2:1.0-1\t/_rcc/gcompris/src/activities/categorization/resource/fish.png\tGPL-3+\n");
  put(root() / "lists/video_sources.tsv",
      "group\tdebian_package\tversion\tpath_in_package\tframe_step\tlicense\n"
      "clip\tfakepkg\t2:1.0-1\t/usr/share/fake/clip.avi\t3\tCC0\n"
      "frames\tfakepkg\t2:1.0-1\t/usr/share/fake/frames/frame_*.png\t2\tCC0\n");
}

std::string build_args() {
  return "corpus build --out " + (root() / "out").string() + " --lists " + (root() / "lists").string() +
         " --debs " + (root() / "debs").string() + " --jobs 2";
}

}  // namespace

TEST(CorpusCli, BuildRebuildAndChangedFile) {
  const cv::Mat photo = pattern(3000, 1000, 1);
  make_deb(photo);
  make_lists();
  const fs::path out = root() / "out";

  const Result r = run(build_args());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("1 packages built, 0 already in place; 2 stills, 6 video frames"), std::string::npos) << r.err;

  // The big photo: scaled to 2048 on the long side.
  const cv::Mat big = cv::imread((out / "stills/big/photo.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(big.empty());
  EXPECT_EQ(big.cols, 2048);
  EXPECT_EQ(big.rows, 683);
  // The bundle's PNG: small, so written pixel for pixel.
  const cv::Mat fish = cv::imread((out / "stills/fish/fish.png").string(), cv::IMREAD_COLOR);
  ASSERT_EQ(fish.size(), cv::Size(60, 40));
  EXPECT_EQ(cv::norm(fish, pattern(60, 40, 5), cv::NORM_INF), 0);
  // Frames of the folder: 0, 2, 4 of five, exact.
  for (int i : {0, 2, 4}) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%03d.png", i);
    const cv::Mat f = cv::imread((out / "video/frames" / name).string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(f.empty()) << name;
    EXPECT_EQ(cv::norm(f, pattern(32, 24, 40 * i), cv::NORM_INF), 0) << name;
  }
  EXPECT_FALSE(fs::exists(out / "video/frames/frame_001.png"));
  // Frames of the clip: 0, 3, 6 of seven.
  for (const char* f : {"clip_f000000.png", "clip_f000003.png", "clip_f000006.png"})
    EXPECT_TRUE(fs::exists(out / "video/clip" / f)) << f;
  EXPECT_FALSE(fs::exists(out / "video/clip/clip_f000001.png"));
  EXPECT_FALSE(fs::exists(out / ".work"));  // the unpacked package is gone

  const auto m = parse_manifest(slurp(out / "manifest.tsv"), "manifest.tsv");
  ASSERT_EQ(m.size(), 8u);
  const std::string photo_sha = sha256_hex(slurp(root() / "pkgroot/usr/share/fake/photo.png"));
  const std::string clip_sha = sha256_hex(slurp(root() / "pkgroot/usr/share/fake/clip.avi"));
  int clip_rows = 0;
  for (const auto& row : m) {
    EXPECT_TRUE(fs::exists(out / row.file)) << row.file;
    EXPECT_EQ(row.package, "fakepkg");
    EXPECT_EQ(row.version, "2:1.0-1");
    if (row.file == "stills/big/photo.png") {
      EXPECT_EQ(row.sha256, photo_sha);
      EXPECT_EQ(row.kind, "still");
      EXPECT_EQ(row.licence, "CC0");
      EXPECT_EQ(row.path, "/usr/share/fake/photo.png");
    }
    if (row.group == "clip") {
      ++clip_rows;
      EXPECT_EQ(row.sha256, clip_sha);
      EXPECT_EQ(row.kind, "video-frame");
      EXPECT_EQ(row.frame % 3, 0);
    }
    if (row.group == "frames") {
      EXPECT_EQ(row.path, "/usr/share/fake/frames/frame_00" + std::to_string(row.frame) + ".png");
    }
  }
  EXPECT_EQ(clip_rows, 3);

  // A rebuild with everything in place does nothing: same manifest, outputs untouched.
  const auto stamp = fs::last_write_time(out / "stills/big/photo.png");
  const std::string manifest_before = slurp(out / "manifest.tsv");
  const Result again = run(build_args());
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.err.find("0 packages built, 1 already in place"), std::string::npos) << again.err;
  EXPECT_EQ(fs::last_write_time(out / "stills/big/photo.png"), stamp);
  EXPECT_EQ(slurp(out / "manifest.tsv"), manifest_before);
  // --verify unpacks and checks it again; the same package passes.
  const Result verified = run(build_args() + " --verify");
  ASSERT_EQ(verified.code, 0) << verified.err;
  EXPECT_EQ(slurp(out / "manifest.tsv"), manifest_before);

  // A missing output is rebuilt.
  fs::remove(out / "stills/fish/fish.png");
  ASSERT_EQ(run(build_args()).code, 0);
  EXPECT_TRUE(fs::exists(out / "stills/fish/fish.png"));

  // The package changes under the same version: an error naming the file and its package.
  make_deb(pattern(3000, 1000, 2));
  for (const std::string extra : {" --verify", ""}) {
    if (extra.empty()) fs::remove(out / "stills/big/photo.png");
    const Result bad = run(build_args() + extra);
    EXPECT_EQ(bad.code, 1) << extra;
    EXPECT_NE(bad.err.find("/usr/share/fake/photo.png in package fakepkg 2:1.0-1 changed"), std::string::npos)
        << bad.err;
    EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
    EXPECT_EQ(slurp(out / "manifest.tsv"), manifest_before);  // not silently used
  }
}

TEST(CorpusCli, Refusals) {
  make_lists();
  fs::create_directories(root() / "nodebs");
  const Result missing = run("corpus build --out " + (root() / "o2").string() + " --lists " +
                             (root() / "lists").string() + " --debs " + (root() / "nodebs").string());
  EXPECT_EQ(missing.code, 1);
  EXPECT_NE(missing.err.find("no fakepkg_2%3a1.0-1_*.deb in"), std::string::npos) << missing.err;
  const Result unknown = run("corpus build --out " + (root() / "o3").string() + " --lists " +
                             (root() / "lists").string() + " --packages nosuch");
  EXPECT_EQ(unknown.code, 1);
  EXPECT_NE(unknown.err.find("'nosuch' is not in the lists"), std::string::npos) << unknown.err;
  EXPECT_EQ(run("corpus frob").code, 2);
  EXPECT_EQ(run("corpus list").code, 2);
  const Result help = run("corpus --help");
  EXPECT_EQ(help.code, 0);
  EXPECT_NE(help.out.find("usage: tagbench corpus build"), std::string::npos);
}

TEST(CorpusCli, ListFolder) {
  const fs::path d = root() / "user";
  fs::create_directories(d / "x");
  cv::imwrite((d / "x" / "good.png").string(), pattern(10, 8, 0));
  put(d / "bad.jpg", "garbage");
  put(d / "readme.md", "text");
  const Result r = run("corpus list --from " + d.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("ok\t" + (d / "x" / "good.png").string() + "\t10\t8\t\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("unreadable\t" + (d / "bad.jpg").string() + "\t\t\t"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("1 images, 1 unreadable, 1 other files"), std::string::npos) << r.err;
}
