#include "raytrace/comparators.hpp"

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>

#include <Eigen/Dense>
#include <apriltag/apriltag.h>
#include <apriltag/apriltag_pose.h>
#include <apriltag/tag16h5.h>
#include <apriltag/tag25h9.h>
#include <apriltag/tag36h10.h>
#include <apriltag/tag36h11.h>
#include <opencv2/aruco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/eigen.hpp>

#include "codes/families.hpp"
#include "detect/detector.hpp"
#include "detect/detector_opencv.hpp"
#include "raytrace/detector_variants.hpp"

namespace tagbench::bench {

DetectorOutput Comparator::run(const cv::Mat& gray8) {
  if (gray8.empty() || gray8.type() != CV_8UC1) throw std::invalid_argument(name_ + ": needs an 8-bit gray image");
  const auto t0 = std::chrono::steady_clock::now();
  DetectorOutput out;
  out.found = detect(gray8);
  out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

std::optional<LossExplanation> Comparator::explain(const cv::Mat&, const std::string&, int, const Corners&) {
  return std::nullopt;
}

namespace {

bool wants_pose(const ComparatorSetup& s) { return s.camera.has_value(); }

void check_setup(const ComparatorSetup& s) {
  if (s.camera && (!s.camera->valid() || !(s.tag_size > 0) || !std::isfinite(s.tag_size)))
    throw std::invalid_argument("a pose needs valid intrinsics and a tag size > 0");
}

// ---- ours ------------------------------------------------------------------------------------------

class Ours final : public Comparator {
 public:
  // profile: DetectorOptions::paper(), thorough() or the default; variant: see detector_variants.hpp.
  Ours(std::string name, const ComparatorSetup& s, const DetectorOptions& profile, bool half,
       const std::string& variant = "")
      : Comparator(name), detector_(options(s, profile, half, variant, name)) {}

 private:
  static DetectorOptions options(const ComparatorSetup& s, const DetectorOptions& profile, bool half,
                                 const std::string& variant, const std::string& name) {
    DetectorOptions o = profile;
    o.families = {s.family};
    o.half_resolution = half;
    o.input_gamma = s.input_gamma;
    if (wants_pose(s)) {
      o.camera = *s.camera;
      o.tag_size = s.tag_size;
      o.distortion = s.distortion;
    }
    apply_detector_variant(o, variant, name);
    return o;
  }

  std::vector<Found> detect(const cv::Mat& gray8) override {
    std::vector<Found> out;
    for (const Detection& d : tagbench::detect(detector_, gray8, workspace_)) {
      Found f;
      f.family = d.family;
      f.id = d.id;
      f.hamming = d.hamming;
      f.decision_margin = d.decision_margin;
      f.corners = d.corners;
      if (d.pose) f.pose = d.pose->pose;
      out.push_back(std::move(f));
    }
    return out;
  }

  std::optional<LossExplanation> explain(const cv::Mat& gray8, const std::string& family, int id,
                                         const Corners& truth) override {
    for (const TagFamily& f : detector_.families()) {
      if (canonical_family_name(f.name()) != canonical_family_name(family)) continue;
      DetectorTrace trace;
      const std::vector<Detection> dets = tagbench::detect(detector_, gray8, workspace_, &trace);
      return explain_loss({&f, id, truth}, trace, dets, detector_.options());
    }
    return std::nullopt;
  }
  bool can_explain() const override { return true; }

  Detector detector_;
  DetectorWorkspace workspace_;  // reused frame after frame (a Comparator is one thread's)
};

// ---- libapriltag 3.3 --------------------------------------------------------------------------------

struct AprilFamily {
  apriltag_family_t* (*create)();
  void (*destroy)(apriltag_family_t*);
};

AprilFamily april_family(const std::string& name) {
  if (name == "16h5") return {tag16h5_create, tag16h5_destroy};
  if (name == "25h9") return {tag25h9_create, tag25h9_destroy};
  if (name == "36h10") return {tag36h10_create, tag36h10_destroy};
  if (name == "36h11") return {tag36h11_create, tag36h11_destroy};
  throw std::invalid_argument("libapriltag has no family '" + name + "' (16h5, 25h9, 36h10, 36h11)");
}

class LibAprilTag final : public Comparator {
 public:
  LibAprilTag(std::string name, const ComparatorSetup& s, float decimate)
      : Comparator(std::move(name)), setup_(s), family_name_(canonical_family_name(s.family)), fam_(april_family(family_name_)) {
    tf_ = fam_.create();
    td_ = apriltag_detector_create();
    apriltag_detector_add_family(td_, tf_);  // its default: 2 corrected bits
    td_->quad_decimate = decimate;
    td_->nthreads = 1;
  }
  ~LibAprilTag() override {
    apriltag_detector_destroy(td_);
    fam_.destroy(tf_);
  }
  LibAprilTag(const LibAprilTag&) = delete;
  LibAprilTag& operator=(const LibAprilTag&) = delete;

 private:
  std::vector<Found> detect(const cv::Mat& gray8) override {
    image_u8_t im{gray8.cols, gray8.rows, static_cast<std::int32_t>(gray8.step), gray8.data};
    zarray_t* dets = apriltag_detector_detect(td_, &im);
    std::vector<Found> out;
    for (int i = 0; i < zarray_size(dets); ++i) {
      apriltag_detection_t* det = nullptr;
      zarray_get(dets, i, &det);
      Found f;
      f.family = family_name_;
      f.id = det->id;
      f.hamming = det->hamming;
      f.decision_margin = det->decision_margin;
      // Its p[0..3] are the printed BL, BR, TR, TL, in "pixel i covers [i, i+1)".
      for (int k = 0; k < 4; ++k)
        f.corners[static_cast<std::size_t>(k)] = Eigen::Vector2d(det->p[3 - k][0] - 0.5, det->p[3 - k][1] - 0.5);
      if (wants_pose(setup_)) {
        apriltag_detection_info_t info{det, setup_.tag_size, setup_.camera->fx, setup_.camera->fy,
                                       setup_.camera->cx + 0.5, setup_.camera->cy + 0.5};
        apriltag_pose_t pose{nullptr, nullptr};
        estimate_tag_pose(&info, &pose);
        if (pose.R && pose.t) {
          Pose p;
          for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) p.R(r, c) = MATD_EL(pose.R, r, c);
            p.t(r) = MATD_EL(pose.t, r, 0);
          }
          if (p.R.allFinite() && p.t.allFinite()) f.pose = p;  // its tag frame is ours
        }
        std::free(pose.R);  // matd_destroy is not exported; a matd_t is one allocation
        std::free(pose.t);
      }
      out.push_back(std::move(f));
    }
    apriltag_detections_destroy(dets);
    return out;
  }

  ComparatorSetup setup_;
  std::string family_name_;
  AprilFamily fam_;
  apriltag_family_t* tf_ = nullptr;
  apriltag_detector_t* td_ = nullptr;
};

// ---- OpenCV aruco ------------------------------------------------------------------------------------

cv::aruco::PREDEFINED_DICTIONARY_NAME aruco_dictionary(const std::string& name) {
  if (name == "16h5") return cv::aruco::DICT_APRILTAG_16h5;
  if (name == "25h9") return cv::aruco::DICT_APRILTAG_25h9;
  if (name == "36h10") return cv::aruco::DICT_APRILTAG_36h10;
  if (name == "36h11") return cv::aruco::DICT_APRILTAG_36h11;
  throw std::invalid_argument("OpenCV aruco has no AprilTag dictionary for '" + name + "' (16h5, 25h9, 36h10, 36h11)");
}

class Aruco final : public Comparator {
 public:
  // apriltag_refinement: CORNER_REFINE_APRILTAG (its corners in the [i, i+1) convention); otherwise
  // OpenCV's default CORNER_REFINE_NONE (corners at pixel centres already).
  Aruco(std::string name, const ComparatorSetup& s, bool apriltag_refinement)
      : Comparator(std::move(name)),
        shift_(apriltag_refinement ? 0.5f : 0.0f),
        setup_(s),
        family_name_(canonical_family_name(s.family)),
        dict_(cv::aruco::getPredefinedDictionary(aruco_dictionary(family_name_))),
        params_(cv::aruco::DetectorParameters::create()) {
    if (apriltag_refinement) params_->cornerRefinementMethod = cv::aruco::CORNER_REFINE_APRILTAG;
    if (wants_pose(s)) {
      camera_ = (cv::Mat_<double>(3, 3) << s.camera->fx, 0, s.camera->cx, 0, s.camera->fy, s.camera->cy, 0, 0, 1);
      if (s.distortion) {
        const auto& k = *s.distortion;
        dist_ = (cv::Mat_<double>(1, 5) << k[0], k[1], k[2], k[3], k[4]);
      }
      // Its marker's corners in its frame (x right, y up, z out of the face), as estimatePoseSingleMarkers has them.
      const float h = static_cast<float>(s.tag_size / 2);
      object_ = {{-h, h, 0}, {h, h, 0}, {h, -h, 0}, {-h, -h, 0}};
    }
  }

