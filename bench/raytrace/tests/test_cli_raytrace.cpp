// `tagbench raytrace` end to end (issue 4, sections 2 and 4): a small run writes its three files with
// one row per frame and detector, a rerun renders nothing and writes the same rows, bad options are
// refused with one line and no output, a missing POV-Ray is one line naming the package, and a frame
// that fails to render is reported while the run goes on.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "csv_timing.hpp"
#include "raytrace/render.hpp"
#include "test_frames.hpp"

#include "run_tagbench.hpp"
#include "scratch_dir.hpp"

namespace test_cli_raytrace {

namespace fs = std::filesystem;

namespace {

using Result = tagbench::testing::CommandResult;

using tagbench::testing::slurp;

// The program's scratch folder (made on first use, removed at exit).
const fs::path& scratch() { return tagbench::testing::program_scratch("tagbench_cli_raytrace"); }

Result run(const std::string& args) { return tagbench::testing::run_tagbench("raytrace " + args, scratch()); }

using tagbench::testing::lines;

// The rows without the timing column (the last one).
std::string without_ms(const std::string& csv) { return tagbench::testing::csv_without_timing(csv); }

std::string common(const fs::path& out) {
  return "--processes 1 --cache " + tagbench::bench::test::shared_cache().string() + " --out " + out.string();
}

}  // namespace

TEST(CliRaytrace, HelpNamesTheExperimentsAndTheFiles) {
  const Result r = run("--help");
  EXPECT_EQ(r.code, 0);
  for (const char* s : {"usage: tagbench raytrace angle|distance|conditions|sixdof", "--trials", "--frames", "--lens", "sixdof.csv", "--tag-size", "--seed",
                        "--detectors", "--scene", "--processes", "--cache", "--out", "fig9_angle.csv",
                        "fig10_distance.csv", "conditions.csv", "_summary.csv", "66 px"})
    EXPECT_NE(r.out.find(s), std::string::npos) << s;
}

TEST(CliRaytrace, BadOptionsAreRefusedWithOneLineAndNoOutput) {
  const fs::path out = scratch() / "refused";
  fs::remove_all(out);
  const std::string o = " --out " + out.string() + " --cache " + (scratch() / "refused-cache").string();
  const std::pair<std::string, std::string> cases[] = {
      {"", "which experiment?"},
      {"height", "unknown experiment 'height'"},
      {"angle --angles 90", "angle 90 is outside [0, 90) degrees"},
      {"angle --angles 0,-5", "angle -5 is outside [0, 90) degrees"},
      {"angle --angles 10,x", "--angles: 'x' is not a finite number"},
      {"distance --distances 0", "distance must be in (0, 1e6] metres"},
      {"distance --distances 5,-2", "distance must be in (0, 1e6] metres"},
      {"angle --distance 0", "distance must be in (0, 1e6] metres"},
      {"angle --trials 0", "trials must be in 1..1000000"},
      {"angle --trials 1000000000", "trials must be in 1..1000000"},
      {"conditions --trials -1", "trials must be in 1..1000000"},
      {"angle --tag-size 0", "tag size must be in [0.001, 1000] metres"},
      {"angle --detectors tagbench-paper,zbar", "unknown detector 'zbar'"},
      {"angle --scene studio", "unknown scene 'studio' (plain, realistic)"},
      {"conditions --conditions noise,fog", "unknown condition 'fog'"},
      {"distance --distances 1", "does not fit"},
      {"angle --distances 5", "--distances belongs to the distance sweep"},
      {"angle --frobnicate", "unknown option '--frobnicate'"},
      {"sixdof --trials 3", "--trials: the sixdof sweep takes --frames N"},
      {"sixdof --frames 0", "frames must be in 1..1000000"},
      {"sixdof --distance 2", "--distance: the sixdof sweep takes --distance-range A,B"},
      {"sixdof --distance-range 3", "--distance-range: expected A,B (metres), got '3'"},
      {"sixdof --distance-range 3,1", "distance range must be 0 < A <= B metres (got 3,1)"},
      {"sixdof --distance-range 0.05,0.1", "the tag does not fit in the 400 x 400 image"},
      {"sixdof --phi-max 95", "phi max 95 is outside [0, 90) degrees"},
      {"sixdof --lens 0.1,0", "--lens: expected k1,k2,p1,p2,k3 (OpenCV's model), got '0.1,0'"},
      {"sixdof --lens 0,0,0,0,x", "--lens: 'x' is not a finite number"},
      {"sixdof --noise-max -1", "noise max -1 is outside [0, 255] levels"},
      {"sixdof --defocus-max 99", "defocus max 99 is outside [0, 50] px"},
      {"sixdof --bins 0", "bins must be in 1..100 (got 0)"},
      {"sixdof --angles 5", "--angles belongs to the angle sweep"},
      {"angle --frames 5", "--frames belongs to the sixdof sweep"},
      {"conditions --lens 0,0,0,0,0", "--lens belongs to the sixdof sweep"},
  };
  for (const auto& [args, fragment] : cases) {
    const Result r = run(args + o);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_NE(r.err.find(fragment), std::string::npos) << args << "\nstderr: " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line: " << r.err;
    EXPECT_EQ(r.err.rfind("tagbench raytrace: ", 0), 0u) << r.err;
    EXPECT_FALSE(fs::exists(out)) << args;
  }
  EXPECT_FALSE(fs::exists(scratch() / "refused-cache")) << "nothing created for refused options";
}

// A path or a name given with --povray that cannot be run: that one (the default name missing from
// PATH names the package to install: test_bad_input).
TEST(CliRaytrace, MissingPovrayIsOneLineNamingThePackageOrThePath) {
  const fs::path out = scratch() / "nopovray", cache = scratch() / "nopovray-cache";
  fs::remove_all(out);
  fs::remove_all(cache);
  Result r = run("angle --trials 1 --angles 10 --detectors tagbench-paper --povray /nonexistent/povray --cache " +
                 cache.string() + " --out " + out.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.err, "tagbench raytrace: povray '/nonexistent/povray': not an executable file\n");
  EXPECT_FALSE(fs::exists(out));
  r = run("angle --trials 1 --angles 10 --detectors tagbench-paper --povray no-such-povray-name --cache " +
          cache.string() + " --out " + out.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.err, "tagbench raytrace: povray 'no-such-povray-name': no executable of this name in PATH\n");
  EXPECT_FALSE(fs::exists(out));
}

TEST(CliRaytrace, SmallRunWritesRowsSummaryAndSidecarAndARerunRendersNothing) {
  if (!tagbench::bench::test::have_povray()) GTEST_SKIP() << "povray is not installed";
  const fs::path a = scratch() / "run-a", b = scratch() / "run-b";
  fs::remove_all(a);
  fs::remove_all(b);
  const std::string args = "angle --trials 2 --angles 0,40 --detectors tagbench-paper,aruco ";
  const Result first = run(args + common(a));
  ASSERT_EQ(first.code, 0) << first.err;
  const auto rows = lines(slurp(a / "fig9_angle.csv"));
  ASSERT_EQ(rows.size(), 1u + 2 * 2 * 2);  // header + frames x detectors
  EXPECT_EQ(rows[0].rfind("experiment,condition,step,step_unit,trial,seed,", 0), 0u);
  for (std::size_t i = 1; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].rfind("angle,none,", 0), 0u) << rows[i];
    EXPECT_TRUE(rows[i].find(",tagbench-paper,") != std::string::npos || rows[i].find(",aruco,") != std::string::npos);
    if (rows[i].find(",tagbench-paper,") != std::string::npos) {
      EXPECT_NE(rows[i].find(",tagbench-paper,1,0,"), std::string::npos) << "ours finds it: " << rows[i];
    }
  }
  const auto summary = lines(slurp(a / "fig9_angle_summary.csv"));
  ASSERT_EQ(summary.size(), 1u + 2 * 2);  // header + steps x detectors
  EXPECT_NE(summary[0].find("detection_rate,rate_lo95,rate_hi95"), std::string::npos);
  const std::string json = slurp(a / "fig9_angle.json");
  EXPECT_NE(json.find("\"detectors\": [\"tagbench-paper\", \"aruco\"]"), std::string::npos) << json;
  EXPECT_NE(json.find("\"steps\": [0, 40]"), std::string::npos) << json;

  // The same settings again (into another folder): nothing rendered, the same rows.
  const Result second = run(args + common(b));
  ASSERT_EQ(second.code, 0) << second.err;
  EXPECT_NE(second.err.find("0 rendered, 4 from the cache, 0 failed"), std::string::npos) << second.err;
  EXPECT_EQ(without_ms(slurp(b / "fig9_angle.csv")), without_ms(slurp(a / "fig9_angle.csv")));
  // Another seed: other frames.
  const Result third = run(args + "--seed 7 " + common(b));
  ASSERT_EQ(third.code, 0) << third.err;
  EXPECT_NE(without_ms(slurp(b / "fig9_angle.csv")), without_ms(slurp(a / "fig9_angle.csv")));
  for (const auto& d : {a, b}) {
    for (const auto& e : fs::directory_iterator(d)) EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos);
  }
}

