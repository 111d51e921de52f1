// The whole detector on tags warped into images by known homographies (supersampled).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <new>
#include <random>
#include <set>
#include <thread>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/detector.hpp"
#include "detect/detector_opencv.hpp"
#include "synthetic_tag.hpp"

using namespace tagbench;

// This test binary replaces the global operator new/delete to record what is allocated while
// g_count_allocations is set (the total and the largest block): the workspace test proves with it
// that a second frame of one size allocates nothing per pixel. Otherwise plain malloc/free.
namespace {
std::atomic<bool> g_count_allocations{false};
std::atomic<std::size_t> g_allocated_bytes{0}, g_largest_allocation{0};

// Out of line so GCC does not pair the inlined free() with operator new (-Wmismatched-new-delete).
[[gnu::noinline]] void release_memory(void* p) noexcept { std::free(p); }

void* counted_malloc(std::size_t n) noexcept {
  if (g_count_allocations.load(std::memory_order_relaxed)) {
    g_allocated_bytes += n;
    std::size_t largest = g_largest_allocation.load();
    while (n > largest && !g_largest_allocation.compare_exchange_weak(largest, n)) {
    }
  }
  return std::malloc(n == 0 ? 1 : n);
}
}  // namespace

// Every non-aligned form, so no block is made by one allocator and freed by another (the aligned
// forms stay the library's, new and delete alike).
void* operator new(std::size_t n) {
  if (void* p = counted_malloc(n)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return ::operator new(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return counted_malloc(n); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return counted_malloc(n); }
void operator delete(void* p) noexcept { release_memory(p); }
void operator delete[](void* p) noexcept { release_memory(p); }
void operator delete(void* p, std::size_t) noexcept { release_memory(p); }
void operator delete[](void* p, std::size_t) noexcept { release_memory(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { release_memory(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { release_memory(p); }

namespace {

DetectorOptions opts(std::vector<std::string> fams, int max_hamming = 1) {
  DetectorOptions o = DetectorOptions::paper();
  o.families = std::move(fams);
  o.max_hamming = max_hamming;
  return o;
}

// A random perspective view of a tag: centre, size, in-plane angle, and a tilt (corner jitter).
Corners random_view(std::mt19937& rng, int w, int h, double side) {
  std::uniform_real_distribution<double> cx(side, w - side), cy(side, h - side), ang(-M_PI, M_PI), j(-0.12, 0.12);
  Corners c = synth::square_tag_corners(cx(rng), cy(rng), side, ang(rng));
  for (auto& p : c) p += side * Eigen::Vector2d(j(rng), j(rng));
  return c;
}

}  // namespace

TEST(Detector, EveryShippedFamilyRightIdRotationAndCorners) {
  std::mt19937 rng(21);
  const auto pending = pending_family_names();
  for (const auto& name : builtin_family_names()) {
    const TagFamily& f = builtin_family(name);
    if (!f.info().seed) continue;  // AprilTag families (the rival codebooks use other tag layouts)
    const Detector det(opts({name}, 0));
    for (const double side : {40.0, 70.0}) {
      const int id = static_cast<int>(rng() % f.size());
      const Corners truth = random_view(rng, 160, 150, side);
      const ImageF img = synth::render_tag(160, 150, tag_cells(f, id), synth::homography_for(truth), 0.5f, 6);
      const auto dets = det.detect(img);
      ASSERT_EQ(dets.size(), 1u) << name << " side " << side;
      EXPECT_EQ(dets[0].family, f.name());
      EXPECT_EQ(dets[0].id, id) << name;
      EXPECT_EQ(dets[0].hamming, 0);
      for (std::size_t i = 0; i < 4; ++i)
        EXPECT_LT((dets[0].corners[i] - truth[i]).norm(), 0.2) << name << " corner " << i << " side " << side;
      EXPECT_LT((dets[0].center - synth::homography_for(truth).col(2).hnormalized()).norm(), 0.2);
    }
  }
}

TEST(Detector, HalfResolutionFindsLargeTags) {
  const TagFamily& f = builtin_family("25h9");
  DetectorOptions o = opts({"25h9"});
  o.half_resolution = true;
  const Corners truth = synth::square_tag_corners(100, 90, 90, 0.5);
  const ImageF img = synth::render_tag(200, 180, tag_cells(f, 11), synth::homography_for(truth));
  const auto dets = Detector(o).detect(img);
  ASSERT_EQ(dets.size(), 1u);
  EXPECT_EQ(dets[0].id, 11);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_LT((dets[0].corners[i] - truth[i]).norm(), 1.0);
}

TEST(Detector, BitErrorsUpToMaxHammingDecodeBeyondNot) {
  const TagFamily& f = builtin_family("36h15");
  const Corners truth = synth::square_tag_corners(80, 80, 100, 0.3);
  const int id = 4;
  for (int errors = 0; errors <= 4; ++errors) {
    // Flip `errors` payload cells of the printed tag.
    TagCells cells = tag_cells(f, id);
    for (int e = 0; e < errors; ++e) {
      const int y = 2 + (e * 5) % 6, x = 2 + (e * 3 + 1) % 6;
      cells.white[static_cast<std::size_t>(y * cells.n + x)] ^= 1;
    }
    const ImageF img = synth::render_tag(160, 160, cells, synth::homography_for(truth));
    for (int k = 0; k <= 4; ++k) {
      const auto dets = Detector(opts({"36h15"}, k)).detect(img);
      if (errors <= k) {
        ASSERT_EQ(dets.size(), 1u) << errors << " errors, max " << k;
        EXPECT_EQ(dets[0].id, id);
        EXPECT_EQ(dets[0].hamming, errors);
      } else {
        EXPECT_TRUE(dets.empty()) << errors << " errors, max " << k;
      }
    }
  }
}

TEST(Detector, PartlyOccludedBorderEdgeStillDetected) {
  const TagFamily& f = builtin_family("25h9");
  const Corners truth = synth::square_tag_corners(90, 90, 100, 0.15);
  ImageF img = synth::render_tag(180, 180, tag_cells(f, 2), synth::homography_for(truth));
  // A grey blob covers the middle third of the bottom border edge (outside the payload).
  const Eigen::Vector2d a = truth[3], b = truth[2];
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const Eigen::Vector2d p(x, y);
      const Eigen::Vector2d m = 0.5 * (a + b);
      if ((p - m).norm() < 16) img.at(x, y) = 0.5f;
    }
  const auto dets = Detector(opts({"25h9"}, 2)).detect(img);
  ASSERT_EQ(dets.size(), 1u);
  EXPECT_EQ(dets[0].id, 2);
}

TEST(Detector, StrongLightingGradientStillDecoded) {
  const TagFamily& f = builtin_family("16h5");
  const Corners truth = synth::square_tag_corners(90, 80, 90, -0.4);
  ImageF img = synth::render_tag(180, 160, tag_cells(f, 9), synth::homography_for(truth));
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) img.at(x, y) *= static_cast<float>(1.0 - 0.85 * x / img.width);
  const auto dets = Detector(opts({"16h5"}, 0)).detect(img);
  ASSERT_EQ(dets.size(), 1u);
  EXPECT_EQ(dets[0].id, 9);
}

TEST(Detector, NothingInBlankNoiseOrTexture) {
  std::mt19937 rng(5);
  std::vector<ImageF> imgs;
  imgs.emplace_back(320, 240, 0.5f);
  ImageF noise(320, 240);
  std::uniform_real_distribution<float> u(0, 1);
  for (auto& v : noise.data) v = u(rng);
  imgs.push_back(noise);
  // Blocky texture: random rectangles, the kind of structure that makes quads.
  ImageF tex(320, 240, 0.5f);
  std::uniform_int_distribution<int> px(0, 300), sz(5, 60);
  for (int r = 0; r < 200; ++r) {
    const int x0 = px(rng), y0 = px(rng) % 220, w = sz(rng), h = sz(rng);
    const float v = u(rng);
    for (int y = y0; y < std::min(240, y0 + h); ++y)
      for (int x = x0; x < std::min(320, x0 + w); ++x) tex.at(x, y) = v;
  }
  imgs.push_back(tex);
  const Detector det(opts({"36h11"}, 0));
  for (const auto& img : imgs) EXPECT_TRUE(det.detect(img).empty());
}

TEST(Detector, PoseOfASyntheticView) {
  const TagFamily& f = builtin_family("36h15");
  DetectorOptions o = opts({"36h15"});
  o.camera = CameraIntrinsics{400, 400, 199.5, 199.5};
  o.tag_size = 0.2;
  // A tag 1.2 m away, tilted 35 degrees about a diagonal axis.
  Pose truth;
  truth.R = Eigen::AngleAxisd(35 * M_PI / 180, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  truth.t = Eigen::Vector3d(0.05, -0.03, 1.2);
  const Corners c = project_tag_corners(truth, *o.camera, o.tag_size);
  const ImageF img = synth::render_tag(400, 400, tag_cells(f, 1), synth::homography_for(c));
  const auto dets = Detector(o).detect(img);
  ASSERT_EQ(dets.size(), 1u);
  ASSERT_TRUE(dets[0].pose.has_value());
  EXPECT_LT(rotation_angle_deg(dets[0].pose->pose.R, truth.R), 0.5);
  EXPECT_LT(std::abs(dets[0].pose->pose.t.norm() - truth.t.norm()), 0.01 * truth.t.norm());
  ASSERT_TRUE(dets[0].pose_alternative.has_value());
  EXPECT_GT(rotation_angle_deg(dets[0].pose_alternative->pose.R, truth.R), 1.0);
  EXPECT_GE(dets[0].pose_alternative->reprojection_rms_px, dets[0].pose->reprojection_rms_px);
}

TEST(Detector, DetectIsConstAndThreadSafe) {
  const TagFamily& f = builtin_family("25h9");
  const Corners truth = synth::square_tag_corners(100, 100, 80, 0.7);
  const ImageF img = synth::render_tag(200, 200, tag_cells(f, 13), synth::homography_for(truth));
  const Detector det(opts({"25h9", "16h5"}));
  const auto reference = det.detect(img);
  ASSERT_EQ(reference.size(), 1u);
  std::vector<std::thread> pool;
  std::atomic<int> mismatches{0};
  for (int t = 0; t < 4; ++t)
    pool.emplace_back([&] {
      for (int i = 0; i < 5; ++i) {
        const auto d = det.detect(img);
        if (d.size() != 1 || d[0].id != 13 || (d[0].corners[0] - reference[0].corners[0]).norm() > 0) ++mismatches;
      }
    });
  for (auto& th : pool) th.join();
  EXPECT_EQ(mismatches.load(), 0);
}

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

namespace {

// A 8-bit frame: one tag at (cx, cy) over a fixed background of grey rectangles (the same for every
// frame, like a static camera), so frames differ only where the tag is.
cv::Mat tag_frame(int w, int h, int id, double cx, double cy, double phi) {
  const TagFamily& f = builtin_family("36h11");
  const Corners c = synth::square_tag_corners(cx, cy, 0.3 * h, phi);
  const ImageF tag = synth::render_tag(w, h, tag_cells(f, id), synth::homography_for(c), -1.0f, 2);
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> u(0, 1);
  cv::Mat back(h, w, CV_32F, cv::Scalar(0.5));
  for (int r = 0; r < 25; ++r) {
    const int rw = 5 + static_cast<int>(u(rng) * w / 6), rh = 5 + static_cast<int>(u(rng) * h / 6);
    back(cv::Rect(static_cast<int>(u(rng) * (w - rw)), static_cast<int>(u(rng) * (h - rh)), rw, rh))
        .setTo(0.2 + 0.6 * u(rng));
  }
  cv::Mat out(h, w, CV_8U);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      // render_tag gives -1 where no sample hit the tag: the background shows there.
      const float t = tag.at(x, y);
      const float v = t < 0 ? back.at<float>(y, x) : t;
      out.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(std::lround(255 * std::clamp(v, 0.0f, 1.0f)));
    }
  return out;
}

void expect_same(const std::vector<Detection>& a, const std::vector<Detection>& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].id, b[i].id) << what;
    EXPECT_EQ(a[i].decision_margin, b[i].decision_margin) << what;
    for (std::size_t k = 0; k < 4; ++k) EXPECT_EQ(a[i].corners[k], b[i].corners[k]) << what << " corner " << k;
  }
}

}  // namespace

TEST(DetectorWorkspace, SecondFrameOfOneSizeReallocatesNothing) {
  const cv::Mat first = tag_frame(640, 480, 3, 250, 200, 0.3);
  const cv::Mat second = tag_frame(640, 480, 17, 400, 260, -0.5);  // another tag, elsewhere
  const double pixels = 640.0 * 480.0;
  for (const bool half : {false, true}) {
    DetectorOptions o = opts({"36h11"});
    o.half_resolution = half;
    o.decode_sigma = 0.5;  // so the decoding image's buffer is exercised too
    const Detector det(o);
    DetectorWorkspace ws;
    const auto counted = [&](const cv::Mat& frame, std::size_t& total, std::size_t& largest) {
      g_allocated_bytes = 0;
      g_largest_allocation = 0;
      g_count_allocations = true;
      auto d = detect(det, frame, ws);
      g_count_allocations = false;
      total = g_allocated_bytes;
      largest = g_largest_allocation;
      return d;
    };
    std::size_t first_total = 0, first_largest = 0, second_total = 0, second_largest = 0;
    const auto d1 = counted(first, first_total, first_largest);
    const auto before = ws.buffers();
    const auto d2 = counted(second, second_total, second_largest);
    const auto after = ws.buffers();

    ASSERT_EQ(d1.size(), 1u);
    ASSERT_EQ(d2.size(), 1u);
    EXPECT_EQ(d2[0].id, 17);
    // The counter sees the per-pixel buffers when they are made (tens of bytes a pixel; the
    // smallest, a float per half-resolution pixel, is `pixels` bytes)...
    const double scale = half ? 0.25 : 1.0;
    EXPECT_GT(static_cast<double>(first_total), 30 * pixels * scale) << "half " << half;
    EXPECT_GE(static_cast<double>(first_largest), 4 * pixels * scale) << "half " << half;
    // ...and on the second frame only the small vectors that scale with the scene's segments
    // (segments, quad search, results): no block near a per-pixel buffer's size.
    EXPECT_LT(static_cast<double>(second_largest), pixels / 16) << "half " << half;
    EXPECT_LT(second_total * 10, first_total) << "half " << half;
    ASSERT_EQ(before.size(), after.size());
    for (std::size_t i = 0; i < before.size(); ++i) {
      EXPECT_EQ(before[i].data, after[i].data) << before[i].name << " half " << half;
      EXPECT_EQ(before[i].capacity_bytes, after[i].capacity_bytes) << before[i].name << " half " << half;
    }
    EXPECT_GT(ws.capacity_bytes(), static_cast<std::size_t>(30 * pixels * (half ? 0.25 : 1.0)));
    ws.release();
    EXPECT_LT(ws.capacity_bytes(), 64u);  // an empty Clusters keeps its one offset
  }
}

TEST(DetectorWorkspace, ReusedAcrossSizesAndInputsGivesTheSameDetections) {
  // Stale contents of a reused buffer (a previous frame, a larger image) must never leak into a
  // result: every frame through one workspace equals the same frame through a fresh detect().
  std::vector<cv::Mat> frames = {tag_frame(320, 240, 5, 150, 120, 0.2), tag_frame(320, 240, 6, 180, 110, 1.0),
                                 tag_frame(200, 150, 7, 100, 75, -0.4), tag_frame(321, 241, 8, 160, 120, 2.0)};
  frames.push_back(frames[0]);
  cv::Mat colour;
  cv::cvtColor(frames[1], colour, cv::COLOR_GRAY2BGR);
  colour.convertTo(colour, CV_16UC3, 257.0);
  frames.push_back(colour);
  for (const bool half : {false, true}) {
    DetectorOptions o = opts({"36h11"});
    o.half_resolution = half;
    const Detector det(o);
    DetectorWorkspace ws;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      const auto fresh = detect(det, frames[i]);
      EXPECT_EQ(fresh.size(), 1u) << "frame " << i;
      expect_same(detect(det, frames[i], ws), fresh, "frame " + std::to_string(i) + " half " + std::to_string(half));
      // The ImageF entry point shares the workspace with the cv::Mat one.
      expect_same(det.detect(to_float_image(frames[i]), ws), fresh, "ImageF frame " + std::to_string(i));
    }
    DetectorWorkspace moved = std::move(ws);
    expect_same(detect(det, frames[2], moved), detect(det, frames[2]), "moved-to");
    expect_same(detect(det, frames[2], ws), detect(det, frames[2]), "moved-from");  // usable again
  }
}

