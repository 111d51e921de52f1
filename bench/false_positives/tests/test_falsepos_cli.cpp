// The false-positive experiments end to end on a small corpus made here, as `make bench` runs them:
// corpus candidates -> falsepos complexity / codes / detectors -> plots. The corpus: two stills
// and two video frames (a manifest as `corpus build` writes it), one of each holding 36h11 tags, so
// the counts that must come out are known: every tag is a "false" positive of every detector, and
// its quad's 6x6 payload is an exact 36h11 code in Fig. 7's store.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "run_tagbench.hpp"
#include "scenes.hpp"
#include "scratch_dir.hpp"

namespace test_falsepos_cli {

namespace fs = std::filesystem;
using tagbench::testing::run_tagbench;
using tagbench::testing::slurp;

namespace {

std::vector<std::map<std::string, std::string>> read_csv(const fs::path& p) {
  std::istringstream in(slurp(p));
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> out;
  auto split = [](const std::string& s) {
    std::vector<std::string> f;
    std::string cur;
    bool q = false;
    for (char c : s) {
      if (c == '"') q = !q;
      else if (c == ',' && !q) {
        f.push_back(cur);
        cur.clear();
      } else cur += c;
    }
    f.push_back(cur);
    return f;
  };
  while (std::getline(in, line)) {
    if (header.empty()) {
      header = split(line);
      continue;
    }
    const auto f = split(line);
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < header.size() && i < f.size(); ++i) row[header[i]] = f[i];
    out.push_back(std::move(row));
  }
  return out;
}

const char* kSha = "0000000000000000000000000000000000000000000000000000000000000000";

// 3 + 2 tags of 36h11 in a still and a video frame; a noise still and a gradient video frame.
void make_corpus(const fs::path& dir) {
  fs::create_directories(dir / "stills" / "g1");
  fs::create_directories(dir / "video" / "clip");
  cv::imwrite((dir / "stills/g1/tags.png").string(), tagbench::bench::make_scene(640, 480, "36h11", 3, 21).image);
  cv::Mat noise(300, 400, CV_8UC1);
  cv::randu(noise, 0, 256);
  cv::imwrite((dir / "stills/g1/noise.png").string(), noise);
  cv::imwrite((dir / "video/clip/c_f0.png").string(), tagbench::bench::make_scene(480, 360, "36h11", 2, 22).image);
  cv::Mat grad(240, 320, CV_8UC1);
  for (int y = 0; y < grad.rows; ++y)
    for (int x = 0; x < grad.cols; ++x) grad.at<uchar>(y, x) = static_cast<uchar>((x + y) / 3);
  cv::imwrite((dir / "video/clip/c_f5.png").string(), grad);
  std::ofstream m(dir / "manifest.tsv");
  m << "file\tgroup\tpackage\tversion\tpath\tlicence\tsha256\tkind\tframe\n";
  m << "stills/g1/tags.png\tg1\tp\t1\t/a\tx\t" << kSha << "\tstill\t\n";
  m << "stills/g1/noise.png\tg1\tp\t1\t/b\tx\t" << kSha << "\tstill\t\n";
  m << "video/clip/c_f0.png\tclip\tp\t1\t/c\tx\t" << kSha << "\tvideo-frame\t0\n";
  m << "video/clip/c_f5.png\tclip\tp\t1\t/c\tx\t" << kSha << "\tvideo-frame\t5\n";
}

}  // namespace