// Another family's sweep goes to files named with the family, beside (never over) the 36h11 run's.
TEST(CliRaytrace, AnotherFamilysRunWritesFilesNamedWithTheFamily) {
  if (!tagbench::bench::test::have_povray()) GTEST_SKIP() << "povray is not installed";
  const fs::path out = scratch() / "run-16h5";
  fs::remove_all(out);
  fs::create_directories(out);
  { std::ofstream(out / "fig10_distance.csv") << "the 36h11 run\n"; }
  const Result r = run("distance --family 16h5 --trials 1 --distances 4 --detectors tagbench " + common(out));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("wrote fig10_distance_16h5.csv, fig10_distance_16h5_summary.csv, fig10_distance_16h5.json"),
            std::string::npos) << r.err;
  EXPECT_EQ(slurp(out / "fig10_distance.csv"), "the 36h11 run\n");
  const auto rows = lines(slurp(out / "fig10_distance_16h5.csv"));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_NE(rows[1].find(",16h5,"), std::string::npos) << rows[1];
  EXPECT_NE(rows[1].find(",tagbench,1,0,"), std::string::npos) << "a 100 px tag is found: " << rows[1];
  EXPECT_EQ(lines(slurp(out / "fig10_distance_16h5_summary.csv")).size(), 2u);
  EXPECT_NE(slurp(out / "fig10_distance_16h5.json").find("\"rows\": \"fig10_distance_16h5.csv\""), std::string::npos);
}

