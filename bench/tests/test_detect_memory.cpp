// detect_memory (bench/detect_memory.cpp): the CSV it writes for results/memory.csv, on small sizes.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "run_tagbench.hpp"

namespace test_detect_memory {

namespace fs = std::filesystem;
using tagbench::testing::shell_quote;
using tagbench::testing::slurp;

namespace {

struct ToolRun {
  int code = -1;
  std::string err;
};

ToolRun detect_memory(const std::string& args, const fs::path& dir) {
  const fs::path err = dir / "stderr.txt";
  const std::string cmd = shell_quote(DETECT_MEMORY_BIN) + " " + args + " >/dev/null 2>" + shell_quote(err.string());
  const int st = std::system(cmd.c_str());
  return {WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st), slurp(err)};
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, sep);) out.push_back(item);
  return out;
}

class DetectMemory : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("tagbench_detect_memory_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

}  // namespace

TEST_F(DetectMemory, WritesOneRowPerSizeAndSettingWithPlausibleNumbers) {
  const fs::path csv = dir_ / "memory.csv";
  const ToolRun r = detect_memory("--out " + shell_quote(csv.string()) + " --sizes 400x300,240x200 --tags 2", dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto lines = split(slurp(csv), '\n');
  ASSERT_EQ(lines.size(), 5u);  // header + 2 sizes x (full, half)
  const std::string header =
      "width,height,megapixels,half_resolution,families,max_hamming,seg_sigma,max_pixels,tags_in_scene,"
      "detections,detect_ms,peak_rss_mb,bytes_per_pixel,workspace_mb,warm_frame_peak_mb";
  EXPECT_EQ(lines[0], header);
  const auto columns = split(header, ',');
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const auto v = split(lines[i], ',');
    ASSERT_EQ(v.size(), columns.size()) << lines[i];
    auto num = [&](const char* name) {
      for (std::size_t c = 0; c < columns.size(); ++c)
        if (columns[c] == name) return std::stod(v[c]);
      ADD_FAILURE() << "no column " << name;
      return 0.0;
    };
    const bool big = i <= 2;
    EXPECT_EQ(num("width"), big ? 400 : 240);
    EXPECT_EQ(num("height"), big ? 300 : 200);
    EXPECT_EQ(num("half_resolution"), i % 2 == 0 ? 1 : 0);
    EXPECT_DOUBLE_EQ(num("megapixels"), big ? 0.12 : 0.048);
    EXPECT_EQ(v[4], "36h11");
    // Full resolution needs tens of bytes a pixel (the float image alone is 4), half about a
    // quarter of that plus the full-size float image; never hundreds.
    const double bpp = num("bytes_per_pixel");
    EXPECT_GT(bpp, i % 2 == 0 ? 5.0 : 20.0) << lines[i];
    EXPECT_LT(bpp, 400.0) << lines[i];
    EXPECT_NEAR(num("peak_rss_mb"), bpp * num("megapixels") * 1e6 / (1024 * 1024), 0.11) << lines[i];
    EXPECT_GT(num("workspace_mb"), 0.0) << lines[i];
    // The warm workspace: a second frame of the same size adds a small fraction of the first's peak.
    EXPECT_LT(num("warm_frame_peak_mb"), 0.25 * num("peak_rss_mb")) << lines[i];
  }
  // Only the result is left: the temporary was renamed over it.
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_)) ++files;
  EXPECT_EQ(files, 2u);  // memory.csv and stderr.txt
}

TEST_F(DetectMemory, BadSizeIsAUsageErrorAndWritesNothing) {
  const fs::path csv = dir_ / "memory.csv";
  const ToolRun r = detect_memory("--out " + shell_quote(csv.string()) + " --sizes 640x480,12xx3", dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("12xx3"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(csv));
}

}  // namespace test_detect_memory
