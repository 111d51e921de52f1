// The open benchmark end to end (issue 12, sections 1 and 2): `tagbench dataset export`, then
// `tagbench detect --format jsonl` on its frames, then `tagbench score` gives exactly the rows and
// summaries `tagbench raytrace` gives the same detector (all but the timing column), at full and half
// resolution; bad input is one line and writes nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "../../raytrace/tests/test_frames.hpp"
#include "run_tagbench.hpp"
#include "scratch_dir.hpp"

namespace test_cli_score {

namespace fs = std::filesystem;

namespace {

using tagbench::testing::CommandResult;
using tagbench::testing::run_tagbench;
using tagbench::testing::slurp;

// Every column but the timing one (`ms`) and the loss stage (`loss_stage`, `loss_bits`: the sweep
// explains a frame ours missed, the scorer of another detector's output cannot).
std::string without_ms(const std::string& csv) {
  std::istringstream in(csv);
  std::string out;
  std::size_t ms = std::string::npos, loss = std::string::npos;
  for (std::string l; std::getline(in, l);) {
    std::vector<std::string> cells;
    std::istringstream cs(l);
    for (std::string c; std::getline(cs, c, ',');) cells.push_back(c);
    if (!l.empty() && l.back() == ',') cells.push_back("");
    if (ms == std::string::npos) {
      ms = static_cast<std::size_t>(std::find(cells.begin(), cells.end(), "ms") - cells.begin());
      loss = static_cast<std::size_t>(std::find(cells.begin(), cells.end(), "loss_stage") - cells.begin());
    }
    for (std::size_t i = 0; i < cells.size(); ++i)
      if (i != ms && i != loss && i != loss + 1) out += cells[i] + (i + 1 < cells.size() ? "," : "");
    out += "\n";
  }
  return out;
}

std::string sweep_options() { return "angle --angles 0,50 --trials 2 --processes 1 --cache " + tagbench::bench::test::shared_cache().string(); }

// Export `options`' dataset, run ours on it through detect --format jsonl (with `camera` options) and
// score it: the rows equal `tagbench raytrace`'s for the same detector; `stem` names the files.
void export_detect_score_equals_the_sweep(const std::string& options, const std::string& camera, const std::string& stem,
                                          const std::string& last_frame) {
  tagbench::testing::ScratchDir dir("tagbench_cli_score");
  const fs::path ds = dir / "ds";
  CommandResult r = run_tagbench("dataset export " + options + " --out " + ds.string(), dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(ds / "truth.json"));
  EXPECT_TRUE(fs::exists(ds / last_frame));
  r = run_tagbench("raytrace " + options + " --detectors tagbench,tagbench-half --out " + (dir / "rt").string(),
                   dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string rt_rows = slurp(dir / "rt" / (stem + ".csv"));
  for (const auto& [name, extra] : {std::pair<std::string, std::string>{"tagbench", ""}, {"tagbench-half", " --half-res"}}) {
    r = run_tagbench("detect " + ds.string() + " --format jsonl --family 36h11 --input-gamma 1 " + camera + extra + " --threads 1",
                     dir.path());
    ASSERT_EQ(r.code, 0) << r.err;
    const fs::path lines = dir / (name + ".jsonl");
    std::ofstream(lines) << r.out;
    const fs::path out = dir / ("score-" + name);
    r = run_tagbench("score " + ds.string() + " " + lines.string() + " --out " + out.string(), dir.path());
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err.find("fits the truth far better"), std::string::npos) << r.err;
    // The built-in rows of this detector, in frame order.
    std::string want;
    std::istringstream in(rt_rows);
    for (std::string l; std::getline(in, l);)
      if (want.empty() || l.find("," + name + ",") != std::string::npos) want += l + "\n";
    EXPECT_EQ(without_ms(slurp(out / (stem + ".csv"))), without_ms(want)) << name;
    EXPECT_TRUE(fs::exists(out / (stem + "_summary.csv")));
    EXPECT_NE(slurp(out / (stem + ".json")).find("\"tool\": \"tagbench score\""), std::string::npos);
    if (stem == "sixdof") {  // the settings scripts/plot_sixdof.py reads
      EXPECT_NE(slurp(out / "sixdof.json").find("\"sixdof\": {\"frames\": 4, \"distance_range_m\": [0.5, 3]"),
                std::string::npos);
    }
  }
}

TEST(CliScore, ExportDetectScoreEqualsTheBuiltInSweep) {
  if (!tagbench::bench::test::have_povray()) GTEST_SKIP() << "povray not installed";
  export_detect_score_equals_the_sweep(sweep_options(), "--camera 400,400,199.5,199.5 --tag-size 0.166", "fig9_angle",
                                       "frame_00003.png");
}

TEST(CliScore, ExportDetectScoreEqualsTheBuiltInSixdofSweep) {
  // The 6-DoF sweep's frames carry its lens, defocus and noise; truth.json gives the lens to a detector.
  if (!tagbench::bench::test::have_povray()) GTEST_SKIP() << "povray not installed";
  export_detect_score_equals_the_sweep(
      "sixdof --frames 4 --distance-range 0.5,3 --processes 1 --cache " + tagbench::bench::test::shared_cache().string(),
      "--camera 400,400,199.5,199.5 --tag-size 0.166 --distortion -0.2,0.05,0.001,-0.0005,0", "sixdof", "frame_00003.png");
}

TEST(CliScore, BadInputIsOneLineAndWritesNothing) {
  tagbench::testing::ScratchDir dir("tagbench_cli_score");
  CommandResult r = run_tagbench("score " + (dir / "nothing").string() + " x.jsonl --out " + (dir / "o").string(), dir.path());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("nothing"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(dir / "o"));
  r = run_tagbench("score a b --corner-order tl-tr-br --out " + (dir / "o").string(), dir.path());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("corner order 'tl-tr-br'"), std::string::npos) << r.err;
  r = run_tagbench("dataset export angle --angles 95 --out " + (dir / "d").string(), dir.path());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("angle 95 is outside [0, 90)"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "d"));
  r = run_tagbench("dataset export angle", dir.path());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--out DIR is required"), std::string::npos) << r.err;
  r = run_tagbench("score --help", dir.path());
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("--corner-order"), std::string::npos);
  r = run_tagbench("dataset export --help", dir.path());
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("truth.json"), std::string::npos);
}

}  // namespace

}  // namespace test_cli_score