TEST(FalseposCli, TheThreeExperimentsOnASmallCorpus) {
  tagbench::testing::ScratchDir s("tagbench_falsepos");
  const fs::path corpus = s.path() / "corpus", out = s.path() / "results";
  make_corpus(corpus);
  fs::create_directories(out);
  const std::string store = (corpus / "corpus_candidates.bin").string();
  auto r = run_tagbench("corpus candidates --corpus " + corpus.string() + " --jobs 2", s.path());
  ASSERT_EQ(r.code, 0) << r.err;

  // Fig. 7: the five tags' quads carry exact 36h11 codes, so 36h11 accepts at least five at k = 0
  // (a tag's quad can be found more than once), in the still and video subsets 3 and 2 at least.
  r = run_tagbench("falsepos codes --candidates " + store + " --out " + out.string() + " --max-bits 3", s.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto fig7 = read_csv(out / "fig7_codes.csv");
  ASSERT_EQ(fig7.size(), 6u * 3u * 4u);  // 6 schemes x (all, still, video-frame) x k = 0..3
  for (const auto& row : fig7) {
    if (row.at("family") != "36h11" || row.at("bits_corrected") != "0") continue;
    const int accepted = std::stoi(row.at("accepted"));
    const std::string& sub = row.at("subset");
    EXPECT_GE(accepted, sub == "all" ? 5 : sub == "still" ? 3 : 2) << sub;
    EXPECT_GT(std::stod(row.at("ci95_hi")), std::stod(row.at("rate")));
  }
  EXPECT_NE(slurp(out / "fig7_codes.json").find("\"payload_records\""), std::string::npos);

  // Fig. 6 on three thresholds: families generated here, seeds 250900 + c.
  r = run_tagbench("falsepos complexity --candidates " + store + " --out " + out.string() + " --complexity 7-9", s.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto fig6 = read_csv(out / "fig6_complexity.csv");
  ASSERT_EQ(fig6.size(), 3u * 3u * 5u);
  EXPECT_EQ(fig6.front().at("scheme"), "25h9, complexity >= 7");
  EXPECT_EQ(fig6.back().at("min_complexity"), "9");
  const std::string js6 = slurp(out / "fig6_complexity.json");
  EXPECT_NE(js6.find("\"seed\": 250908"), std::string::npos);

  // Whole detectors: every one of ours and aruco's finds the five tags, nothing else.
  r = run_tagbench("falsepos detectors --corpus " + corpus.string() + " --out " + out.string() +
                       " --detectors tagbench-paper,aruco-default --families 36h11 --jobs 2",
                   s.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto det = read_csv(out / "fp_detectors.csv");
  int checked = 0;
  for (const auto& row : det) {
    const std::string& sub = row.at("subset");
    const std::string want = sub == "all" ? "5" : sub == "still" || sub == "group:g1" ? "3" : "2";
    EXPECT_EQ(row.at("detections"), want) << row.at("detector") << " " << sub;
    ++checked;
  }
  EXPECT_EQ(checked, 2 * 5);  // 2 detectors x (all, still, video-frame, group:clip, group:g1)
  EXPECT_EQ(read_csv(out / "fp_detections.csv").size(), 10u);

  // Our detector as an external one (tagbench detect -, all images in one run) finds the same false
  // detections, row for row, as the built-in one.
  const fs::path ext = s.path() / "external";
  fs::create_directories(ext);
  fs::create_directories(s.path() / "bad");
  // The built-in one reads the corpus as photographs (ComparatorSetup::input_gamma 2.2).
  const std::string mine = std::string(TAGBENCH_BIN) + " detect - --format jsonl --family 36h11 --input-gamma 2.2";
  r = run_tagbench("falsepos detectors --corpus " + corpus.string() + " --out " + ext.string() +
                       " --families 36h11 --jobs 2 --detectors 'tagbench,external:mine=" + mine + "'",
                   s.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto rows = read_csv(ext / "fp_detections.csv");
  std::vector<std::map<std::string, std::string>> builtin, external;
  for (auto row : rows) {
    const std::string who = row.at("detector");
    row.erase("detector");
    (who == "mine" ? external : builtin).push_back(row);
  }
  EXPECT_EQ(builtin.size(), 5u);
  EXPECT_EQ(external, builtin);
  EXPECT_NE(slurp(ext / "fp_detectors.json").find("\"external\": [{\"name\": \"mine\""), std::string::npos);
  r = run_tagbench("falsepos detectors --corpus " + corpus.string() + " --out " + (s.path() / "bad").string() +
                       " --families 36h11 --detectors 'external:bad=sh -c \"exit 9\"'",
                   s.path());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("external detector bad: exited with status 9 at image '"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(s.path() / "bad" / "fp_detectors.csv"));

  // The plots, as make bench draws them.
  const std::string plot = "/usr/bin/python3 " + std::string(TAGBENCH_SOURCE_DIR) + "/scripts/plot_falsepos.py " +
                           out.string() + " >/dev/null 2>&1";
  ASSERT_EQ(std::system(plot.c_str()), 0);
  for (const char* png : {"fig6_complexity.png", "fig7_codes.png", "fp_detectors.png"})
    EXPECT_GT(fs::file_size(out / png), 10000u) << png;
}

// The margin trade-off end to end: the corpus's five 36h11 tags are its "false" detections (clean
// synthetic tags, read with margins near 1), the true side a tiny ray-traced sweep; then the plot.
TEST(FalseposCli, MarginTradeoffOnASmallCorpusAndATinySweep) {
  tagbench::testing::ScratchDir s("tagbench_falsepos");
  const fs::path corpus = s.path() / "corpus", out = s.path() / "results";
  make_corpus(corpus);
  fs::create_directories(out);
  // One run into `into` on `jobs` threads; the frames are cached in the scratch folder.
  const auto margin = [&](const fs::path& into, int jobs) {
    return run_tagbench("falsepos margin --corpus " + corpus.string() + " --out " + into.string() +
                            " --families 36h11 --thresholds 0,0.5,1 --trials 2 --distances 2,4 --conditions noise"
                            " --processes 1 --jobs " + std::to_string(jobs) + " --cache " +
                            (s.path() / "cache").string(),
                        s.path());
  };
  const auto r = margin(out, 2);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto rows = read_csv(out / "margin_tradeoff.csv");
  ASSERT_EQ(rows.size(), 3u);
  for (const auto& row : rows) {
    const std::string& m = row.at("threshold");
    EXPECT_EQ(row.at("family"), "36h11");
    EXPECT_EQ(row.at("images"), "4");
    EXPECT_EQ(row.at("distance_frames"), "4");
    EXPECT_EQ(row.at("noise_frames"), "10");  // 2 trials x (baseline + 4 strengths)
    if (m == "0" || m == "0.5") {
      EXPECT_EQ(row.at("false_detections"), "5") << m;
      EXPECT_EQ(row.at("images_with_false"), "2") << m;
      EXPECT_EQ(row.at("distance_detected"), "4") << m;  // 1 m tag at 2 and 4 m: 200 and 100 px
      EXPECT_EQ(row.at("distance_range_m"), "4") << m;
      EXPECT_GE(std::stoi(row.at("noise_detected")), 8) << m;
    } else {
      // Margin 1 keeps only reads with every cell exactly at its model: fewer than at 0.5.
      EXPECT_EQ(m, "1");
      EXPECT_LE(std::stoi(row.at("distance_detected")), 4);
      EXPECT_LE(std::stoi(row.at("false_detections")), 5);
    }
  }
  const auto steps = read_csv(out / "margin_tradeoff_steps.csv");
  EXPECT_EQ(steps.size(), 3u * (2 + 5));  // thresholds x (2 distances + 5 noise strengths)
  const std::string js = slurp(out / "margin_tradeoff.json");
  EXPECT_NE(js.find("\"thresholds\": [0, 0.5, 1]"), std::string::npos) << js;
  EXPECT_NE(js.find("\"experiment\": \"conditions\", \"conditions\": [\"noise\"]"), std::string::npos) << js;
  // The same numbers from one thread (the frames now come from the cache).
  const fs::path again = s.path() / "again";
  fs::create_directories(again);
  const auto r1 = margin(again, 1);
  ASSERT_EQ(r1.code, 0) << r1.err;
  EXPECT_EQ(slurp(again / "margin_tradeoff.csv"), slurp(out / "margin_tradeoff.csv"));
  EXPECT_EQ(slurp(again / "margin_tradeoff_steps.csv"), slurp(out / "margin_tradeoff_steps.csv"));
  const std::string plot = "/usr/bin/python3 " + std::string(TAGBENCH_SOURCE_DIR) + "/scripts/plot_falsepos.py " +
                           out.string() + " margin >/dev/null 2>&1";
  ASSERT_EQ(std::system(plot.c_str()), 0);
  EXPECT_GT(fs::file_size(out / "margin_tradeoff.png"), 10000u);
}

TEST(FalseposCli, RefusesBadInputInOneLineWithoutOutput) {
  tagbench::testing::ScratchDir s("tagbench_falsepos");
  const fs::path out = s.path() / "results";
  fs::create_directories(out);
  fs::create_directories(s.path() / "empty");
  fs::create_directories(s.path() / "one");
  cv::Mat grey(50, 60, CV_8UC1, cv::Scalar(128));
  cv::imwrite((s.path() / "one" / "grey.png").string(), grey);
  std::ofstream(s.path() / "junk.bin") << "not a store";
  struct Case {
    std::string args, message;
    int code;
  };
  const std::vector<Case> cases{
      {"falsepos codes --out " + out.string(), "--candidates FILE is required", 2},
      {"falsepos codes --candidates " + (s.path() / "none.bin").string() + " --out " + out.string(), "none.bin: no such file", 1},
      {"falsepos codes --candidates " + (s.path() / "junk.bin").string() + " --out " + out.string(), "junk.bin", 1},
      {"falsepos complexity --candidates x --out " + (s.path() / "nowhere").string(), "nowhere: no such directory", 2},
      {"falsepos complexity --candidates x --out " + out.string() + " --complexity 9-3", "empty range", 2},
      {"falsepos detectors --corpus " + (s.path() / "empty").string() + " --out " + out.string(), "no images", 1},
      {"falsepos detectors --corpus " + (s.path() / "empty").string() + " --out " + out.string() + " --detectors nonesuch",
       "unknown detector 'nonesuch'", 2},
      {"falsepos detectors --corpus " + (s.path() / "empty").string() + " --out " + out.string() +
           " --detectors aruco-default --families 36h15",
       "no AprilTag dictionary for '36h15'", 2},
      {"falsepos margin --corpus " + (s.path() / "empty").string() + " --out " + out.string() + " --thresholds 0.5,0.2",
       "--thresholds: the thresholds must be ascending", 2},
      {"falsepos margin --corpus " + (s.path() / "empty").string() + " --out " + out.string() + " --thresholds 0,2",
       "--thresholds: 2 is outside the allowed range", 2},
      {"falsepos margin --corpus " + (s.path() / "empty").string() + " --out " + out.string() + " --conditions fog",
       "unknown condition 'fog'", 2},
      {"falsepos margin --corpus " + (s.path() / "empty").string() + " --out " + out.string() + " --families 36h99",
       "unknown family '36h99'", 2},
      {"falsepos margin --corpus " + (s.path() / "empty").string() + " --out " + out.string() + " --distances 0.5",
       "does not fit", 2},
      {"falsepos margin --corpus " + (s.path() / "empty").string() + " --out " + out.string(), "no images", 1},
      {"falsepos margin --corpus " + (s.path() / "one").string() + " --out " + out.string() +
           " --povray ./nopovray --trials 1 --distances 2 --conditions none --cache " + (s.path() / "cache").string(),
       "povray './nopovray': not an executable file", 1},
      {"falsepos frobnicate", "unknown subcommand 'frobnicate'", 2},
  };
  for (const auto& c : cases) {
    const auto r = run_tagbench(c.args, s.path());
    EXPECT_EQ(r.code, c.code) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << c.args << "\n" << r.err;
    EXPECT_TRUE(fs::is_empty(out)) << c.args;
  }
}

}  // namespace test_falsepos_cli
