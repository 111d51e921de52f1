#pragma once
// The 6-DoF sweep's own parts (sweeps.hpp declares the shared ones): its plan and its camera.
#include <vector>

#include "raytrace/sweeps.hpp"

namespace cv {
class Mat;
}

namespace tagbench::bench {

// The frames of a resolved sixdof sweep: Halton points (halton.hpp; 8 dimensions, scrambled from the
// sweep's seed) taken from index 1 on, each mapped to distance, phi, tilt axis, roll, image x, image y
// (the tag centre in the distorted image, anywhere in [0, width - 1] x [0, height - 1]), defocus and
// noise; a point whose tag would not be in view (sixdof_fits) is skipped, so the frames are the first
// `trials` points inside the feasible region and frame k does not depend on how many are asked for.
// Throws std::invalid_argument when too few points fit (more than 50 skipped per frame asked).
std::vector<SweepFrame> plan_sixdof(const SweepSettings& resolved);

// The camera applied to an 8-bit gray pinhole render (CameraEffects' order). The distortion maps are
// computed once per lens and image size (cached, thread-safe).
cv::Mat apply_camera_effects(const cv::Mat& gray8, const CameraEffects& e);

// One line on the sweep's sampling and camera, for the sidecars.
std::string sixdof_description();
// The sixdof settings as the sidecars write them (what scripts/plot_sixdof.py reads): {"frames",
// "distance_range_m", "phi_max_deg", "lens", "defocus_max_px", "noise_max", "quantization_bits",
// "margin_px", "bins", "variables": [{"name", "lo", "hi"}]}.
std::string sixdof_settings_json(const SweepSettings& resolved);

}  // namespace tagbench::bench
