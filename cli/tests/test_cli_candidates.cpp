// `tagbench corpus candidates|score|list` on the tiny corpus of the candidate tests
// (corpus_tools/tests/candidate_corpus.hpp): the program's store equals the library's at any --jobs, a
// manifest is followed, a damaged store is one line, a folder without images is one line and writes nothing, a full disk leaves
// neither file, scoring a store without quads of the family's size says so, `corpus list` decodes.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "candidates.hpp"
#include "sources.hpp"
#include "tests/candidate_corpus.hpp"
#include "tools/atomic_file.hpp"

#include "kill_run.hpp"

namespace test_cli_candidates {

namespace fs = std::filesystem;
using namespace tagbench;
using namespace tagbench::corpus;
using namespace tagbench::corpus::testing;

namespace {


struct Result {
  int code = -1;
  std::string out, err;
};
Result run(const std::string& args) {
  const fs::path out = corpus_dir() / "stdout.txt", err = corpus_dir() / "stderr.txt";
  const std::string cmd =
      std::string(TAGBENCH_BIN) + " " + args + " >" + out.string() + " 2>" + err.string() + " </dev/null";
  const int st = std::system(cmd.c_str());
  Result r{WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st), slurp(out), slurp(err)};
  fs::remove(out);
  fs::remove(err);
  return r;
}

}  // namespace

TEST(CandidatesCli, CommandLine) {
  const fs::path a = corpus_dir() / "out" / "j1.bin", b = corpus_dir() / "out" / "j2.bin";
  const auto r1 = run("corpus candidates --corpus " + corpus_dir().string() + " --out " + a.string() + " --jobs 1");
  ASSERT_EQ(r1.code, 0) << r1.err;
  const auto r2 = run("corpus candidates --corpus " + corpus_dir().string() + " --out " + b.string() + " --jobs 2");
  ASSERT_EQ(r2.code, 0) << r2.err;
  EXPECT_EQ(slurp(a), slurp(b));
  EXPECT_EQ(slurp(corpus_dir() / "out" / "j1.tsv"), slurp(corpus_dir() / "out" / "j2.tsv"));
  EXPECT_EQ(slurp(a), encode_candidates(store1()));
  EXPECT_NE(r1.err.find("unreadable: broken.jpg"), std::string::npos) << r1.err;

  const auto s = run("corpus score --candidates " + a.string() + " --family 36h11,16h5 --max-bits 2");
  ASSERT_EQ(s.code, 0) << s.err;
  std::istringstream in(s.out);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "family\tbits_corrected\tquads\taccepted\trate");
  std::vector<std::string> rows;
  while (std::getline(in, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 6u);
  const auto sc = score_family(store1().records, builtin_family("36h11"), 2);
  EXPECT_EQ(rows[0].rfind("36h11\t0\t" + std::to_string(sc.quads) + "\t" + std::to_string(sc.accepted[0]) + "\t", 0),
            0u)
      << rows[0];
  EXPECT_EQ(rows[3].rfind("16h5\t0\t", 0), 0u) << rows[3];

  // A corpus with a manifest is read through it.
  const fs::path m = side_dir("withmanifest");  // not in the corpus, whose listing the other tests rely on
  fs::create_directories(m / "stills" / "g");
  fs::copy_file(corpus_dir() / "tag.png", m / "stills" / "g" / "t.png");
  write_file_atomic(m / "manifest.tsv",
                    manifest_tsv({{"stills/g/t.png", "g", "pkg", "1", "/usr/t.png", "MIT", std::string(64, 'a'),
                                   "still", -1}}));
  const auto rm = run("corpus candidates --corpus " + m.string() + " --jobs 2");
  ASSERT_EQ(rm.code, 0) << rm.err;
  const auto st = read_candidates(m / "corpus_candidates.bin");
  ASSERT_EQ(st.images.size(), 1u);
  EXPECT_EQ(st.images[0].group, "g");
  EXPECT_EQ(st.images[0].kind, "still");
  EXPECT_GE(score_family(st.records, builtin_family("36h11"), 0).accepted[0], 1u);
  EXPECT_NE(run("corpus candidates --corpus " + (m / "nope").string()).code, 0);
}

