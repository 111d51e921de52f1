// The sixdof sweep's plan: Halton points mapped to poses and camera effects, the tag kept in view.
#include <cmath>
#include <stdexcept>

#include "codes/families.hpp"
#include "raytrace/halton.hpp"
#include "raytrace/sixdof.hpp"
#include "raytrace/sweep_detail.hpp"
#include "tools/format.hpp"
#include "tools/json.hpp"

namespace tagbench::bench {

using namespace sweep_detail;

namespace {

constexpr std::size_t kDimensions = 8;  // the six pose variables, defocus, noise
constexpr int kSkipsPerFrame = 50;      // how many skipped points per frame asked before giving up

}  // namespace

std::vector<SixdofVariable> sixdof_variables(const SweepSettings& s) {
  const SixdofSettings& x = s.sixdof;
  return {{"distance_m", x.distance_min, x.distance_max},
          {"phi_deg", 0, x.phi_max_deg},
          {"tilt_axis_deg", 0, 360},
          {"roll_deg", 0, 360},
          {"image_x", 0, kRenderWidth - 1},
          {"image_y", 0, kRenderHeight - 1},
          {"defocus_sigma_px", 0, x.defocus_max_px},
          {"noise_sigma", 0, x.noise_max}};
}

double sixdof_value(const SweepFrame& f, std::size_t variable) {
  switch (variable) {
    case 0: return f.view.distance;
    case 1: return f.view.phi_deg;
    case 2: return f.view.tilt_axis_deg;
    case 3: return f.view.roll_deg;
    case 4: return f.image_position.x();
    case 5: return f.image_position.y();
    case 6: return f.effect.camera ? f.effect.camera->defocus_sigma_px : 0;
    case 7: return f.effect.camera ? f.effect.camera->noise_sigma : 0;
    default: throw std::out_of_range("sixdof_value: no variable " + std::to_string(variable));
  }
}

std::string sixdof_description() {
  return "frames: scrambled Halton points (bases 2, 3, 5, 7, 11, 13, 17, 19; a random digit permutation per "
         "dimension and digit position drawn from the seed) from index 1 on, mapped linearly to distance, phi, "
         "tilt axis, roll, the tag centre's position in the distorted image (x, y over the whole image), defocus "
         "sigma and noise sigma; a point is skipped unless the whole printed tag (white border included, 16 "
         "points an edge) is margin_px inside the image both in the pinhole render and through the lens; per "
         "frame, splitmix64 seeded from (seed, experiment, Halton index) draws the id and the noise's seed; "
         "camera: the pinhole render remapped through OpenCV's lens model (cv::undistortPoints of every "
         "pixel, bilinear), Gaussian defocus, Gaussian sensor noise, rounded to 8 bits; truth corners: "
         "cv::projectPoints with the lens";
}

std::string sixdof_settings_json(const SweepSettings& s) {
  const SixdofSettings& x = s.sixdof;
  std::string j = "{\"frames\": " + std::to_string(s.trials) + ", \"distance_range_m\": " +
                  json_numbers({x.distance_min, x.distance_max}) + ", \"phi_max_deg\": " + json_number(x.phi_max_deg) +
                  ", \"lens\": " + json_numbers({x.distortion.begin(), x.distortion.end()}) +
                  ", \"defocus_max_px\": " + json_number(x.defocus_max_px) + ", \"noise_max\": " +
                  json_number(x.noise_max) + ", \"quantization_bits\": 8, \"margin_px\": " + json_number(x.margin_px) +
                  ", \"bins\": " + std::to_string(x.bins) + ",\n      \"variables\": [";
  const auto vars = sixdof_variables(s);
  for (std::size_t i = 0; i < vars.size(); ++i)
    j += std::string(i ? ", " : "") + "{\"name\": " + json_string(vars[i].name) + ", \"lo\": " +
         json_number(vars[i].lo) + ", \"hi\": " + json_number(vars[i].hi) + "}";
  return j + "]}";
}

std::vector<SweepFrame> plan_sixdof(const SweepSettings& s) {
  const SixdofSettings& x = s.sixdof;
  const TagFamily family = load_family(s.family);
  const int d = static_cast<int>(std::lround(std::sqrt(static_cast<double>(family.bits()))));
  const double printed = *s.tag_size * (d + 4) / (d + 2);  // the tag with its white border
  const Halton halton(kDimensions, s.seed);
  const std::uint64_t experiment_seed = derive(s.seed, static_cast<std::uint64_t>(s.experiment) + 1);
  std::vector<SweepFrame> frames;
  const auto wanted = static_cast<std::size_t>(s.trials);
  const std::uint64_t limit = static_cast<std::uint64_t>(wanted) * (kSkipsPerFrame + 1);
  for (std::uint64_t index = 1; frames.size() < wanted; ++index) {
    if (index > limit) {
      throw std::invalid_argument("the tag does not fit in the 400 x 400 image at " + std::to_string(wanted) +
                                  " Halton points: only " + std::to_string(frames.size()) + " of the first " +
                                  std::to_string(limit) + " keep the whole printed tag in view (use larger distances "
                                  "or a smaller tag size)");
    }
    const std::vector<double> u = halton.point(index);
    ViewSpec view;
    view.distance = x.distance_min + u[0] * (x.distance_max - x.distance_min);
    view.phi_deg = u[1] * x.phi_max_deg;
    view.tilt_axis_deg = 360 * u[2];
    view.roll_deg = 360 * u[3];
    const Eigen::Vector2d image(u[4] * (kRenderWidth - 1), u[5] * (kRenderHeight - 1));
    const auto pinhole = undistort_pixel(image, x.distortion);
    if (!pinhole) continue;
    view.pixel = *pinhole;
    const Pose pose = view_pose(view);
    if (!sixdof_fits(pose, printed, x.distortion, x.margin_px)) continue;
    SweepFrame f;
    f.step = 0;
    f.trial = static_cast<int>(frames.size());
    f.seed = derive(experiment_seed, index);
    f.sample = index;
    f.view = view;
    f.image_position = image;
    f.frame.pose = pose;
    f.frame.family = s.family;
    f.frame.family_name = family.name();
    Rng rng{f.seed};
    f.frame.id = static_cast<int>(rng.next() % family.size());
    f.frame.tag_size = *s.tag_size;
    f.truth = ground_truth(f.frame);
    f.truth.corners = project_corners(pose, *s.tag_size, x.distortion);
    double edges = 0;
    for (std::size_t k = 0; k < 4; ++k) edges += (f.truth.corners[(k + 1) % 4] - f.truth.corners[k]).norm();
    f.truth.black_square_px = edges / 4;
    CameraEffects cam;
    cam.distortion = x.distortion;
    cam.defocus_sigma_px = u[6] * x.defocus_max_px;
    cam.noise_sigma = u[7] * x.noise_max;
    cam.noise_seed = rng.next();
    f.effect.camera = cam;
    frames.push_back(std::move(f));
  }
  return frames;
}

}  // namespace tagbench::bench