 private:
  std::vector<Found> detect(const cv::Mat& gray8) override {
    std::vector<std::vector<cv::Point2f>> corners;
    std::vector<int> ids;
    cv::aruco::detectMarkers(gray8, dict_, corners, ids, params_);
    std::vector<Found> out;
    const Eigen::Matrix3d flip = Eigen::Vector3d(-1, 1, -1).asDiagonal();
    for (std::size_t i = 0; i < ids.size(); ++i) {
      Found f;
      f.family = family_name_;
      f.id = ids[i];
      // Its corner 0 is its marker's top-left, which is the official tag's bottom-right.
      std::vector<cv::Point2f> centred(4);
      for (std::size_t k = 0; k < 4; ++k) centred[k] = corners[i][k] - cv::Point2f(shift_, shift_);
      for (std::size_t k = 0; k < 4; ++k) {
        const cv::Point2f& c = centred[(k + 2) % 4];
        f.corners[k] = Eigen::Vector2d(c.x, c.y);
      }
      if (wants_pose(setup_)) {
        cv::Mat rvec, tvec;
        const cv::_InputArray dist = dist_.empty() ? cv::_InputArray(cv::noArray()) : cv::_InputArray(dist_);
        if (cv::solvePnP(object_, centred, camera_, dist, rvec, tvec, false, cv::SOLVEPNP_IPPE_SQUARE)) {
          cv::Mat Rcv;
          cv::Rodrigues(rvec, Rcv);
          Eigen::Matrix3d Ra;
          Eigen::Vector3d t;
          cv::cv2eigen(Rcv, Ra);
          cv::cv2eigen(tvec, t);
          Pose p;
          p.R = Ra * flip;  // X_aruco = diag(-1, 1, -1) X_ours
          p.t = t;
          if (p.R.allFinite() && p.t.allFinite()) f.pose = p;
        }
      }
      out.push_back(std::move(f));
    }
    return out;
  }