TEST(CliRaytrace, SixdofRunIsReproducibleAndRecordsEveryVariableAndCameraEffect) {
  if (!tagbench::bench::test::have_povray()) GTEST_SKIP() << "povray is not installed";
  const fs::path a = scratch() / "sixdof-a", b = scratch() / "sixdof-b";
  fs::remove_all(a);
  fs::remove_all(b);
  const std::string args = "sixdof --frames 4 --detectors tagbench,aruco ";
  const Result first = run(args + common(a));
  ASSERT_EQ(first.code, 0) << first.err;
  const auto rows = lines(slurp(a / "sixdof.csv"));
  ASSERT_EQ(rows.size(), 1u + 4 * 2);
  for (const char* c : {"distance_m,phi_deg,tilt_axis_deg,roll_deg,image_x,image_y,black_square_px,halton_index,k1,k2,p1,"
                        "p2,k3,defocus_sigma_px,noise_sigma,quantization_bits,detector,detected_right_id,wrong_id,",
                        "corner_rms_px", "orientation_error_deg", "distance_error_m", ",ms,loss_stage,loss_bits"})
    EXPECT_NE(rows[0].find(c), std::string::npos) << c;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].rfind("sixdof,none,0,none,", 0), 0u) << rows[i];
    EXPECT_NE(rows[i].find(",-0.2,0.05,0.001,-0.0005,0,"), std::string::npos) << rows[i];
  }
  const auto summary = lines(slurp(a / "sixdof_summary.csv"));
  EXPECT_EQ(summary[0].rfind("experiment,variable,bin_lo,bin_hi,detector,frames,detected,detection_rate,rate_lo95,", 0), 0u);
  const std::string json = slurp(a / "sixdof.json");
  for (const char* k : {"\"experiment\": \"sixdof\"", "\"lens\": [-0.2, 0.05, 0.001, -5e-04, 0]", "Halton",
                        "\"distortion\": [-0.2, 0.05, 0.001, -5e-04, 0]", "\"distance_range_m\": [0.5, 6]"})
    EXPECT_NE(json.find(k), std::string::npos) << k;
  // The same command again: the same rows and summary, timing aside.
  const Result second = run(args + common(b));
  ASSERT_EQ(second.code, 0) << second.err;
  EXPECT_NE(second.err.find("0 rendered, 4 from the cache"), std::string::npos) << second.err;
  EXPECT_EQ(without_ms(slurp(b / "sixdof.csv")), without_ms(slurp(a / "sixdof.csv")));
  EXPECT_EQ(without_ms(slurp(b / "sixdof_summary.csv")), without_ms(slurp(a / "sixdof_summary.csv")));
}

