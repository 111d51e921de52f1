// One detection per tag: each rule of suppress_duplicates, its single-pass first-match behaviour,
// and the minimum decision margin filter.
#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "detect/detector_options.hpp"
#include "detect/suppress_duplicates.hpp"

namespace test_suppress_duplicates {

using namespace tagbench;

namespace {

// An axis-aligned square detection of side `side` (perimeter 4 side) centred at (x, y).
Detection det(double x, double y, double side = 40, int id = 1, int hamming = 0, double observed = 100,
              const std::string& family = "36h11") {
  Detection d;
  d.family = family;
  d.id = id;
  d.hamming = hamming;
  d.observed_perimeter = observed;
  d.center = Eigen::Vector2d(x, y);
  const double h = side / 2;
  d.corners = {Eigen::Vector2d(x - h, y - h), Eigen::Vector2d(x + h, y - h), Eigen::Vector2d(x + h, y + h),
               Eigen::Vector2d(x - h, y + h)};
  return d;
}

std::vector<double> xs(const std::vector<Detection>& v) {
  std::vector<double> r;
  for (const auto& d : v) r.push_back(d.center.x());
  return r;
}

}  // namespace

TEST(SuppressDuplicates, DifferentFamilyOrIdAreNotDuplicates) {
  EXPECT_EQ(suppress_duplicates({det(0, 0), det(1, 0, 40, 2)}).size(), 2u);
  EXPECT_EQ(suppress_duplicates({det(0, 0), det(1, 0, 40, 1, 0, 100, "16h5")}).size(), 2u);
  EXPECT_EQ(suppress_duplicates({det(0, 0), det(1, 0)}).size(), 1u);
}

TEST(SuppressDuplicates, CloserThanASixteenthOfTheSummedPerimeters) {
  // Two squares of side 40: perimeters 160 + 160, threshold 20 px (strictly closer merges).
  EXPECT_EQ(suppress_duplicates({det(0, 0), det(19.99, 0)}).size(), 1u);
  EXPECT_EQ(suppress_duplicates({det(0, 0), det(20, 0)}).size(), 2u);
  // The corners' perimeters count, not the observed ones: side 80 + side 40 gives 30 px.
  EXPECT_EQ(suppress_duplicates({det(0, 0, 80, 1, 0, 1), det(0, 29.9, 40, 1, 0, 1)}).size(), 1u);
  EXPECT_EQ(suppress_duplicates({det(0, 0, 80, 1, 0, 1), det(0, 30, 40, 1, 0, 1)}).size(), 2u);
}

TEST(SuppressDuplicates, LowerHammingThenLongerObservedPerimeterThenTheFirst) {
  for (const bool swap : {false, true}) {
    std::vector<Detection> v = {det(0, 0, 40, 1, 1, 500), det(5, 0, 40, 1, 0, 10)};
    if (swap) std::swap(v[0], v[1]);
    const auto out = suppress_duplicates(v);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].hamming, 0) << swap;  // lower hamming wins over a longer perimeter
  }
  for (const bool swap : {false, true}) {
    std::vector<Detection> v = {det(0, 0, 40, 1, 1, 100), det(5, 0, 40, 1, 1, 120)};
    if (swap) std::swap(v[0], v[1]);
    const auto out = suppress_duplicates(v);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].observed_perimeter, 120) << swap;
  }
  const auto tie = suppress_duplicates({det(0, 0), det(5, 0)});
  ASSERT_EQ(tie.size(), 1u);
  EXPECT_EQ(tie[0].center.x(), 0);  // a full tie keeps the earlier one
}

TEST(SuppressDuplicates, OnlyTheFirstKeptDuplicateCounts) {
  // Kept: A at 0 (hamming 0) and B at 30 (hamming 2), not duplicates of each other (threshold 20).
  // D at 15 duplicates both; A comes first and is better, so D is dropped though it beats B.
  auto out = suppress_duplicates({det(0, 0, 40, 1, 0), det(30, 0, 40, 1, 2), det(15, 0, 40, 1, 1)});
  EXPECT_EQ(xs(out), (std::vector<double>{0, 30}));
  // D better than A: it replaces A in place; B stays, though D is now within B's reach.
  out = suppress_duplicates({det(0, 0, 40, 1, 1), det(30, 0, 40, 1, 2), det(15, 0, 40, 1, 0)});
  EXPECT_EQ(xs(out), (std::vector<double>{15, 30}));
  EXPECT_EQ(out[0].hamming, 0);
  // A detection that duplicates nothing is appended in order.
  out = suppress_duplicates({det(100, 0), det(0, 0), det(50, 0)});
  EXPECT_EQ(xs(out), (std::vector<double>{100, 0, 50}));
}

TEST(SuppressDuplicates, MinimumDecisionMargin) {
  std::vector<Detection> v = {det(0, 0), det(100, 0), det(200, 0), det(300, 0)};
  v[0].decision_margin = 0.3;
  v[1].decision_margin = 0.29;
  v[2].decision_margin = 0.9;
  v[3].decision_margin = 0;
  drop_below_margin(v, 0.3);
  EXPECT_EQ(xs(v), (std::vector<double>{0, 200}));  // equal to the threshold is kept
  drop_below_margin(v, 0);
  EXPECT_EQ(v.size(), 2u);
}

