// `tagbench corpus build` end to end against a small local fake: a .deb made here with dpkg-deb
// (a large PNG, a Qt resource bundle holding a PNG, an MJPEG clip and a folder of frames), lists
// naming them, --debs instead of apt-get. Checks the outputs, the manifest, the no-op rebuild and
// the changed-file error; `tagbench corpus list`; and `corpus candidates --shard` with `corpus
// merge` against the single run, byte for byte, and the merge's refusals.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "candidates.hpp"
#include "rcc_writer.hpp"
#include "sha256.hpp"
#include "sources.hpp"

#include "run_tagbench.hpp"
#include "scratch_dir.hpp"

namespace test_corpus_cli {

namespace fs = std::filesystem;
using namespace tagbench::corpus;

namespace {

using Result = tagbench::testing::CommandResult;

using tagbench::testing::slurp;

const fs::path& root() { return tagbench::testing::program_scratch("tagbench_corpus_cli"); }

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

// Sources taken out of the lists leave the corpus at the next full build: their rows, then their
// files; a build restricted by --packages prunes nothing; a row naming a file outside stills/ and
// video/ is dropped from the manifest but its file is never touched.
TEST(CorpusCli, RowsOfSourcesNoLongerListedArePrunedWithTheirFiles) {
  make_deb(pattern(3000, 1000, 1));
  const fs::path lists = root() / "lists-prune", out = root() / "out-prune";
  const std::string header = "group\tdebian_package\tversion\tpath_in_package\tlicense\n";
  const std::string big = "big\tfakepkg\t2:1.0-1\t/usr/share/fake/photo.png\tCC0\n";
  const std::string fish = "fish\tfakepkg\t2:1.0-1\t/_rcc/gcompris/src/activities/categorization/resource/fish.png\tGPL-3+\n";
  const std::string vheader = "group\tdebian_package\tversion\tpath_in_package\tframe_step\tlicense\n";
  const std::string clip = "clip\tfakepkg\t2:1.0-1\t/usr/share/fake/clip.avi\t3\tCC0\n";
  const std::string frames = "frames\tfakepkg\t2:1.0-1\t/usr/share/fake/frames/frame_*.png\t2\tCC0\n";
  auto lists_with = [&](const std::string& photos, const std::string& videos) {
    put(lists / "photo_sources.tsv", header + photos);
    put(lists / "video_sources.tsv", vheader + videos);
  };
  const std::string args = "corpus build --out " + out.string() + " --lists " + lists.string() + " --debs " +
                           (root() / "debs").string() + " --jobs 2";
  lists_with(big + fish, clip + frames);
  Result r = run(args);
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(parse_manifest(slurp(out / "manifest.tsv"), "m").size(), 8u);
  const auto stamp = fs::last_write_time(out / "stills/big/photo.png");

  // A row of a package no list names, whose file lies outside stills/ and video/: dropped, file kept
  // (the manifest reader already refuses paths leaving the corpus folder).
  put(out / "other/outside.png", "not ours");
  auto rows = parse_manifest(slurp(out / "manifest.tsv"), "m");
  ManifestRow odd = rows.front();
  odd.package = "otherpkg";
  odd.file = "other/outside.png";
  rows.push_back(odd);
  put(out / "manifest.tsv", manifest_tsv(rows));

  // fish and frames leave the lists; a build limited to the package prunes nothing.
  lists_with(big, clip + frames);
  r = run(args + " --packages fakepkg");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(parse_manifest(slurp(out / "manifest.tsv"), "m").size(), 9u);
  lists_with(big, clip);
  r = run(args);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("; 5 rows of sources no longer listed removed"), std::string::npos) << r.err;
  const auto kept = parse_manifest(slurp(out / "manifest.tsv"), "m");
  ASSERT_EQ(kept.size(), 4u);  // the photo and three clip frames
  for (const auto& row : kept) {
    EXPECT_TRUE(row.group == "big" || row.group == "clip") << row.file;
    EXPECT_TRUE(fs::exists(out / row.file)) << row.file;
  }
  EXPECT_FALSE(fs::exists(out / "stills/fish")) << "the file and its emptied group folder";
  EXPECT_FALSE(fs::exists(out / "video/frames"));
  EXPECT_TRUE(fs::exists(out / "other/outside.png"));
  EXPECT_EQ(fs::last_write_time(out / "stills/big/photo.png"), stamp);  // the rest untouched
  // Nothing left to prune: the next build says nothing about it.
  r = run(args);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find("no longer listed"), std::string::npos) << r.err;
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

// ---- Shards: `corpus candidates --shard i/N` and `corpus merge` (issue 5, section 4) ----

namespace {

// A small scanned corpus: three synthetic scenes (tags in perspective on clutter, so there are
// quads), a mid-grey image without any, and a file that does not decode. Sorted: a.png, b.png,
// broken.jpg, sub/c.png, z.png (M = 5).
const fs::path& shard_corpus() {
  static const fs::path d = [] {
    const fs::path p = root() / "shardcorpus";
    fs::create_directories(p / "sub");
    int seed = 1;
    for (const char* name : {"a.png", "b.png", "sub/c.png"}) {
      const Result r = run("scene --width 320 --height 240 --count 3 --seed " + std::to_string(seed++) + " -o " +
                           (p / name).string());
      EXPECT_EQ(r.code, 0) << r.err;
    }
    cv::imwrite((p / "z.png").string(), cv::Mat(100, 90, CV_8UC1, cv::Scalar(128)));
    put(p / "broken.jpg", "not a jpeg");
    return p;
  }();
  return d;
}

fs::path shard_file(std::uint64_t i, std::uint64_t n) {
  return root() / ("shards" + std::to_string(n)) / (std::to_string(i) + ".bin");
}

// Runs shard i of n of the corpus into shard_file(i, n) (once per process).
void make_shard(std::uint64_t i, std::uint64_t n) {
  if (fs::exists(shard_file(i, n))) return;
  const Result r = run("corpus candidates --corpus " + shard_corpus().string() + " --shard " + std::to_string(i) +
                       "/" + std::to_string(n) + " --jobs " + std::to_string(1 + i % 2) + " --out " +
                       shard_file(i, n).string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("shard " + std::to_string(i) + "/" + std::to_string(n) + ": rows "), std::string::npos) << r.err;
}

// The single, unsharded run (once per process).
fs::path single_run() {
  const fs::path bin = root() / "single" / "c.bin";
  if (!fs::exists(bin)) {
    const Result r = run("corpus candidates --corpus " + shard_corpus().string() + " --jobs 2 --out " + bin.string());
    EXPECT_EQ(r.code, 0) << r.err;
  }
  return bin;
}

void copy_store(const fs::path& from, const fs::path& to) {
  fs::copy_file(from, to, fs::copy_options::overwrite_existing);
  fs::copy_file(candidate_index_path(from), candidate_index_path(to), fs::copy_options::overwrite_existing);
}

}  // namespace

TEST(CorpusCli, MergedShardsAreByteIdenticalToTheSingleRun) {
  const fs::path single = single_run();
  const std::string bin = slurp(single), tsv = slurp(candidate_index_path(single));
  // Not a vacuous comparison: the scenes give quads and payload records, and the index lists all 5.
  const CandidateStore whole = read_candidates(single);
  ASSERT_EQ(whole.images.size(), 5u);
  EXPECT_GT(whole.quads, 5u);
  EXPECT_GT(whole.records.size(), 10u);
  EXPECT_EQ(whole.images[2].status, "unreadable");

  // N = 3: rows [0,1), [1,3), [3,5). N = 8 > M = 5: shards 0, 2 and 5 are empty.
  for (const std::uint64_t n : {3u, 8u}) {
    std::string files;
    for (std::uint64_t i = n; i-- > 0;) {  // given in reverse: the order must not matter
      make_shard(i, n);
      files.append(" ").append(shard_file(i, n).string());
    }
    if (n == 8) {
      for (const std::uint64_t i : {0u, 2u, 5u}) EXPECT_TRUE(read_candidates(shard_file(i, n)).images.empty()) << i;
    } else {
      const CandidateStore s1 = read_candidates(shard_file(1, n));
      ASSERT_EQ(s1.images.size(), 2u);
      EXPECT_EQ(s1.images[0].file, "b.png");
      for (const auto& r : s1.records) EXPECT_LT(r.image, 2u);  // ids local to the shard
    }
    const fs::path merged = root() / ("merged" + std::to_string(n)) / "c.bin";
    const Result r = run("corpus merge --out " + merged.string() + files);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("tagbench corpus merge: " + std::to_string(n) + " shards, 5 images"), std::string::npos)
        << r.err;
    EXPECT_TRUE(slurp(merged) == bin) << "N=" << n << ": the merged .bin differs from the single run's";
    EXPECT_EQ(slurp(candidate_index_path(merged)), tsv) << "N=" << n;
  }