// A POV-Ray that loses the first frame of its first run (and says so with exit status 1): the frame is
// reported on stderr and in the sidecar, the other frame's rows are written, and a rerun with the real
// POV-Ray renders only the lost frame.
TEST(CliRaytrace, AFrameThatFailsToRenderIsReportedAndTheRunGoesOn) {
  const auto povray = tagbench::bench::find_povray();
  if (!povray) GTEST_SKIP() << "povray is not installed";
  const fs::path dir = scratch() / "failing", cache = dir / "cache", out = dir / "out", fake = dir / "povray-once";
  fs::remove_all(dir);
  fs::create_directories(cache);
  std::ofstream(fake) << "#!/bin/sh\n"
                         "# runs in the cache directory; the first run loses its first frame\n"
                      << povray->string() << " \"$@\"\n"
                         "[ -e lost-once ] && exit 0\n"
                         ": > lost-once\n"
                         "for a in \"$@\"; do case $a in +SF*) first=${a#+SF};; esac; done\n"
                         "for f in tmp-*.png; do n=${f##*-}; n=${n%.png}; n=$(expr $n + 0);"
                         " [ \"$n\" = \"$first\" ] && rm -f \"$f\"; done\n"
                         "exit 1\n";
  fs::permissions(fake, fs::perms::owner_all);
  const std::string args = "angle --trials 1 --angles 5,35 --detectors tagbench-paper --processes 1 --cache " +
                           cache.string() + " --out " + out.string();
  const Result r = run(args + " --povray " + fake.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("tagbench raytrace: frame not rendered (phi 5 deg, trial 0): povray exited with status 1"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("1 rendered, 0 from the cache, 1 failed"), std::string::npos) << r.err;
  const auto rows = lines(slurp(out / "fig9_angle.csv"));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1].rfind("angle,none,35,deg,0,", 0), 0u) << rows[1];
  const std::string json = slurp(out / "fig9_angle.json");
  EXPECT_NE(json.find("\"step\": 5, \"trial\": 0, \"error\": \"povray exited with status 1\""), std::string::npos)
      << json;
  const Result again = run(args);
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.err.find("1 rendered, 1 from the cache, 0 failed"), std::string::npos) << again.err;
  EXPECT_EQ(lines(slurp(out / "fig9_angle.csv")).size(), 3u);
  fs::remove_all(dir);
}

}  // namespace test_cli_raytrace
