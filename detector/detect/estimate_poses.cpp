#include "detect/estimate_poses.hpp"

#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "detect/homography.hpp"

namespace tagbench {
namespace {

Corners undistort(const Corners& c, const CameraIntrinsics& K, const std::array<double, 5>& dist) {
  std::vector<cv::Point2d> in, out;
  for (const auto& p : c) in.emplace_back(p.x(), p.y());
  const cv::Matx33d Km(K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1);
  const cv::Matx<double, 1, 5> D(dist[0], dist[1], dist[2], dist[3], dist[4]);
  cv::undistortPoints(in, out, Km, D, cv::noArray(), Km);  // P = K keeps pixel units
  Corners r;
  for (std::size_t i = 0; i < 4; ++i) r[i] = Eigen::Vector2d(out[i].x, out[i].y);
  return r;
}

}  // namespace

void estimate_poses(std::span<Detection> detections, const CameraIntrinsics& camera, double tag_size,
                    const std::optional<std::array<double, 5>>& distortion, bool refine) {
  for (auto& d : detections) {
    const Corners c = distortion ? undistort(d.corners, camera, *distortion) : d.corners;
    if (refine) {
      const auto sols = tag_pose_solutions(c, camera, tag_size);
      if (!sols.empty()) d.pose = sols[0];
      if (sols.size() > 1) d.pose_alternative = sols[1];
    } else if (const auto H = tag_homography(c)) {
      const Pose p = pose_from_homography(*H, camera, tag_size);
      d.pose = PoseSolution{p, corner_rms_error(p, c, camera, tag_size)};
    }
  }
}

}  // namespace tagbench
