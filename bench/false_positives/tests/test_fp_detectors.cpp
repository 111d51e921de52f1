// Whole detectors on a small corpus made here: two scenes with known tags (a stand-in for false
// detections: every detection in a corpus counts as false), blank and noise images, an unreadable
// file. The counts, rates and intervals must follow from the known tags; the run must not depend on
// the number of threads.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "fp_detectors.hpp"
#include "scenes.hpp"
#include "scratch_dir.hpp"

namespace test_fp_detectors {

namespace fs = std::filesystem;
using namespace tagbench;
using namespace tagbench::bench;

namespace {

corpus::CandidateImage image(const std::string& file, const std::string& group, const std::string& kind) {
  corpus::CandidateImage i;
  i.file = file;
  i.group = group;
  i.kind = kind;
  return i;
}

// Images: scene with 3 tags (still, group "s"), blank (still, "s"), noise (video, "v"), scene with
// 2 tags (video, "v"), and a corrupt file (still, "s").
std::vector<corpus::CandidateImage> make_corpus(const fs::path& dir) {
  cv::imwrite((dir / "three.png").string(), make_scene(640, 480, "36h11", 3, 11).image);
  cv::imwrite((dir / "blank.png").string(), cv::Mat(300, 400, CV_8UC1, cv::Scalar(128)));
  cv::Mat noise(240, 320, CV_8UC1);
  cv::randu(noise, 0, 256);
  cv::imwrite((dir / "noise.png").string(), noise);
  cv::imwrite((dir / "two.png").string(), make_scene(640, 480, "36h11", 2, 12).image);
  std::ofstream(dir / "bad.png") << "\x89PNG\r\n\x1a\nnot really";
  return {image("three.png", "s", "still"), image("blank.png", "s", "still"), image("noise.png", "v", "video-frame"),
          image("two.png", "v", "video-frame"), image("bad.png", "s", "still")};
}

}  // namespace

TEST(FpDetectors, CountsEveryDetectionPerImageMegapixelAndGroup) {
  tagbench::testing::ScratchDir tmp("tagbench_fpdet");
  const auto images = make_corpus(tmp.path());
  FpDetectorsOptions o;
  o.families = {"36h11", "16h5"};
  o.jobs = 2;
  const FpDetectorsRun run = run_fp_detectors(tmp.path(), images, o);
  ASSERT_EQ(run.images.size(), 5u);
  EXPECT_EQ(run.images[4].status, "unreadable");
  EXPECT_EQ(run.images[0].width, 640);
  EXPECT_EQ(run.images[1].height, 300);
  // Every detector finds the five 36h11 tags (a scene is made for them) and none of 16h5 is
  // expected there; noise and blank give nothing.
  for (const auto& det : o.detectors) {
    int n36 = 0;
    for (const auto& d : run.detections)
      if (d.detector == det && d.family == "36h11") {
        ++n36;
        EXPECT_TRUE(d.image == 0 || d.image == 3) << det;
        // Clean synthetic tags: ours reads them with a clear margin; aruco reports none.
        if (det == "tagbench-paper") {
          EXPECT_GT(d.decision_margin, 0.5);
        }
        if (det == "aruco-default") {
          EXPECT_TRUE(std::isnan(d.decision_margin));
        }
        if (det == "libapriltag-d2") {
          EXPECT_GT(d.decision_margin, 0);
        }
      }
    EXPECT_EQ(n36, 5) << det;
  }
  const auto rows = fp_detector_rows(run);
  auto row = [&](const std::string& det, const std::string& fam, const std::string& subset) {
    for (const auto& r : rows)
      if (r.detector == det && r.family == fam && r.subset == subset) return r;
    ADD_FAILURE() << det << " " << fam << " " << subset;
    return FpDetectorRow{};
  };
  for (const auto& det : o.detectors) {
    const auto all = row(det, "36h11", "all");
    EXPECT_EQ(all.images, 4u);  // the unreadable one counts nowhere
    EXPECT_NEAR(all.megapixels, (2 * 640 * 480 + 400 * 300 + 320 * 240) / 1e6, 1e-9);
    EXPECT_EQ(all.detections, 5u);
    EXPECT_EQ(all.images_with_detections, 2u);
    EXPECT_DOUBLE_EQ(all.per_image, 5.0 / 4);
    EXPECT_DOUBLE_EQ(all.per_megapixel, 5 / all.megapixels);
    EXPECT_DOUBLE_EQ(all.image_share, 0.5);
    EXPECT_LT(all.per_image_ci.lo, all.per_image);
    EXPECT_GT(all.per_image_ci.hi, all.per_image);
    EXPECT_GT(all.ms_per_image, 0);
    const auto still = row(det, "36h11", "still");
    EXPECT_EQ(still.images, 2u);
    EXPECT_EQ(still.detections, 3u);
    const auto video = row(det, "36h11", "video-frame");
    EXPECT_EQ(video.images, 2u);
    EXPECT_EQ(video.detections, 2u);
    EXPECT_EQ(row(det, "36h11", "group:s").detections, 3u);
    EXPECT_EQ(row(det, "36h11", "group:v").detections, 2u);
    EXPECT_EQ(video.ms_per_image, 0);  // timings on the "all" rows only
  }
  const std::string csv = fp_detections_csv(run);
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "file,group,kind,detector,family,id,hamming,x0,y0,x1,y1,x2,y2,x3,y3,decision_margin");
  EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')), run.detections.size() + 1);
}

TEST(FpDetectors, TheNumberOfThreadsChangesNothing) {
  tagbench::testing::ScratchDir tmp("tagbench_fpdet");
  const auto images = make_corpus(tmp.path());
  FpDetectorsOptions o;
  o.detectors = {"tagbench-paper", "libapriltag-d2"};
  o.families = {"36h11"};
  o.jobs = 1;
  const auto one = run_fp_detectors(tmp.path(), images, o);
  o.jobs = 3;
  const auto three = run_fp_detectors(tmp.path(), images, o);
  EXPECT_EQ(fp_detections_csv(one), fp_detections_csv(three));
  EXPECT_EQ(one.images, three.images);
}

TEST(FpDetectors, RefusesUnknownDetectorsAndFamilies) {
  tagbench::testing::ScratchDir tmp("tagbench_fpdet");
  const auto images = make_corpus(tmp.path());
  FpDetectorsOptions o;
  o.detectors = {"nonesuch"};
  EXPECT_THROW(run_fp_detectors(tmp.path(), images, o), std::invalid_argument);
  o.detectors = {"aruco-default"};
  o.families = {"36h15"};  // aruco has no 36h15
  EXPECT_THROW(run_fp_detectors(tmp.path(), images, o), std::invalid_argument);
}

}  // namespace test_fp_detectors
