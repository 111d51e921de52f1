#include "scenes.hpp"

#include <random>

#include <opencv2/imgproc.hpp>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"

namespace tagbench::bench {

Scene make_scene(int width, int height, const std::string& family, int count, std::uint32_t seed) {
  const TagFamily& fam = builtin_family(family);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const int S = 2;  // supersampling
  cv::Mat big(height * S, width * S, CV_32F);
  // Background: a lighting gradient plus random rectangles, blurred.
  for (int y = 0; y < big.rows; ++y)
    for (int x = 0; x < big.cols; ++x) big.at<float>(y, x) = static_cast<float>(0.35 + 0.3 * x / big.cols + 0.1 * y / big.rows);
  for (int r = 0; r < 60; ++r) {
    const int w = static_cast<int>(big.cols * (0.02 + 0.15 * u(rng))), h = static_cast<int>(big.rows * (0.02 + 0.15 * u(rng)));
    const int x = static_cast<int>((big.cols - w) * u(rng)), y = static_cast<int>((big.rows - h) * u(rng));
    big(cv::Rect(x, y, w, h)).setTo(0.15 + 0.7 * u(rng));
  }
  cv::GaussianBlur(big, big, cv::Size(0, 0), 1.5 * S);
  Scene scene;
  std::vector<cv::Rect> used;
  for (int k = 0, attempts = 0; k < count && attempts < 200; ++attempts) {
    const double side = height * (0.08 + 0.17 * u(rng));
    const double cx = side + (width - 2 * side) * u(rng), cy = side + (height - 2 * side) * u(rng);
    const cv::Rect box(static_cast<int>(cx - side), static_cast<int>(cy - side), static_cast<int>(2 * side),
                       static_cast<int>(2 * side));
    bool overlap = false;
    for (const auto& b : used) overlap = overlap || (b & box).area() > 0;
    if (overlap) continue;
    used.push_back(box);
    // Corners of a square, rotated in plane, then each corner moved to fake a perspective tilt.
    const double a = 2 * M_PI * u(rng), tilt = 0.25 * u(rng);
    const Eigen::Vector2d ex(std::cos(a), std::sin(a)), ey(-std::sin(a), std::cos(a)), c(cx, cy);
    const double h2 = side / 2;
    Corners corners = {c - h2 * ex - h2 * ey, c + h2 * ex - h2 * ey, c + h2 * ex + h2 * ey, c - h2 * ex + h2 * ey};
    const int shrink = static_cast<int>(rng() % 4);  // one edge foreshortened
    corners[static_cast<std::size_t>(shrink)] += tilt * (c - corners[static_cast<std::size_t>(shrink)]);
    corners[static_cast<std::size_t>((shrink + 1) % 4)] += tilt * (c - corners[static_cast<std::size_t>((shrink + 1) % 4)]);
    const int id = static_cast<int>(rng() % fam.size());
    const TagCells cells = tag_cells(fam, id);
    // Tag image with one pixel per cell; map cell edges (pixel corners) to the supersampled image.
    cv::Mat tag(cells.n, cells.n, CV_32F);
    for (int y = 0; y < cells.n; ++y)
      for (int x = 0; x < cells.n; ++x) tag.at<float>(y, x) = cells.at(y, x) ? 0.92f : 0.08f;
    // Black square corners are at cell-edge coordinates 1 and n-1 (pixel-corner convention: -0.5 offsets).
    const double lo = 1 - 0.5, hi = cells.n - 1 - 0.5;
    std::vector<cv::Point2f> src = {{static_cast<float>(lo), static_cast<float>(lo)},
                                    {static_cast<float>(hi), static_cast<float>(lo)},
                                    {static_cast<float>(hi), static_cast<float>(hi)},
                                    {static_cast<float>(lo), static_cast<float>(hi)}};
    std::vector<cv::Point2f> dst;
    for (const auto& p : corners)  // image pixel centres at integers -> supersampled pixel centres
      dst.emplace_back(static_cast<float>((p.x() + 0.5) * S - 0.5), static_cast<float>((p.y() + 0.5) * S - 0.5));
    const cv::Mat M = cv::getPerspectiveTransform(src, dst);
    cv::Mat warped, mask;
    cv::warpPerspective(tag, warped, M, big.size(), cv::INTER_NEAREST, cv::BORDER_CONSTANT, cv::Scalar(-1));
    mask = warped >= 0;
    warped.copyTo(big, mask);
    scene.tags.push_back({id, corners});
    ++k;
  }
  cv::Mat small;
  cv::resize(big, small, cv::Size(width, height), 0, 0, cv::INTER_AREA);
  cv::Mat noise(small.size(), CV_32F);
  cv::RNG cvrng(seed);
  cvrng.fill(noise, cv::RNG::NORMAL, 0.0, 0.01);
  small += noise;
  small.convertTo(scene.image, CV_8U, 255.0);
  return scene;
}

}  // namespace tagbench::bench
