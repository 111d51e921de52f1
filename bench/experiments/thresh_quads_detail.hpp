#pragma once
// What thresh_quads.cpp (the detectors, the tables, the modes) takes from thresh_quads_frames.cpp: the
// frames the experiments run on, each with its tags' true corners, and the images of a folder.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "detect/homography.hpp"

namespace tagbench::bench::experiments::thresh_quads_detail {

struct TruthTag {
  int id;
  Corners corners;
  double px;  // sqrt of the black square's area
  double tilt = -1;  // degrees between the tag's normal and the line of sight (-1: unknown)
};
struct Frame {
  cv::Mat gray;
  std::vector<TruthTag> tags;
};

double quad_area(const Corners& c);

// bench/realistic frames; blur >= 0: every frame's defocus sigma fixed at blur px.
std::vector<Frame> realistic_frames(int n, const std::string& family, std::uint64_t seed, double blur = -1);
// make_scene at 5x, shrunk to 240 x 180 (tags ~14-45 px) with noise and JPEG.
std::vector<Frame> small_frames(int n, const std::string& family, std::uint32_t seed);
// make_scene at 640 x 480 (tags 38-120 px), defocused by a Gaussian blur of sigma px, noise and JPEG.
std::vector<Frame> defocus_frames(int n, const std::string& family, double sigma);

// The images under dir and its subfolders (png, jpg, jpeg, webp), sorted; at most max, spread over the list.
std::vector<std::string> image_files(const std::string& dir, std::size_t max);
// Read as gray, at most 2048 px on the longer side; unreadable files are skipped.
std::vector<cv::Mat> load_gray(const std::vector<std::string>& files);

}  // namespace tagbench::bench::experiments::thresh_quads_detail
