#pragma once
// Stage 7 of the detector (paper section III-C): each detection's pose from its corners.
// Conventions as in detector.hpp and pose.hpp (pixels; tag size in metres, the black square's edge).
#include <array>
#include <optional>
#include <span>

#include "detect/detector.hpp"
#include "detect/pose.hpp"

namespace tagbench {

// For every detection: the corners, undistorted first when `distortion` is given (OpenCV's k1, k2,
// p1, p2, k3; the undistorted points stay in pixels), give the pose. With `refine` (beyond the
// paper) both solutions of the planar ambiguity minimising the corners' reprojection error
// (tag_pose_solutions): the better one in `pose`, the other in `pose_alternative`. Without it the
// paper's pose from the homography (pose_from_homography), in `pose`. A detection whose corners
// give no pose keeps none. Detections' other fields are left alone.
void estimate_poses(std::span<Detection> detections, const CameraIntrinsics& camera, double tag_size,
                    const std::optional<std::array<double, 5>>& distortion, bool refine);

}  // namespace tagbench
