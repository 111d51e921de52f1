// The whole detector's reusable workspace (DetectorWorkspace) and its entry points: a second frame of
// one size allocates nothing per pixel, a workspace reused across sizes and inputs (or moved) gives
// the same detections, one detector serves threads with a workspace each, and the 8-bit buffer view
// gives the cv::Mat path's detections. This file replaces the program's global operator new/delete.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <new>
#include <random>
#include <thread>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/detector.hpp"
#include "detect/detector_opencv.hpp"
#include "synthetic_tag.hpp"
#include "whole_detector.hpp"

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

namespace test_detector_workspace {

using namespace tagbench;
using tagbench::test_detector::expect_same;
using tagbench::test_detector::opts;

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

}  // namespace test_detector_workspace