TEST(CandidatesCli, ADamagedStoreIsOneLine) {
  const std::string good = encode_candidates(store1());
  const fs::path f = corpus_dir() / "out" / "cut.bin";
  fs::create_directories(f.parent_path());
  write_file_atomic(f, good.substr(0, good.size() - 7));
  const auto r = run("corpus score --candidates " + f.string() + " --family 36h11");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("cut.bin"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(CandidatesCli, CorpusListDecodesEveryImage) {
  const fs::path d = side_dir("listing");
  fs::copy_file(corpus_dir() / "tag.png", d / "tag.png", fs::copy_options::overwrite_existing);
  const std::string bytes = slurp(d / "tag.png");
  std::ofstream(d / "cut.png", std::ios::binary) << bytes.substr(0, bytes.size() / 3);  // signature intact
  std::ofstream(d / "fake.png", std::ios::binary) << "no image signature";
  std::ofstream(d / "readme.txt") << "not an image";
  const auto r = run("corpus list --from " + d.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("unreadable\t" + (d / "cut.png").string()), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("ok\t" + (d / "tag.png").string() + "\t300\t220"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("1 images, 2 unreadable, 1 other files"), std::string::npos) << r.err;
}

TEST(CandidatesCli, AFolderWithoutImagesIsAnErrorNamingItAndNothingIsWritten) {
  const fs::path empty = side_dir("noimages"), text = side_dir("onlytext"), manifest = side_dir("emptymanifest");
  std::ofstream(text / "notes.txt") << "no image here";
  write_file_atomic(manifest / "manifest.tsv", manifest_tsv({}));
  for (const auto& [dir, why] : {std::pair{empty, "no image file under it"}, std::pair{text, "no image file under it"},
                                 std::pair{manifest, "its manifest.tsv lists none"}}) {
    std::vector<fs::path> before;
    for (const auto& e : fs::recursive_directory_iterator(dir)) before.push_back(e.path());
    for (const std::string extra : {"", " --shard 0/2"}) {
      const auto r = run("corpus candidates --corpus " + dir.string() + extra);
      EXPECT_EQ(r.code, 1) << dir;
      EXPECT_EQ(r.err, "tagbench corpus candidates: " + dir.string() + ": no images (" + why + ")\n");
    }
    std::vector<fs::path> after;
    for (const auto& e : fs::recursive_directory_iterator(dir)) after.push_back(e.path());
    EXPECT_EQ(after, before) << "nothing written in " << dir;
  }
}

TEST(CandidatesCli, ScoringAStoreWithoutQuadsOfTheFamilysSizeWorksAndSaysSo) {
  const fs::path d = side_dir("blankonly");
  cv::imwrite((d / "blank.png").string(), cv::Mat(60, 80, CV_8UC1, cv::Scalar(128)));
  const auto c = run("corpus candidates --corpus " + d.string());
  ASSERT_EQ(c.code, 0) << c.err;
  const auto r =
      run("corpus score --candidates " + (d / "corpus_candidates.bin").string() + " --family 36h11,16h5 --max-bits 1");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, "family\tbits_corrected\tquads\taccepted\trate\n36h11\t0\t0\t0\t0\n36h11\t1\t0\t0\t0\n"
                   "16h5\t0\t0\t0\t0\n16h5\t1\t0\t0\t0\n");
  for (const char* f : {"36h11 (6x6)", "16h5 (4x4)"})
    EXPECT_NE(r.err.find("tagbench corpus score: note: " + (d / "corpus_candidates.bin").string() +
                         " has no quad of the payload size of " + f),
              std::string::npos)
        << r.err;
  // A store with quads of the size: no note.
  const fs::path full = side_dir("withquads") / "c.bin";
  write_candidates(full, store1());
  const auto ok = run("corpus score --candidates " + full.string() + " --family 36h11");
  EXPECT_EQ(ok.code, 0) << ok.err;
  EXPECT_EQ(ok.err.find("note:"), std::string::npos) << ok.err;
}

TEST(CandidatesCli, AFullDiskLeavesNeitherTheStoreNorItsIndex) {
  const fs::path out = side_dir("fulldisk"), logs = side_dir("fulldisk-logs");
  const std::size_t tsv = candidate_index_tsv(store1().images).size(), bin = encode_candidates(store1()).size();
  ASSERT_LT(tsv + 100, bin) << "the index must fit where the store does not";
  // Files up to the index's size plus a little can be written: the index would be, the store not.
  const auto r = tagbench::testing::run_tagbench_with(
      "corpus candidates --corpus " + corpus_dir().string() + " --out " + (out / "c.bin").string(), logs, "",
      static_cast<long long>(tsv + 100));
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_EQ(r.err.rfind("tagbench corpus candidates: cannot write " + (out / "c.bin").string(), 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_TRUE(fs::is_empty(out)) << "no store, no index, no temporary";
}

}  // namespace test_cli_candidates
