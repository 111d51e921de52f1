// The `tagbench` program end to end: family, render, generate (with a kill -9 and resume) and the
// bad-input rules (one-line error naming the problem, non-zero exit, no output file left behind).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <opencv2/imgcodecs.hpp>

#include "codes/families.hpp"
#include "codes/family_io.hpp"

#include "run_tagbench.hpp"
#include "scratch_dir.hpp"

namespace test_cli {

namespace fs = std::filesystem;
using namespace tagbench;

namespace {

using Result = tagbench::testing::CommandResult;

std::string bin() { return TAGBENCH_BIN; }

using tagbench::testing::slurp;

fs::path scratch(const std::string& name) {
  const fs::path d = tagbench::testing::program_scratch("tagbench_cli");
  fs::create_directories(d);
  return d / name;
}

Result run(const std::string& args) { return tagbench::testing::run_tagbench(args, scratch("").parent_path()); }

// A bad input: non-zero exit, exactly one line on stderr mentioning `fragment`, and `out` not created.
void expect_refused(const std::string& args, const std::string& fragment, const fs::path& out = {}) {
  const Result r = run(args);
  EXPECT_NE(r.code, 0) << args;
  EXPECT_LT(r.code, 128) << "crashed: " << args;
  EXPECT_NE(r.err.find(fragment), std::string::npos) << args << "\nstderr: " << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line: " << r.err;
  if (!out.empty()) {
    EXPECT_FALSE(fs::exists(out)) << out;
  }
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

}  // namespace

TEST(Cli, HelpForEveryCommand) {
  for (const char* c : {"--help", "family --help", "family generate --help", "render --help", "codes --help",
                        "generator-speed --help", "corpus --help"}) {
    const Result r = run(c);
    EXPECT_EQ(r.code, 0) << c;
    EXPECT_NE(r.out.find("usage: tagbench"), std::string::npos) << c;
  }
  expect_refused("frobnicate", "unknown command 'frobnicate'");
}

TEST(Cli, FamilyListShowStats) {
  const Result list = run("family list");
  ASSERT_EQ(list.code, 0);
  for (const char* n : {"16h5", "25h9", "artoolkitplus-bch", "artag-2046"}) EXPECT_NE(list.out.find(n), std::string::npos);
  const Result show = run("family show 16h5");
  ASSERT_EQ(show.code, 0);
  EXPECT_EQ(std::count(show.out.begin(), show.out.end(), '\n'), 30);
  EXPECT_EQ(show.out.rfind("0x231b\n", 0), 0u);
  const Result stats = run("family stats 25h9 artoolkitplus-simple");
  ASSERT_EQ(stats.code, 0);
  EXPECT_NE(stats.out.find("family 25h9: 35 codes"), std::string::npos);
  EXPECT_NE(stats.out.find("minimum distance with rotations:    9"), std::string::npos);
  EXPECT_NE(stats.out.find("minimum distance with rotations:    4"), std::string::npos);
}

TEST(Cli, GenerateWritesTheFamilyFileAndCpp) {
  const fs::path out = scratch("g16h5.fam");
  const Result r = run("family generate --bits 16 --hamming 5 --threads 2 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const TagFamily f = read_family_file(out);
  EXPECT_EQ(f.codes(), builtin_family("16h5").codes());
  EXPECT_EQ(f.info().seed.value(), 160505);
  EXPECT_EQ(run("family check " + out.string()).code, 0);
  const Result cpp = run("family generate --bits 16 --hamming 5 --format cpp");
  ASSERT_EQ(cpp.code, 0);
  EXPECT_NE(cpp.out.find("tag16h5_codes[30]"), std::string::npos);
  EXPECT_NE(cpp.out.find("0x231bULL"), std::string::npos);
  const Result lex = run("family generate --bits 9 --hamming 3 --complexity 2 --order lex");
  ASSERT_EQ(lex.code, 0);
  EXPECT_NE(lex.out.find("name: 9h3_c2_lex"), std::string::npos);
}

TEST(Cli, KilledGenerationResumesToTheIdenticalFamily) {
  const fs::path ckpt = scratch("25h7.ckpt"), out = scratch("25h7.fam");
  // The scratch folder is named by pid and may hold files of an earlier run whose pid was the same.
  fs::remove(ckpt);
  fs::remove(out);
  const std::string args = "family generate --bits 25 --hamming 7 --threads 1 --checkpoint-seconds 0.02 --checkpoint " +
                           ckpt.string() + " --out " + out.string();
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::execl("/bin/sh", "sh", "-c", ("exec " + bin() + " " + args + " 2>/dev/null").c_str(), nullptr);
    ::_exit(127);
  }
  // Kill -9 as soon as a checkpoint with some progress exists.
  bool killed = false;
  for (int i = 0; i < 2000 && !killed; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    if (fs::exists(ckpt)) {
      ::kill(pid, SIGKILL);
      killed = true;
    }
  }
  int st = 0;
  ::waitpid(pid, &st, 0);
  ASSERT_TRUE(killed && WIFSIGNALED(st)) << "the run finished before it could be killed";
  EXPECT_FALSE(fs::exists(out)) << "no output from a killed run";
  const Checkpoint c = read_checkpoint(ckpt);
  EXPECT_GT(c.state.next_index, 0u);
  EXPECT_LT(c.state.next_index, std::uint64_t{1} << 25);
  const Result r = run("family generate --checkpoint " + ckpt.string() + " --resume --threads 2 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(read_family_file(out).codes(), builtin_family("25h7").codes());
  EXPECT_FALSE(fs::exists(ckpt)) << "a completed run removes its checkpoint";
}

TEST(Cli, RenderPngAndSvg) {
  const fs::path png = scratch("t.png"), big = scratch("t10.png"), svg = scratch("t.svg");
  ASSERT_EQ(run("render --family 16h5 --id 0 -o " + png.string()).code, 0);
  const cv::Mat img = cv::imread(png.string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(img.rows, 8);
  ASSERT_EQ(img.cols, 8);
  EXPECT_EQ(img.at<std::uint8_t>(0, 0), 255);  // white ring
  EXPECT_EQ(img.at<std::uint8_t>(1, 1), 0);    // black ring
  // Payload: 0x231b, MSB = top-left payload cell (pixel 2,2), row-major.
  const Code code = builtin_family("16h5").codes()[0];
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x)
      EXPECT_EQ(img.at<std::uint8_t>(2 + y, 2 + x), ((code >> (15 - (4 * y + x))) & 1) ? 255 : 0);
  ASSERT_EQ(run("render --family 36h15 --id 3 --px-per-cell 10 -o " + big.string()).code, 0);
  EXPECT_EQ(cv::imread(big.string(), cv::IMREAD_UNCHANGED).rows, 100);
  ASSERT_EQ(run("render --family 25h9 --id 1 --tag-size-mm 70 -o " + svg.string()).code, 0);
  const std::string s = slurp(svg);
  EXPECT_NE(s.find("width=\"90mm\""), std::string::npos) << "9 cells of 10 mm: black square 7 cells = 70 mm";
  EXPECT_NE(s.find("<svg"), std::string::npos);
}

TEST(Cli, BadInputIsRefusedOnOneLine) {
  const fs::path out = scratch("never.png"), fam = scratch("never.fam");
  expect_refused("render --family 36h99 --id 0 -o " + out.string(), "unknown family '36h99'", out);
  expect_refused("render --family 16h5 --id 30 -o " + out.string(), "id 30 is out of range for family 16h5 (0..29)", out);
  expect_refused("render --family 16h5 --id -1 -o " + out.string(), "--id", out);
  expect_refused("render --family 16h5 --id 0 -o " + scratch("x.bmp").string(), "unknown output format");
  expect_refused("render --family 16h5 --id 0 -o /no/such/dir/x.png", "/no/such/dir/x.png");
  expect_refused("family generate --bits 20 --hamming 5 --out " + fam.string(), "not the square", fam);
  expect_refused("family generate --bits 81 --hamming 5 --out " + fam.string(), "--bits", fam);
  expect_refused("family generate --bits 16 --hamming 17 --out " + fam.string(), "hamming 17", fam);
  expect_refused("family generate --bits 16 --hamming x", "--hamming: 'x' is not an integer");
  expect_refused("family generate --bits 16 --hamming 5 --order random", "unknown candidate order 'random'");
  expect_refused("family generate --bits 16 --hamming 5 --bogus", "unknown option '--bogus'");
  expect_refused("family generate --resume", "--resume needs --checkpoint");
  expect_refused("family show 36h99", "unknown family '36h99'");
  expect_refused("family show /no/such.fam", "no such file");

  const std::string good = slurp(fs::path(TAGBENCH_SOURCE_DIR) / "detector/codes/families/tag16h5.fam");
  const auto bad = [&](const std::string& name, const std::string& from, const std::string& to) {
    std::string t = good;
    t.replace(t.find(from), from.size(), to);
    const fs::path p = scratch(name);
    write(p, t);
    return p.string();
  };
  expect_refused("family show " + bad("nonhex.fam", "0x2ea5", "0x2ez5"), "not a hex code: '0x2ez5'");
  expect_refused("family show " + bad("count.fam", "count: 30", "count: 31"), "count 31 but the file has 30");
  expect_refused("family show " + bad("dup.fam", "0x2ea5", "0x231b"), "duplicate code 0x231b");
  expect_refused("family stats " + bad("close.fam", "hamming: 5", "hamming: 7"), "closer than h=7");
  expect_refused("render --family " + bad("close2.fam", "hamming: 5", "hamming: 7") + " --id 0 -o " + out.string(),
                 "closer than h=7", out);
}

TEST(Cli, SceneGroundTruthAndDetectAgree) {
  const fs::path png = scratch("scene.png"), json = scratch("scene.json");
  ASSERT_EQ(run("scene --width 480 --height 360 --count 4 --seed 9 -o " + png.string()).code, 0);
  ASSERT_TRUE(fs::exists(json));
  const std::string truth = slurp(json);
  const Result r = run("detect " + png.string() + " --format csv");
  ASSERT_EQ(r.code, 0) << r.err;
  // Every true tag is detected once with its corners within 0.3 px (ids come from the seed).
  std::istringstream lines(r.out);
  std::string line;
  std::getline(lines, line);  // header
  int rows = 0;
  while (std::getline(lines, line)) {
    ++rows;
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) f.push_back(c);
    const std::string id = f[2];
    const auto at = truth.find("{\"id\": " + id + ",");
    ASSERT_NE(at, std::string::npos) << "id " << id << " is not in the scene";
    std::stringstream t(truth.substr(truth.find("[[", at) + 2));
    for (int k = 0; k < 4; ++k) {
      double x = 0, y = 0;
      char ch = 0;
      t >> x >> ch >> y;
      while (t.peek() == ']' || t.peek() == ',' || t.peek() == ' ' || t.peek() == '[') t.get();
      EXPECT_NEAR(std::stod(f[static_cast<std::size_t>(6 + 2 * k)]), x, 0.3) << "id " << id << " corner " << k;
      EXPECT_NEAR(std::stod(f[static_cast<std::size_t>(7 + 2 * k)]), y, 0.3) << "id " << id << " corner " << k;
    }
  }
  EXPECT_EQ(rows, 4);
  expect_refused("scene -o " + scratch("x.jpg").string(), "written as .png");
  expect_refused("scene --family 36h99 -o " + scratch("y.png").string(), "unknown family '36h99'", scratch("y.png"));
}

}  // namespace test_cli
