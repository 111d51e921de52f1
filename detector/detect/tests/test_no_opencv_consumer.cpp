// A program that uses the detector through its public header and the library alone: this target
// links tagbench_core and nothing of OpenCV, and its include path must not hold OpenCV's headers.
// It fails to build if tagbench_core passes OpenCV on to its users again (linked PUBLIC: its
// include directory would appear below) or if detector.hpp, or any header it includes, includes
// an OpenCV header (not found without that directory).
#if __has_include(<opencv2/core.hpp>) || __has_include(<opencv2/core/mat.hpp>)
#error "OpenCV's headers are on this target's include path: tagbench_core must link OpenCV PRIVATE"
#endif

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "detect/detector.hpp"
#include "synthetic_tag.hpp"

using namespace tagbench;

#if defined(CV_VERSION) || defined(OPENCV_CORE_HPP)
#error "detector.hpp brought in OpenCV"
#endif

TEST(NoOpenCvConsumer, DetectsATagInAnEightBitBufferWithPadding) {
  const TagCells cells = tag_cells(builtin_family("36h11"), 7);
  Eigen::Matrix3d H;
  H << 60, 8, 160, -6, 58, 120, 0.0004, -0.0003, 1;
  const ImageF f = synth::render_tag(320, 240, cells, H);
  const int stride = 336;  // rows padded past the width: the view must honour the stride
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(stride) * 240, 0xAB);
  for (int y = 0; y < 240; ++y)
    for (int x = 0; x < 320; ++x)
      buf[static_cast<std::size_t>(y) * stride + x] = static_cast<std::uint8_t>(std::lround(f.at(x, y) * 255));

  Detector det(DetectorOptions{});
  DetectorWorkspace ws;
  const auto found = det.detect(ImageU8View{320, 240, stride, buf.data()}, ws);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].id, 7);
  EXPECT_NEAR(found[0].center.x(), 160, 1.0);
  EXPECT_NEAR(found[0].center.y(), 120, 1.0);
}

TEST(NoOpenCvConsumer, RefusesABadView) {
  Detector det(DetectorOptions{});
  const std::uint8_t px[4] = {0, 0, 0, 0};
  EXPECT_THROW(det.detect(ImageU8View{0, 2, 2, px}), std::invalid_argument);
  EXPECT_THROW(det.detect(ImageU8View{2, 2, 2, nullptr}), std::invalid_argument);
  EXPECT_THROW(det.detect(ImageU8View{2, 2, 1, px}), std::invalid_argument);
}
