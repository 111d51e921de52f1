// External detectors (issue 12, section 3): the batch protocol (paths on stdin, lines back in any
// order) and every fault, each one line naming the detector and the image.
#include <gtest/gtest.h>

#include "external/external_detector.hpp"
#include "scratch_dir.hpp"

namespace tagbench::bench {
namespace test_external {
namespace {

const std::vector<std::string> kImages = {"/data/a.png", "/data/b.png", "/data/c.png"};

// The error of running `script` (sh -c) as detector "det", or "ok".
std::string error_of(const std::string& script, double timeout = 30) {
  testing::ScratchDir dir("tagbench_external");
  try {
    ExternalDetector d = parse_external_detector("det=sh -c '" + script + "'", timeout);
    run_external(d, kImages, dir.path());
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "ok";
}

// Echoes a line per path read, in reverse order (any order is fine), with a detection in one of them.
constexpr const char* kGood =
    "tac | while read p; do if [ \"$p\" = /data/b.png ]; then "
    "echo \"{\\\"image\\\": \\\"$p\\\", \\\"ms\\\": 3, \\\"detections\\\": [{\\\"family\\\": \\\"36h11\\\", \\\"id\\\": 5, "
    "\\\"corners\\\": [[1, 2], [3, 4], [5, 6], [7, 8]]}]}\"; "
    "else echo \"{\\\"image\\\": \\\"$p\\\", \\\"detections\\\": []}\"; fi; done";

TEST(External, ABatchInAnyOrderComesBackInInputOrder) {
  testing::ScratchDir dir("tagbench_external");
  const ExternalDetector d = parse_external_detector(std::string("det=sh -c '") + kGood + "'", 30);
  EXPECT_EQ(d.argv.size(), 3u);
  const auto got = run_external(d, kImages, dir.path());
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(got[0].image, "/data/a.png");
  EXPECT_TRUE(got[0].found.empty());
  ASSERT_EQ(got[1].found.size(), 1u);
  EXPECT_EQ(got[1].found[0].id, 5);
  EXPECT_EQ(got[1].found[0].corners[3].y(), 8);
  EXPECT_EQ(got[1].ms, 3);
  EXPECT_TRUE(std::isnan(got[2].ms));
}

TEST(External, EveryFaultIsOneLineNamingTheDetectorAndTheImage) {
  EXPECT_EQ(error_of("read a; echo oops >&2; exit 3"),
            "external detector det: exited with status 3 at image '/data/a.png' (its last message: oops)");
  EXPECT_EQ(error_of("read a; echo \"{\\\"image\\\": \\\"$a\\\", \\\"detections\\\": []}\"; kill -SEGV $$"),
            "external detector det: was killed by signal 11 at image '/data/b.png'");
  EXPECT_EQ(error_of("read a; echo \"{\\\"image\\\": \\\"$a\\\", \\\"detections\\\": []}\"; sleep 30", 0.3),
            "external detector det: no end within 0.3 s (--external-timeout); killed at image '/data/b.png' "
            "(2 of 3 images without a line)");
  EXPECT_EQ(error_of("echo \"{bad\""),
            "external detector det: output line 1 is not a detection line (at byte 1: expected a member name in "
            "double quotes) (first image without a valid line: '/data/a.png')");
  EXPECT_EQ(error_of("read a; echo \"{\\\"image\\\": \\\"$a\\\", \\\"detections\\\": []}\""),
            "external detector det: no line for image '/data/b.png' (2 of 3 images left out)");
  EXPECT_EQ(error_of("echo \"{\\\"image\\\": \\\"/data/x.png\\\", \\\"detections\\\": []}\""),
            "external detector det: output line 1 names image '/data/x.png', which it was not given (first image "
            "without a valid line: '/data/a.png')");
  EXPECT_EQ(error_of("read a; echo \"{\\\"image\\\": \\\"$a\\\", \\\"error\\\": \\\"cannot decode\\\"}\""),
            "external detector det: image '/data/a.png': cannot decode");
  testing::ScratchDir dir("tagbench_external");
  try {
    run_external(parse_external_detector("det=/no/such/program --x", 30), kImages, dir.path());
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "external detector det: cannot run '/no/such/program' (not found or not executable), at "
                           "image '/data/a.png'");
  }
}

TEST(External, BadSpecsAreRefused) {
  EXPECT_THROW(parse_external_detector("no-equals", 1), std::invalid_argument);
  EXPECT_THROW(parse_external_detector("=cmd", 1), std::invalid_argument);
  EXPECT_THROW(parse_external_detector("a,b=cmd", 1), std::invalid_argument);
  EXPECT_THROW(parse_external_detector("a=cmd 'unclosed", 1), std::invalid_argument);
  EXPECT_EQ(parse_external_detector("a=py x.py --k 'a b',c", 1).argv, (std::vector<std::string>{"py", "x.py", "--k", "a b,c"}));
}

}  // namespace
}  // namespace test_external
}  // namespace tagbench::bench
