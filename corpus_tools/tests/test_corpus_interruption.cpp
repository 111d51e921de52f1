// Interruption and determinism of the corpus commands (issue 6, items 4 and 5): `tagbench corpus
// build --debs` and `tagbench corpus candidates` killed with kill -9 in the middle of their work and
// run again end with the files of an uninterrupted run, byte for byte, and nothing else (no unpacked
// package, no temporary); `corpus candidates` writes the same store with 1 and with 4 jobs, sharded
// or not.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "candidates.hpp"
#include "tools/atomic_file.hpp"

#include "kill_run.hpp"
#include "run_tagbench.hpp"
#include "scratch_dir.hpp"

namespace test_corpus_interruption {

namespace fs = std::filesystem;
using namespace tagbench::testing;

namespace {

const fs::path& root() { return program_scratch("tagbench_corpus_interruption"); }

// A folder for a run's stdout and stderr, apart from the folders whose files are compared.
fs::path logs(const std::string& name) {
  const fs::path d = root() / "logs" / name;
  fs::create_directories(d);
  return d;
}

CommandResult run(const std::string& args, const std::string& log = "run") {
  return run_tagbench(args, logs(log));
}

void put(const fs::path& p, const std::string& bytes) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << bytes;
}

// Clutter that gives the quad search work: rotated rectangles of random grey on a noisy gradient.
cv::Mat clutter(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  cv::Mat m(h, w, CV_8UC3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const auto v = static_cast<uchar>(60 + (x * 90) / w + (y * 60) / h);
      m.at<cv::Vec3b>(y, x) = cv::Vec3b(v, static_cast<uchar>(v + 10), static_cast<uchar>(v - 10));
    }
  for (int i = 0; i < 40; ++i) {
    const cv::RotatedRect rr(cv::Point2f(static_cast<float>(rng() % w), static_cast<float>(rng() % h)),
                             cv::Size2f(static_cast<float>(20 + rng() % 120), static_cast<float>(20 + rng() % 120)),
                             static_cast<float>(rng() % 90));
    cv::Point2f pts[4];
    rr.points(pts);
    const std::vector<cv::Point> poly(pts, pts + 4);
    const int v = static_cast<int>(rng() % 256);
    cv::fillConvexPoly(m, poly, cv::Scalar(v, (v * 7) % 256, 255 - v), cv::LINE_AA);
  }
  cv::Mat noise(h, w, CV_8UC3);
  cv::theRNG().state = seed;
  cv::randn(noise, cv::Scalar::all(0), cv::Scalar::all(6));
  cv::add(m, noise, m);
  return m;
}

std::string png(const cv::Mat& m) {
  std::vector<unsigned char> b;
  cv::imencode(".png", m, b);
  return std::string(b.begin(), b.end());
}

// ---- corpus build ----

constexpr int kStillsPerPackage = 6;

// Two packages of stills, each still big enough (decoded, re-encoded as PNG) that a package takes a
// good part of a second: debs/pkga_1.0_all.deb and debs/pkgb_1.0_all.deb, and lists naming every still.
const fs::path& build_inputs() {
  static const fs::path d = [] {
    const fs::path in = root() / "build-inputs";
    std::string list = "group\tdebian_package\tversion\tpath_in_package\tlicense\n";
    for (const std::string pkg : {"pkga", "pkgb"}) {
      const fs::path tree = in / ("tree-" + pkg);
      put(tree / "DEBIAN" / "control", "Package: " + pkg +
                                           "\nVersion: 1.0\nArchitecture: all\nMaintainer: t <t@example.org>\n"
                                           "Description: test\n");
      for (int i = 0; i < kStillsPerPackage; ++i) {
        const std::string name = "still" + std::to_string(i) + ".png";
        put(tree / "usr/share" / pkg / name, png(clutter(1100, 800, static_cast<unsigned>(100 * (pkg == "pkgb") + i))));
        list += std::string(1, pkg.back()) + "\t" + pkg + "\t1.0\t/usr/share/" + pkg + "/" + name + "\tCC0\n";
      }
      fs::create_directories(in / "debs");
      const std::string cmd = "dpkg-deb -Zgzip -z1 --root-owner-group --build " + tree.string() + " " +
                              (in / "debs" / (pkg + "_1.0_all.deb")).string() + " >/dev/null 2>&1";
      EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    }
    put(in / "lists" / "photo_sources.tsv", list);
    return in;
  }();
  return d;
}

std::string build_args(const fs::path& out, int jobs) {
  return "corpus build --out " + out.string() + " --lists " + (build_inputs() / "lists").string() + " --debs " +
         (build_inputs() / "debs").string() + " --jobs " + std::to_string(jobs);
}

bool any_png_in(const fs::path& dir) {
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().extension() == ".png") return true;
  return false;
}

