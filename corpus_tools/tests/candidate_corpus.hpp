#pragma once
// The tiny corpus the candidate tests share (the library's in corpus_tools/tests, the program's in
// cli/tests): a blank image, noise, random rectangles, a rendered 36h11 tag and a file that is not an
// image, made once per test program in its scratch folder.
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "candidates.hpp"
#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/detector_opencv.hpp"
#include "detect/tests/synthetic_tag.hpp"
#include "scratch_dir.hpp"

namespace tagbench::corpus::testing {

namespace fs = std::filesystem;

inline constexpr int kTagId = 42;
inline const Corners kTagCorners = synth::square_tag_corners(150.5, 110.25, 96.0, 0.3);

inline cv::Mat to_mat8(const ImageF& img) {
  cv::Mat m(img.height, img.width, CV_8UC1);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      m.at<uchar>(y, x) = cv::saturate_cast<uchar>(img.at(x, y) * 255.0f + 0.5f);
  return m;
}

inline const fs::path& corpus_dir() {
  static const fs::path d = [] {
    const fs::path p = tagbench::testing::program_scratch("tagbench_candidates") / "corpus";
    fs::remove_all(p);
    fs::create_directories(p / "sub");
    std::mt19937 rng(7);
    cv::imwrite((p / "blank.png").string(), cv::Mat(120, 160, CV_8UC1, cv::Scalar(128)));
    cv::Mat noise(150, 200, CV_8UC1);
    cv::randu(noise, 0, 256);
    cv::imwrite((p / "noise.png").string(), noise);
    for (int n = 0; n < 2; ++n) {  // random filled rectangles, some rotated, on a mid-grey background
      cv::Mat r(240, 320, CV_8UC3, cv::Scalar(120, 130, 125));
      for (int i = 0; i < 25; ++i) {
        const cv::RotatedRect rr(cv::Point2f(static_cast<float>(rng() % 320), static_cast<float>(rng() % 240)),
                                 cv::Size2f(static_cast<float>(15 + rng() % 80), static_cast<float>(15 + rng() % 80)),
                                 static_cast<float>(rng() % 90));
        cv::Point2f pts[4];
        rr.points(pts);
        std::vector<cv::Point> poly(pts, pts + 4);
        const int v = static_cast<int>(rng() % 256);
        cv::fillConvexPoly(r, poly, cv::Scalar(v, (v * 3) % 256, 255 - v), cv::LINE_AA);
      }
      cv::imwrite((p / "sub" / ("rects" + std::to_string(n) + ".png")).string(), r);
    }
    const TagCells cells = tag_cells(builtin_family("36h11"), kTagId);
    const ImageF tag = synth::render_tag(300, 220, cells, synth::homography_for(kTagCorners), 0.6f, 4);
    cv::imwrite((p / "tag.png").string(), to_mat8(tag));
    std::ofstream(p / "broken.jpg") << "not a jpeg";
    return p;
  }();
  return d;
}

inline ImageF load(const std::string& name) {
  return to_float_image(cv::imread((corpus_dir() / name).string(), cv::IMREAD_UNCHANGED));
}

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline const CandidateStore& store1() {
  static const CandidateStore s = extract_candidates(corpus_dir(), corpus_images(corpus_dir()), DetectorOptions::paper(), 1);
  return s;
}

// A folder beside the corpus (not in it: the corpus' listing must not change) for one test.
inline fs::path side_dir(const std::string& name) {
  const fs::path d = tagbench::testing::program_scratch("tagbench_candidates") / "side" / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

}  // namespace tagbench::corpus::testing
