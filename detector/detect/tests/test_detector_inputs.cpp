// The whole detector's input checks and final filter: bad options and inputs are refused, the image
// size limit is enforced with a clear error, and min_decision_margin drops exactly the detections
// read below it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include <opencv2/core.hpp>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/detector.hpp"
#include "detect/detector_opencv.hpp"
#include "synthetic_tag.hpp"
#include "whole_detector.hpp"

namespace test_detector_inputs {

using namespace tagbench;
using tagbench::test_detector::expect_same;
using tagbench::test_detector::opts;

TEST(Detector, BadInputAndOptions) {
  EXPECT_THROW(Detector(opts({"36h99"})), std::invalid_argument);
  EXPECT_THROW(Detector(opts({})), std::invalid_argument);
  DetectorOptions o = opts({"16h5"});
  o.camera = CameraIntrinsics{std::nan(""), 400, 0, 0};
  o.tag_size = 0.1;
  EXPECT_THROW(Detector{o}, std::invalid_argument);
  o.camera = CameraIntrinsics{400, 400, 0, 0};
  o.tag_size = -1;
  EXPECT_THROW(Detector{o}, std::invalid_argument);
  for (const double m : {-0.01, 1.01, std::nan("")}) {
    DetectorOptions bad = opts({"16h5"});
    bad.min_decision_margin = m;
    EXPECT_THROW(Detector{bad}, std::invalid_argument) << m;
  }
  const Detector det(opts({"16h5"}));
  EXPECT_THROW(detect(det, cv::Mat()), std::invalid_argument);
  EXPECT_TRUE(detect(det, cv::Mat(1, 1, CV_8UC1, cv::Scalar(0))).empty());
  DetectorOptions small = opts({"16h5"});
  small.max_pixels = 1000;
  EXPECT_THROW(detect(Detector(small), cv::Mat(100, 100, CV_8UC1, cv::Scalar(0))), std::invalid_argument);
  EXPECT_TRUE(detect(det, cv::Mat(40, 30, CV_16UC3, cv::Scalar(1000, 2000, 3000))).empty());
}

TEST(Detector, ImageSizeLimitIsEnforcedWithAClearError) {
  DetectorOptions o = opts({"16h5"});
  o.max_pixels = 10'000;
  const Detector det(o);
  EXPECT_NO_THROW(detect(det, cv::Mat(100, 100, CV_8UC1, cv::Scalar(128))));  // exactly at the limit
  EXPECT_NO_THROW(det.detect(ImageF(10'000, 1, 0.5f)));
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{101, 100}, {10'001, 1}, {1, 10'001}}) {
    try {
      detect(det, cv::Mat(h, w, CV_8UC1, cv::Scalar(0)));
      ADD_FAILURE() << w << "x" << h << " was accepted";
    } catch (const std::invalid_argument& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(std::to_string(w) + "x" + std::to_string(h)), std::string::npos) << msg;
      EXPECT_NE(msg.find("limit of 10000 pixels"), std::string::npos) << msg;
    }
    DetectorWorkspace ws;
    EXPECT_THROW(det.detect(ImageF(w, h), ws), std::invalid_argument) << w << "x" << h;
    EXPECT_LT(ws.capacity_bytes(), 64u) << "refused before anything is allocated";
  }
  // The default limit, 100 M pixels: 10001 x 10000 is refused (the Mat is never written, so cheap).
  EXPECT_EQ(DetectorOptions().max_pixels, 100'000'000);
  EXPECT_THROW(detect(Detector(opts({"16h5"})), cv::Mat(10'000, 10'001, CV_8UC1)), std::invalid_argument);
  // Limits no option may set: none at all, and past the 32-bit pixel indices.
  for (const long long bad : {0LL, -5LL, kMaxPixelsCeiling + 1}) {
    o.max_pixels = bad;
    EXPECT_THROW(Detector{o}, std::invalid_argument) << bad;
  }
  o.max_pixels = kMaxPixelsCeiling;
  EXPECT_NO_THROW(Detector{o});
  // An ImageF whose data does not match its size is refused instead of read out of bounds.
  ImageF bad(50, 40);
  bad.data.resize(50 * 39);
  EXPECT_THROW(Detector(opts({"16h5"})).detect(bad), std::invalid_argument);
}

// min_decision_margin drops exactly the detections a run at 0 reads below it: the real tag (a clear
// read) stays, the texture's false 16h5 quads (reads near their thresholds) go.
TEST(Detector, MinDecisionMarginFiltersTheFinalDetections) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0, 1);
  std::uniform_int_distribution<int> px(0, 380), sz(4, 40);
  ImageF img(400, 300, 0.5f);
  for (int r = 0; r < 600; ++r) {
    const int x0 = px(rng), y0 = px(rng) % 280, w = sz(rng), h = sz(rng);
    const float v = u(rng);
    for (int y = y0; y < std::min(300, y0 + h); ++y)
      for (int x = x0; x < std::min(400, x0 + w); ++x) img.at(x, y) = v;
  }
  const Corners truth = synth::square_tag_corners(200, 150, 90, 0.2);
  const ImageF tag = synth::render_tag(400, 300, tag_cells(builtin_family("16h5"), 7), synth::homography_for(truth),
                                       -1.0f, 2);
  for (std::size_t i = 0; i < img.data.size(); ++i)
    if (tag.data[i] >= 0) img.data[i] = tag.data[i];
  DetectorOptions o = opts({"16h5"}, 2);
  const auto all = Detector(o).detect(img);
  ASSERT_GE(all.size(), 3u) << "the texture should give false 16h5 detections";
  const auto real = std::find_if(all.begin(), all.end(), [&](const Detection& d) {
    return d.id == 7 && (d.center - Eigen::Vector2d(200, 150)).norm() < 2;
  });
  ASSERT_NE(real, all.end());
  EXPECT_GT(real->decision_margin, 0.5);
  std::set<double> margins;
  for (const auto& d : all) margins.insert(d.decision_margin);
  ASSERT_GE(margins.size(), 3u);
  std::vector<double> thresholds{0, 1};
  for (const double m : margins) {
    thresholds.push_back(m);
    if (m < 1) thresholds.push_back(std::nextafter(m, 1.0));  // just above it: that detection goes
  }
  for (const double m : thresholds) {
    o.min_decision_margin = m;
    std::vector<Detection> want;
    for (const auto& d : all)
      if (d.decision_margin >= m) want.push_back(d);
    expect_same(Detector(o).detect(img), want, "threshold " + std::to_string(m));
  }
  o.min_decision_margin = 0.5;
  const auto kept = Detector(o).detect(img);
  EXPECT_LT(kept.size(), all.size());
  EXPECT_TRUE(std::any_of(kept.begin(), kept.end(), [](const Detection& d) { return d.id == 7; }));
}

}  // namespace test_detector_inputs