// The uninterrupted build (2 jobs), once per process.
const fs::path& reference_build() {
  static const fs::path ref = [] {
    const fs::path out = root() / "build-ref";
    const CommandResult r = run(build_args(out, 2), "build-ref");
    EXPECT_EQ(r.code, 0) << r.err;
    return out;
  }();
  return ref;
}

bool file_named_under(const fs::path& dir, const std::string& name) {
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().filename() == name) return true;
  return false;
}

// ---- corpus candidates ----

// 16 cluttered images (some grey, some colour), a file that does not decode and a text file.
const fs::path& candidates_corpus() {
  static const fs::path d = [] {
    const fs::path c = root() / "cands";
    for (int i = 0; i < 16; ++i) {
      cv::Mat m = clutter(720, 540, static_cast<unsigned>(1000 + i));
      if (i % 3 == 0) cv::cvtColor(m, m, cv::COLOR_BGR2GRAY);
      const fs::path f = c / (i % 2 ? "odd" : "even") / ("img" + std::to_string(100 + i) + ".png");
      fs::create_directories(f.parent_path());
      cv::imwrite(f.string(), m);
    }
    put(c / "broken.jpg", "not a jpeg");
    put(c / "notes.txt", "not an image");
    return c;
  }();
  return d;
}

// The uninterrupted run's store (.bin, .tsv) of candidates_corpus(), with 2 jobs, once per process.
const std::pair<std::string, std::string>& reference_store() {
  static const std::pair<std::string, std::string> s = [] {
    const fs::path bin = root() / "cands-ref" / "c.bin";
    const CommandResult r =
        run("corpus candidates --corpus " + candidates_corpus().string() + " --jobs 2 --out " + bin.string());
    EXPECT_EQ(r.code, 0) << r.err;
    return std::pair{slurp(bin), slurp(tagbench::corpus::candidate_index_path(bin))};
  }();
  return s;
}

}  // namespace

