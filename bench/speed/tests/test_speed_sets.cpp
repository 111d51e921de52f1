#include <cmath>
#include <fstream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "scratch_dir.hpp"
#include "speed/speed_sets.hpp"

namespace tagbench::bench {
namespace test_speed_sets {
namespace {

SpeedRow row(const std::string& set, std::size_t index, const std::string& det, double ms, bool readable = true) {
  SpeedRow r;
  r.set = set;
  r.index = index;
  r.image = "img" + std::to_string(index);
  r.detector = det;
  r.width = 1000;
  r.height = 500;
  r.readable = readable;
  r.ms = ms;
  return r;
}

TEST(SpeedSets, RatiosArePerImageGeometricMeans) {
  // a/b per image: 2, 0.5, 1 -> geometric mean 1; one image a is faster (0.5).
  const std::vector<SpeedRow> rows = {row("s", 0, "a", 20), row("s", 0, "b", 10), row("s", 1, "a", 5),
                                      row("s", 1, "b", 10), row("s", 2, "a", 7),  row("s", 2, "b", 7)};
  const auto q = speed_ratios(rows, {{"a", "b"}});
  ASSERT_EQ(q.size(), 1u);
  EXPECT_EQ(q[0].images, 3u);
  EXPECT_NEAR(q[0].geometric_mean, 1.0, 1e-12);
  EXPECT_NEAR(q[0].median, 1.0, 1e-12);
  EXPECT_NEAR(q[0].share_faster, 1.0 / 3, 1e-12);
  EXPECT_LT(q[0].ci_lo, 1.0);
  EXPECT_GT(q[0].ci_hi, 1.0);
  // A total-time ratio would say 32/27: the per-image mean is not swayed by one slow image.
  const auto s = summarise_speed(rows);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].detector, "a");
  EXPECT_NEAR(s[0].total_ms, 32, 1e-12);
  EXPECT_NEAR(s[0].median_ms, 7, 1e-12);
  EXPECT_NEAR(s[0].megapixels, 1.5, 1e-12);
  EXPECT_NEAR(s[0].mpx_per_s, 1.5 / 0.032, 1e-9);
}

TEST(SpeedSets, UnreadableImagesAndOtherSetsStayOut) {
  const std::vector<SpeedRow> rows = {row("s", 0, "a", 10), row("s", 0, "b", 10), row("s", 1, "a", 0, false),
                                      row("s", 1, "b", 0, false), row("t", 0, "a", 30), row("t", 0, "b", 10)};
  const auto q = speed_ratios(rows, {{"a", "b"}, {"a", "missing"}});
  ASSERT_EQ(q.size(), 2u);  // the pair with a detector never timed gives nothing
  EXPECT_EQ(q[0].set, "s");
  EXPECT_EQ(q[0].images, 1u);
  EXPECT_NEAR(q[0].geometric_mean, 1, 1e-12);
  EXPECT_EQ(q[1].set, "t");
  EXPECT_NEAR(q[1].geometric_mean, 3, 1e-12);
  const auto s = summarise_speed(rows);
  EXPECT_EQ(s[0].images, 1u);
}

TEST(SpeedSets, EveryDetectorTimedOnEveryImage) {
  const ImageSet set = scene_set({{320, 240}}, 2, "36h11");
  ASSERT_EQ(set.size, 2u);
  SpeedOptions o;
  o.detectors = {"tagbench-paper", "libapriltag-d1"};
  std::size_t calls = 0;
  const auto rows = time_image_set(set, o, [&](const SpeedProgress& p) {
    ++calls;
    EXPECT_EQ(p.total, 2u);
  });
  EXPECT_EQ(calls, 2u);
  ASSERT_EQ(rows.size(), 4u);
  for (const auto& r : rows) {
    EXPECT_TRUE(r.readable);
    EXPECT_GT(r.ms, 0);
    EXPECT_EQ(r.width, 320);
    EXPECT_GT(r.found, 0u) << r.detector << " on " << r.image;
  }
  EXPECT_EQ(rows[0].index, 0u);
  EXPECT_EQ(rows[3].index, 1u);
  o.detectors = {"no-such-detector"};
  EXPECT_THROW(time_image_set(set, o), std::invalid_argument);
}

TEST(SpeedSets, CacheFramesAreSpreadEvenly) {
  tagbench::testing::ScratchDir dir("speed_cache");
  const cv::Mat img(8, 8, CV_8UC1, cv::Scalar(128));
  for (int i = 0; i < 10; ++i) cv::imwrite((dir / ("frame-" + std::to_string(i) + ".png")).string(), img);
  std::ofstream(dir / "tag-x.png") << "not a frame";
  std::ofstream(dir / "frame-x.pov") << "not a frame";
  const ImageSet all = raytrace_cache_set(dir.path());
  EXPECT_EQ(all.size, 10u);
  EXPECT_EQ(spread_subset(all, 0).size, 10u);
  EXPECT_EQ(spread_subset(all, 20).size, 10u);
  const ImageSet some = spread_subset(all, 3);
  ASSERT_EQ(some.size, 3u);
  EXPECT_EQ(some.image(0).name, "frame-0.png");
  EXPECT_EQ(some.image(1).name, "frame-3.png");
  EXPECT_EQ(some.image(2).name, "frame-6.png");
  EXPECT_EQ(some.image(2).gray8.cols, 8);
  EXPECT_THROW(raytrace_cache_set(dir / "missing"), std::invalid_argument);
}

TEST(SpeedSets, CsvHasHeaderAndQuotes) {
  std::vector<SpeedRow> rows = {row("s", 0, "a", 1.5)};
  rows[0].image = "a, b.png";
  const std::string csv = speed_rows_csv(rows, "threads=1");
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "set,index,image,width,height,detector,readable,ms,found,settings");
  EXPECT_NE(csv.find("\"a, b.png\""), std::string::npos);
  const std::string sum = speed_summary_csv(summarise_speed(rows), {}, "x");
  EXPECT_EQ(std::count(sum.begin(), sum.end(), '\n'), 2);
  const auto header = sum.substr(0, sum.find('\n'));
  const auto line = sum.substr(sum.find('\n') + 1);
  EXPECT_EQ(std::count(header.begin(), header.end(), ','), std::count(line.begin(), line.end(), ','));
}

}  // namespace
}  // namespace test_speed_sets
}  // namespace tagbench::bench