  float shift_;  // to pixel centres at integers
  ComparatorSetup setup_;
  std::string family_name_;
  cv::Ptr<cv::aruco::Dictionary> dict_;
  cv::Ptr<cv::aruco::DetectorParameters> params_;
  cv::Mat camera_, dist_;  // dist_ empty: no distortion
  std::vector<cv::Point3f> object_;
};

// Our detector's comparator names, each also the base of its variants ("BASE/KEY=V/...").
constexpr const char* kOursBases[] = {"tagbench", "tagbench-half", "tagbench-paper", "tagbench-paper-half",
                                      "tagbench-thorough"};

}  // namespace

const std::vector<std::string>& comparator_names() {
  static const std::vector<std::string> names{"tagbench",       "tagbench-half",  "tagbench-paper", "tagbench-paper-half",
                                              "libapriltag-d1", "libapriltag-d2", "aruco"};
  return names;
}

bool is_ours_variant(const std::string& name) {
  for (const char* base : kOursBases)
    if (name.rfind(std::string(base) + "/", 0) == 0) return true;
  return false;
}

const std::vector<std::string>& known_comparator_names() {
  static const std::vector<std::string> names = [] {
    auto n = comparator_names();
    n.push_back("tagbench-thorough");
    n.push_back("aruco-default");
    return n;
  }();
  return names;
}

std::unique_ptr<Comparator> make_comparator(const std::string& name, const ComparatorSetup& setup) {
  check_setup(setup);
  for (const char* base : kOursBases) {
    const std::string b = base;
    if (name != b && name.rfind(b + "/", 0) != 0) continue;
    const std::string variant = name.size() > b.size() ? name.substr(b.size() + 1) : "";
    const DetectorOptions profile = b.find("paper") != std::string::npos      ? DetectorOptions::paper()
                                    : b.find("thorough") != std::string::npos ? DetectorOptions::thorough()
                                                                              : DetectorOptions{};
    return std::make_unique<Ours>(name, setup, profile, b.find("half") != std::string::npos, variant);
  }
  if (name == "libapriltag-d1") return std::make_unique<LibAprilTag>(name, setup, 1.0f);
  if (name == "libapriltag-d2") return std::make_unique<LibAprilTag>(name, setup, 2.0f);
  if (name == "aruco") return std::make_unique<Aruco>(name, setup, true);
  if (name == "aruco-default") return std::make_unique<Aruco>(name, setup, false);
  std::string known;
  for (const auto& n : known_comparator_names()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown detector '" + name + "' (known: " + known + ")");
}

FoundErrors found_errors(const Found& found, const GroundTruth& truth) {
  FoundErrors e;
  double sq = 0;
  for (std::size_t k = 0; k < 4; ++k) {
    const double d = (found.corners[k] - truth.corners[k]).norm();
    sq += d * d;
    e.corner_max_px = std::max(e.corner_max_px, d);
  }
  e.corner_rms_px = std::sqrt(sq / 4);
  if (found.pose) {
    e.orientation_deg = rotation_angle_deg(found.pose->R, truth.pose.R);
    const double true_dist = truth.pose.t.norm();
    e.distance_m = std::abs(found.pose->t.norm() - true_dist);
    e.distance_percent = 100 * e.distance_m / true_dist;
  } else {
    e.orientation_deg = e.distance_m = e.distance_percent = std::numeric_limits<double>::quiet_NaN();
  }
  return e;
}

}  // namespace tagbench::bench