TEST(CorpusInterruption, BuildKilledTwiceMidRunEndsWithTheUninterruptedCorpus) {
  const fs::path& ref = reference_build();
  const fs::path out = root() / "build-int";
  ASSERT_EQ(file_tree(ref).size(), 2u * kStillsPerPackage + 1) << "the stills and the manifest";

  // Kill 1: while the first package is being unpacked or converted (nothing finished yet).
  const fs::path log1 = logs("build-kill1");
  const pid_t p1 = start_tagbench(build_args(out, 1), log1);
  const KillOutcome k1 = kill_when(p1, [&] { return fs::exists(out / ".work" / "pkga"); });
  ASSERT_TRUE(k1.killed_mid_run) << k1.why << "\n" << slurp(log1 / "stderr");
  EXPECT_FALSE(fs::exists(out / "manifest.tsv")) << "the kill came after the first package was done";

  // Kill 2: the rerun takes the first package; killed once the second one's first still is written.
  const fs::path log2 = logs("build-kill2");
  const pid_t p2 = start_tagbench(build_args(out, 1), log2);
  const KillOutcome k2 = kill_when(p2, [&] { return any_png_in(out / "stills" / "b"); });
  ASSERT_TRUE(k2.killed_mid_run) << k2.why << "\n" << slurp(log2 / "stderr");
  const std::string manifest = slurp(out / "manifest.tsv");
  EXPECT_NE(manifest.find("stills/a/still0.png"), std::string::npos) << manifest;
  EXPECT_EQ(manifest.find("stills/b/"), std::string::npos) << "the kill came after the second package was done";

  // What a kill during an atomic write would leave (the killed run's pid), and a temporary of a run
  // still going (this test's pid), which must be left alone.
  const fs::path stale_png = tagbench::atomic_temporary(out / "stills" / "b" / "still1.png", p2);
  const fs::path stale_manifest = tagbench::atomic_temporary(out / "manifest.tsv", p2);
  const fs::path live = tagbench::atomic_temporary(out / "stills" / "b" / "other.png", ::getpid());
  for (const auto& f : {stale_png, stale_manifest, live}) put(f, "half a file");

  const CommandResult done = run(build_args(out, 1), "build-done");
  ASSERT_EQ(done.code, 0) << done.err;
  EXPECT_NE(done.err.find("1 packages built, 1 already in place"), std::string::npos) << done.err;
  EXPECT_TRUE(fs::exists(live)) << "a temporary of a live process was removed";
  fs::remove(live);
  EXPECT_FALSE(fs::exists(out / ".work")) << "the killed runs' unpacked packages are gone";
  const auto a = file_tree(ref), b = file_tree(out);
  EXPECT_TRUE(a == b) << "the interrupted corpus differs from the uninterrupted one:\n" << tree_difference(a, b);
}

// apt-get download killed halfway (a stand-in apt-get on PATH: its first download writes part of the
// .deb and hangs): the rerun must download again, not unpack the half file it finds.
TEST(CorpusInterruption, BuildKilledWhileDownloadingNeverTakesTheHalfDownload) {
  const fs::path& ref = reference_build();
  const fs::path bin = root() / "fake-apt", out = root() / "dl-out", cache = root() / "dl-cache",
                 marker = root() / "fake-apt-ran";
  put(bin / "apt-get",
      "#!/bin/sh\n"
      "# apt-get download -q PKG=VERSION, from " + (build_inputs() / "debs").string() + "\n"
      "for a; do spec=$a; done\n"
      "pkg=${spec%%=*}\n"
      "src=" + shell_quote((build_inputs() / "debs").string()) + "/${pkg}_1.0_all.deb\n"
      "if [ -e " + shell_quote(marker.string()) + " ]; then cp \"$src\" . && exit 0; exit 1; fi\n"
      ": > " + shell_quote(marker.string()) + "\n"
      "head -c 2000 \"$src\" > \"${pkg}_1.0_all.deb\"\n"
      "exec sleep 60\n");
  fs::permissions(bin / "apt-get", fs::perms::owner_all);
  const std::string args = "corpus build --out " + out.string() + " --lists " + (build_inputs() / "lists").string() +
                           " --cache " + cache.string() + " --jobs 1";
  const std::string env = "PATH=" + bin.string() + ":/usr/bin:/bin";

  const fs::path log = logs("dl-kill");
  const pid_t pid = start_tagbench(args, log, env);
  const KillOutcome k = kill_when(pid, [&] { return file_named_under(cache, "pkga_1.0_all.deb"); });
  ASSERT_TRUE(k.killed_mid_run) << k.why << "\n" << slurp(log / "stderr");
  EXPECT_FALSE(fs::exists(cache / "pkga_1.0_all.deb")) << "a partial download is never under the package's name";

  const CommandResult r = run_tagbench_with(args, logs("dl-rerun"), env);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(cache / "pkga_1.0_all.deb"), slurp(build_inputs() / "debs" / "pkga_1.0_all.deb"));
  std::vector<std::string> cached;
  for (const auto& e : fs::directory_iterator(cache)) cached.push_back(e.path().filename().string());
  std::sort(cached.begin(), cached.end());
  EXPECT_EQ(cached, (std::vector<std::string>{"pkga_1.0_all.deb", "pkgb_1.0_all.deb"})) << "no download folder left";
  const auto a = file_tree(ref), b = file_tree(out);
  EXPECT_TRUE(a == b) << "the corpus differs from the uninterrupted one:\n" << tree_difference(a, b);
}

