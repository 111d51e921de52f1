#pragma once
// 6-DOF tag pose (paper section III-C, and beyond it).
//
// Frames: camera x right, y down, z forward; tag origin at the tag centre, x toward the tag's right
// edge, y toward its bottom edge (as printed), z into the tag. A pose (R, t) maps tag points into
// the camera frame: X_cam = R X_tag + t, in metres. Tag size = the black square's edge (metres), so
// the corners are (±s/2, ±s/2, 0) in the order top-left, top-right, bottom-right, bottom-left.
// Image points: pixels, centres at integer coordinates; lens distortion is removed beforehand.
#include <array>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "homography.hpp"

namespace tagbench {

struct CameraIntrinsics {
  double fx = 0, fy = 0;  // focal lengths, pixels
  double cx = 0, cy = 0;  // principal point, pixels (centres-at-integers convention)
  bool valid() const;     // finite, fx and fy > 0
};

struct Pose {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
};

// How far R is from orthonormal: the largest entry of |R^T R - I| (0 for a rotation or reflection;
// NaN propagates, so `!(rotation_defect(R) <= tol)` refuses it too).
inline double rotation_defect(const Eigen::Matrix3d& R) {
  return (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
}

struct PoseSolution {
  Pose pose;
  double reprojection_rms_px = 0;  // RMS distance between the observed and projected corners
  // Pearson correlation (-1..1) of the decoded tag's pattern projected by this pose with the image
  // (pose_choice.hpp); NaN when the pose choice did not judge it.
  double pattern_correlation = std::numeric_limits<double>::quiet_NaN();
};

// The paper's extrinsics from the tag homography (tag_homography(): square [-1,1]^2 -> pixels):
// remove the intrinsics, scale by the geometric mean of the first two columns' norms, choose the
// sign that puts the tag in front of the camera (t_z > 0 in our frame), third column by the cross
// product, then the polar decomposition (R = U V^T from the SVD) for a proper rotation; the
// translation is scaled by tag_size / 2.
Pose pose_from_homography(const Eigen::Matrix3d& H, const CameraIntrinsics& K, double tag_size);

// The tag's corners projected through a pose (pinhole, no distortion).
Corners project_tag_corners(const Pose& pose, const CameraIntrinsics& K, double tag_size);
double corner_rms_error(const Pose& pose, const Corners& observed, const CameraIntrinsics& K, double tag_size);

// Levenberg-Marquardt on the 6 pose parameters minimising the corners' reprojection error.
Pose refine_pose(const Pose& initial, const Corners& observed, const CameraIntrinsics& K, double tag_size);

// Both solutions of the planar pose ambiguity (infinitesimal plane-based pose estimation, Collins &
// Bartoli 2014, from the homography's Jacobian at the tag centre), each refined by refine_pose, with
// their reprojection errors, best first. A tag seen nearly face-on or small in the image has two
// poses that explain its corners almost equally well: the second one is what a "pose flip" jumps to.
// Returns one or two solutions (one when both converge to the same pose).
std::vector<PoseSolution> tag_pose_solutions(const Corners& observed, const CameraIntrinsics& K, double tag_size);

// The angle of R_a^T R_b in degrees (orientation error).
double rotation_angle_deg(const Eigen::Matrix3d& Ra, const Eigen::Matrix3d& Rb);

}  // namespace tagbench