// The 8-bit buffer entry point (ImageU8View, no OpenCV) gives exactly the cv::Mat path's
// detections, including the homography, pose-free fields and decision margins, through a shared
// workspace or without one, also for rows padded past the width.
TEST(Detector, EightBitViewGivesTheMatPathsDetections) {
  const std::vector<cv::Mat> frames = {tag_frame(320, 240, 5, 150, 120, 0.2), tag_frame(321, 241, 8, 160, 120, 2.0),
                                       tag_frame(640, 480, 3, 250, 200, 0.3)};
  for (const bool half : {false, true}) {
    DetectorOptions o = opts({"36h11"});
    o.half_resolution = half;
    const Detector det(o);
    DetectorWorkspace ws;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      const cv::Mat& m = frames[i];
      const auto want = detect(det, m);
      ASSERT_EQ(want.size(), 1u) << "frame " << i;
      const ImageU8View view{m.cols, m.rows, static_cast<int>(m.step[0]), m.ptr<std::uint8_t>(0)};
      const std::string what = "frame " + std::to_string(i) + " half " + std::to_string(half);
      expect_same(det.detect(view, ws), want, what);
      expect_same(det.detect(view), want, what + " (no workspace)");
      EXPECT_EQ(det.detect(view, ws)[0].homography, want[0].homography) << what;
      cv::Mat padded(m.rows, m.cols + 13, CV_8U, cv::Scalar(255));
      m.copyTo(padded(cv::Rect(0, 0, m.cols, m.rows)));
      expect_same(det.detect(ImageU8View{m.cols, m.rows, padded.cols, padded.ptr<std::uint8_t>(0)}, ws), want,
                  what + " padded");
    }
  }
}

TEST(DetectorWorkspace, OneDetectorManyThreadsEachWithItsOwnWorkspace) {
  const std::vector<cv::Mat> frames = {tag_frame(320, 240, 21, 150, 120, 0.4), tag_frame(320, 240, 22, 170, 110, -1.2),
                                       tag_frame(240, 200, 23, 120, 100, 2.5)};
  const Detector det(opts({"36h11"}));
  std::vector<std::vector<Detection>> reference;
  for (const auto& f : frames) reference.push_back(detect(det, f));
  std::atomic<int> mismatches{0}, runs{0};
  std::vector<std::thread> pool;
  for (int t = 0; t < 4; ++t)
    pool.emplace_back([&, t] {
      DetectorWorkspace ws;
      for (int i = 0; i < 6; ++i) {
        const std::size_t k = static_cast<std::size_t>(t + i) % frames.size();
        const auto d = detect(det, frames[k], ws);
        ++runs;
        if (d.size() != 1 || d[0].id != reference[k][0].id || d[0].corners != reference[k][0].corners) ++mismatches;
      }
    });
  for (auto& th : pool) th.join();
  EXPECT_EQ(runs.load(), 24);
  EXPECT_EQ(mismatches.load(), 0);
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