// suppress_overlaps: another id over the same quad (each centre inside the other's corners, sizes
// within 1.5 x) is one tag read twice; fewer bits corrected wins, then the higher decision margin,
// then the earlier one.
TEST(SuppressOverlaps, AnotherIdOverTheSameQuadKeepsTheBetterReading) {
  const auto with_margin = [](Detection d, double m) {
    d.decision_margin = m;
    return d;
  };
  // Frame 64 of the 16h5 realistic set: both exact, the second 6 px off with margin 0.
  auto kept = suppress_overlaps({with_margin(det(0, 0, 38, 28), 0.96), with_margin(det(1, 6, 38, 21), 0)});
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_EQ(kept[0].id, 28);
  kept = suppress_overlaps({with_margin(det(1, 6, 38, 21), 0), with_margin(det(0, 0, 38, 28), 0.96)});
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_EQ(kept[0].id, 28);  // order does not matter when one is better
  kept = suppress_overlaps({with_margin(det(0, 0, 38, 28, 1), 0.9), with_margin(det(1, 6, 38, 21, 0), 0.1)});
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_EQ(kept[0].id, 21);  // fewer bits corrected first
  kept = suppress_overlaps({with_margin(det(0, 0, 38, 28), 0.5), with_margin(det(1, 6, 38, 21, 0, 100, "25h9"), 0.5)});
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_EQ(kept[0].id, 28);  // a full tie (another family here): the earlier one
}

TEST(SuppressOverlaps, SeparateNestedAndSameIdDetectionsAreLeftAlone) {
  EXPECT_EQ(suppress_overlaps({det(0, 0, 38, 1), det(30, 0, 38, 2)}).size(), 2u);     // apart (centres outside)
  EXPECT_EQ(suppress_overlaps({det(0, 0, 38, 1), det(18, 0, 38, 2)}).size(), 1u);     // centres inside each other
  EXPECT_EQ(suppress_overlaps({det(0, 0, 80, 1), det(0, 0, 20, 2)}).size(), 2u);      // nested: perimeters 4 x apart
  EXPECT_EQ(suppress_overlaps({det(0, 0, 40, 1), det(0, 0, 59, 2)}).size(), 1u);      // under 1.5 x
  EXPECT_EQ(suppress_overlaps({det(0, 0, 40, 1), det(0, 0, 60, 2)}).size(), 2u);      // 1.5 x: left alone
  EXPECT_EQ(suppress_overlaps({det(0, 0, 38, 1), det(2, 0, 38, 1)}).size(), 2u);      // same id: suppress_duplicates'
}

// The best reading first, whatever the input order: C overlaps both A and B (which do not overlap
// each other) and corrects fewer bits, so C alone is kept, in every order; a full tie keeps the
// earlier one.
TEST(SuppressOverlaps, BestReadingFirstInAnyOrder) {
  const Detection a = det(0, 0, 38, 1, 1), b = det(30, 0, 38, 2, 1), c = det(15, 0, 38, 3, 0);
  for (const auto& order : std::vector<std::vector<Detection>>{{a, b, c}, {a, c, b}, {b, a, c}, {c, a, b}, {b, c, a}}) {
    const auto kept = suppress_overlaps(order);
    ASSERT_EQ(kept.size(), 1u);
    EXPECT_EQ(kept[0].id, 3);
  }
  // Kept ones come back in input order: two separate tags, each with a worse reading over it.
  const auto kept =
      suppress_overlaps({det(100, 0, 38, 5, 1), det(0, 0, 38, 1), det(101, 2, 38, 6), det(1, 2, 38, 2, 1)});
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_EQ(kept[0].id, 1);
  EXPECT_EQ(kept[1].id, 6);
}

// Either winding of the corners counts; NaN centres or corners and corners on one line never overlap.
TEST(SuppressOverlaps, WindingNaNAndDegenerateQuads) {
  Detection ccw = det(2, 1, 38, 2, 1);
  std::swap(ccw.corners[1], ccw.corners[3]);  // counter-clockwise
  EXPECT_EQ(suppress_overlaps({det(0, 0, 38, 1), ccw}).size(), 1u);
  Detection nan_centre = det(2, 1, 38, 2, 1);
  nan_centre.center.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(suppress_overlaps({det(0, 0, 38, 1), nan_centre}).size(), 2u);
  Detection nan_corner = det(2, 1, 38, 2, 1);
  nan_corner.corners[2].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(suppress_overlaps({det(0, 0, 38, 1), nan_corner}).size(), 2u);
  Detection line = det(0, 0, 38, 2, 1);  // corners on the line y = 0, perimeter 4 x 19 as a square's 76
  line.corners = {Eigen::Vector2d(-19, 0), Eigen::Vector2d(0, 0), Eigen::Vector2d(19, 0), Eigen::Vector2d(0, 0)};
  EXPECT_EQ(suppress_overlaps({det(0, 0, 20, 1), line}).size(), 2u);
}

}  // namespace test_suppress_duplicates
