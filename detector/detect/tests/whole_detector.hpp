#pragma once
// Shared by the whole-detector tests (test_detector_views.cpp, test_detector_inputs.cpp,
// test_detector_workspace.cpp): the paper's options for some families, and two detection lists
// compared field by field.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "detect/detector.hpp"

namespace tagbench::test_detector {

inline DetectorOptions opts(std::vector<std::string> fams, int max_hamming = 1) {
  DetectorOptions o = DetectorOptions::paper();
  o.families = std::move(fams);
  o.max_hamming = max_hamming;
  return o;
}

inline void expect_same(const std::vector<Detection>& a, const std::vector<Detection>& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].id, b[i].id) << what;
    EXPECT_EQ(a[i].decision_margin, b[i].decision_margin) << what;
    for (std::size_t k = 0; k < 4; ++k) EXPECT_EQ(a[i].corners[k], b[i].corners[k]) << what << " corner " << k;
  }
}

}  // namespace tagbench::test_detector