TEST(CorpusInterruption, CandidatesKilledMidRunThenRerunWritesTheUninterruptedStore) {
  const auto& [ref_bin, ref_tsv] = reference_store();
  ASSERT_GT(ref_bin.size(), 1000u);
  const fs::path corpus = root() / "cands-int";
  fs::remove_all(corpus);
  fs::copy(candidates_corpus(), corpus, fs::copy_options::recursive);
  const auto inputs = file_tree(corpus);
  const std::string args = "corpus candidates --corpus " + corpus.string();  // the store goes into the corpus

  // Killed once it has spent CPU time on the images (listing them costs next to nothing).
  const fs::path log = logs("cands-kill");
  const pid_t pid = start_tagbench(args + " --jobs 1", log);
  const KillOutcome k = kill_when(pid, [&] { return cpu_seconds(pid) >= 0.1; });
  ASSERT_TRUE(k.killed_mid_run) << k.why << "\n" << slurp(log / "stderr");
  EXPECT_FALSE(fs::exists(corpus / "corpus_candidates.bin"));
  EXPECT_FALSE(fs::exists(corpus / "corpus_candidates.tsv"));
  // As a kill while the pair was written would leave them.
  for (const char* f : {"corpus_candidates.bin", "corpus_candidates.tsv"})
    put(tagbench::atomic_temporary(corpus / f, pid), "half a store");

  const CommandResult r = run(args + " --jobs 3", "cands-rerun");
  ASSERT_EQ(r.code, 0) << r.err;
  auto after = file_tree(corpus);
  EXPECT_TRUE(after["corpus_candidates.bin"] == ref_bin) << "the rerun's store differs from the uninterrupted run's";
  EXPECT_EQ(after["corpus_candidates.tsv"], ref_tsv);
  after.erase("corpus_candidates.bin");
  after.erase("corpus_candidates.tsv");
  EXPECT_TRUE(after == inputs) << "besides the store, the folder holds what it held:\n"
                               << tree_difference(inputs, after);
}

TEST(CorpusDeterminism, CandidatesWithOneJobAndWithFourAreTheSameStore) {
  const auto& [ref_bin, ref_tsv] = reference_store();  // 2 jobs
  const auto store = tagbench::corpus::read_candidates(root() / "cands-ref" / "c.bin");
  ASSERT_EQ(store.images.size(), 17u);
  EXPECT_GT(store.records.size(), 500u) << "enough work for the jobs to interleave";
  for (const int jobs : {1, 4}) {
    const fs::path bin = root() / ("cands-j" + std::to_string(jobs)) / "c.bin";
    const CommandResult r = run("corpus candidates --corpus " + candidates_corpus().string() + " --jobs " +
                                std::to_string(jobs) + " --out " + bin.string());
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(slurp(bin) == ref_bin) << jobs << " jobs";
    EXPECT_EQ(slurp(tagbench::corpus::candidate_index_path(bin)), ref_tsv) << jobs << " jobs";
  }
  // Shards run with 1 and with 4 jobs merge to the same store.
  const fs::path s0 = root() / "cands-shards" / "0.bin", s1 = root() / "cands-shards" / "1.bin";
  ASSERT_EQ(run("corpus candidates --corpus " + candidates_corpus().string() + " --shard 0/2 --jobs 4 --out " +
                s0.string()).code, 0);
  ASSERT_EQ(run("corpus candidates --corpus " + candidates_corpus().string() + " --shard 1/2 --jobs 1 --out " +
                s1.string()).code, 0);
  const fs::path merged = root() / "cands-shards" / "merged.bin";
  const CommandResult m = run("corpus merge --out " + merged.string() + " " + s1.string() + " " + s0.string());
  ASSERT_EQ(m.code, 0) << m.err;
  EXPECT_TRUE(slurp(merged) == ref_bin);
  EXPECT_EQ(slurp(tagbench::corpus::candidate_index_path(merged)), ref_tsv);
}

}  // namespace test_corpus_interruption