  // One shard of one, under its default name in the corpus folder, is the whole corpus too.
  const Result one = run("corpus candidates --corpus " + shard_corpus().string() + " --shard 0/1 --jobs 2");
  ASSERT_EQ(one.code, 0) << one.err;
  const fs::path def = shard_corpus() / "corpus_candidates-shard-0-of-1.bin";
  ASSERT_TRUE(fs::exists(def));
  EXPECT_NE(slurp(def), bin);  // the shard lines are in its settings
  const fs::path merged1 = root() / "merged1" / "c.bin";
  ASSERT_EQ(run("corpus merge --out " + merged1.string() + " " + def.string()).code, 0);
  EXPECT_TRUE(slurp(merged1) == bin);
  EXPECT_EQ(slurp(candidate_index_path(merged1)), tsv);
  fs::remove(def);
  fs::remove(candidate_index_path(def));
}

TEST(CorpusCli, MergeAndShardRefusals) {
  for (std::uint64_t i = 0; i < 3; ++i) make_shard(i, 3);
  const fs::path s0 = shard_file(0, 3), s1 = shard_file(1, 3), s2 = shard_file(2, 3);
  const fs::path bad = root() / "bad";
  fs::create_directories(bad);
  const fs::path out = root() / "refused" / "c.bin";

  // Refused with one line "tagbench corpus SUBCOMMAND: ..." containing `needle`, exit `code`, nothing
  // written. `args` begins "corpus SUBCOMMAND ".
  const auto refused = [&](const std::string& args, const std::string& needle, int code = 1) {
    const Result r = run(args);
    EXPECT_EQ(r.code, code) << args << "\n" << r.err;
    const std::string prefix = "tagbench " + args.substr(0, args.find(' ', args.find(' ') + 1)) + ": ";
    EXPECT_EQ(r.err.rfind(prefix, 0), 0u) << prefix << "\n" << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << "wanted: " << needle << "\ngot: " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(out)) << args;
    EXPECT_FALSE(fs::exists(candidate_index_path(out))) << args;
  };
  const auto merge = [&](const std::vector<fs::path>& files) {
    std::string a = "corpus merge --out " + out.string();
    for (const auto& f : files) a.append(" ").append(f.string());
    return a;
  };
  ASSERT_EQ(run(merge({s0, s1, s2})).code, 0);  // the three are fine together
  fs::remove(out);
  fs::remove(candidate_index_path(out));

  refused(merge({s0, s2}), "shard 1/3 is missing: 2 of 3 shards given (" + s0.string() + ", " + s2.string() + ")");
  refused(merge({s1, s2}), "shard 0/3 is missing");
  copy_store(s1, bad / "dup.bin");
  refused(merge({s0, s1, bad / "dup.bin", s2}),
          (bad / "dup.bin").string() + ": shard 1/3 is also given as " + s1.string());
  refused(merge({s0, s1, s1, s2}), s1.string() + ": shard 1/3 is also given as " + s1.string());

  // Other detector settings: shard 2 as if run with another blur.
  {
    CandidateStore s = read_candidates(s2);
    const auto at = s.settings.find("seg_sigma=");
    ASSERT_NE(at, std::string::npos);
    s.settings.replace(at, s.settings.find('\n', at) - at, "seg_sigma=2");
    write_candidates(bad / "sigma.bin", s);
  }
  refused(merge({s0, s1, bad / "sigma.bin"}),
          (bad / "sigma.bin").string() + ": detector settings differ from " + s0.string() + "'s ('seg_sigma=2'");

  // Another N.
  make_shard(1, 2);
  refused(merge({s0, shard_file(1, 2), s2}), shard_file(1, 2).string() + ": shard 1/2, but " + s0.string() +
                                                 " is shard 0/3");

  // A corpus that changed between the shards' runs: an image added.
  {
    const fs::path grown = root() / "grown";
    fs::create_directories(grown / "sub");
    for (const char* f : {"a.png", "b.png", "broken.jpg", "sub/c.png", "z.png"})
      fs::copy_file(shard_corpus() / f, grown / f, fs::copy_options::overwrite_existing);
    cv::imwrite((grown / "y.png").string(), cv::Mat(50, 60, CV_8UC1, cv::Scalar(90)));
    const Result r = run("corpus candidates --corpus " + grown.string() + " --shard 2/3 --out " +
                         (bad / "grown2.bin").string());
    ASSERT_EQ(r.code, 0) << r.err;
    refused(merge({s0, s1, bad / "grown2.bin"}),
            (bad / "grown2.bin").string() + ": made from a corpus list of 6 images");
  }

  // Damaged shards: cut short, a flipped byte, no index, an index of another shard.
  {
    const std::string bytes = slurp(s1);
    copy_store(s1, bad / "cut.bin");
    put(bad / "cut.bin", bytes.substr(0, bytes.size() - 5));
    refused(merge({s0, bad / "cut.bin", s2}), (bad / "cut.bin").string() + ": size ");
    std::string flipped = bytes;
    flipped[flipped.size() - 7] = static_cast<char>(flipped[flipped.size() - 7] ^ 0x04);
    copy_store(s1, bad / "flip.bin");
    put(bad / "flip.bin", flipped);
    refused(merge({s0, bad / "flip.bin", s2}), (bad / "flip.bin").string() + ": checksum mismatch");
    fs::copy_file(s1, bad / "noindex.bin", fs::copy_options::overwrite_existing);
    refused(merge({s0, bad / "noindex.bin", s2}), (bad / "noindex.tsv").string());
    copy_store(s1, bad / "otherindex.bin");
    fs::copy_file(candidate_index_path(s2), bad / "otherindex.tsv", fs::copy_options::overwrite_existing);
    refused(merge({s0, bad / "otherindex.bin", s2}),
            (bad / "otherindex.bin").string() + ": its image index (.tsv) does not list the images");
    put(bad / "garbage.bin", "garbage");
    refused(merge({s0, s1, s2, bad / "garbage.bin"}), (bad / "garbage.bin").string() + ": too short");
  }

  // An unsharded store among the shards.
  refused(merge({s0, s1, s2, single_run()}), single_run().string() + ": not a shard store");

  // Usage: no --out, no shards.
  refused("corpus merge " + s0.string(), "--out FILE is required", 2);
  refused("corpus merge --out " + out.string(), "no shard stores given", 2);

  // Bad --shard values: refused before anything is read or written.
  const std::string cand = "corpus candidates --corpus " + shard_corpus().string() + " --out " + out.string();
  refused(cand + " --shard 3/3", "--shard '3/3': i must be below N", 2);
  refused(cand + " --shard=-1/2", "--shard '-1/2': not of the form i/N", 2);
  refused(cand + " --shard -1/2", "--shard '-1/2': not of the form i/N", 2);
  refused(cand + " --shard 1/0", "--shard '1/0': N must be at least 1", 2);
  refused(cand + " --shard x/y", "--shard 'x/y': not of the form i/N", 2);
  refused(cand + " --shard 1/2/3", "--shard '1/2/3'", 2);
  refused(cand + " --shard", "--shard needs a value", 2);
}

}  // namespace test_corpus_cli
