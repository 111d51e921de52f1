// Fuzz target: the detector (tagbench::Detector) on arbitrary images.
//
// Input layout (fuzz_util.hpp's Reader; missing bytes read as 0):
//   u8 options   bits 0-2 pixel type (kTypes), 3 half resolution, 4-5 family set, 6-7 max hamming
//   u8 more      bit 0 camera (+ tag size), 1 distortion, 2 decode blur, 3 seg blur sigma 0 (none),
//                4 workspace check, 5 trace, 6 tiny max_pixels (the refusal path)
//   u16 width, u16 height   each up to kMaxSide (so 0, 1 and very thin images are all reachable);
//                the area is capped at kMaxArea by shrinking the height
//   camera: 4 x f32 fx, fy, cx, cy and f32 tag size; distortion: 5 x f32 (any bits: NaN, inf, huge)
//   the pixels, raw in the type's layout, repeated when the input is shorter than the image
// The options are "small default-ish": the paper's blur and thresholds, built-in families.
//
// What must hold: detect() either returns or throws std::invalid_argument, and it throws exactly
// for an empty image, an unsupported pixel type and an image over max_pixels; every detection has
// an id of its family, a hamming within max_hamming, a rotation 0..3 and finite geometry; a reused
// workspace gives the same detections as a fresh one.
#include <opencv2/core.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "detect/detector.hpp"
#include "detect/detector_opencv.hpp"
#include "fuzz_util.hpp"

namespace {

constexpr int kMaxSide = 1024;
constexpr long kMaxArea = 1 << 14;  // keeps one detection within milliseconds

// The depths and channel counts images arrive with (imdecode with ANYDEPTH | ANYCOLOR gives 8U,
// 16U and 32F, 1, 3 or 4 channels), plus two the detector must refuse.
constexpr std::array<int, 8> kTypes = {CV_8UC1, CV_16UC1, CV_8UC3, CV_8UC4, CV_32FC1, CV_16UC3, CV_8UC2, CV_64FC1};
bool supported(int type) { return type != CV_8UC2 && type != CV_64FC1; }

const std::array<std::vector<std::string>, 4> kFamilySets = {
    std::vector<std::string>{"36h11"}, {"16h5"}, {"25h9"}, {"36h11", "16h5"}};

// Building a detector loads its families; the few option sets without camera are kept.
const tagbench::Detector& cached(const tagbench::DetectorOptions& opt, const std::string& key) {
  static std::map<std::string, std::unique_ptr<tagbench::Detector>> cache;
  auto& d = cache[key];
  if (!d) d = std::make_unique<tagbench::Detector>(opt);
  return *d;
}

bool finite(const Eigen::Vector2d& v) { return std::isfinite(v.x()) && std::isfinite(v.y()); }

void check_detection(const tagbench::Detection& d, const tagbench::Detector& det) {
  const tagbench::TagFamily* fam = nullptr;
  for (const auto& f : det.families())
    if (f.name() == d.family) fam = &f;
  FUZZ_CHECK(fam != nullptr, "detection of an unknown family " + d.family);
  FUZZ_CHECK(d.id >= 0 && static_cast<std::size_t>(d.id) < fam->size(), "id " + std::to_string(d.id));
  FUZZ_CHECK(d.hamming >= 0 && d.hamming <= det.options().max_hamming, "hamming " + std::to_string(d.hamming));
  FUZZ_CHECK(d.rotation >= 0 && d.rotation <= 3, "rotation " + std::to_string(d.rotation));
  for (const auto& c : d.corners) FUZZ_CHECK(finite(c), "non-finite corner");
  FUZZ_CHECK(finite(d.center), "non-finite centre");
  FUZZ_CHECK(d.homography.allFinite(), "non-finite homography");
  FUZZ_CHECK(std::isfinite(d.decision_margin), "non-finite decision margin");
  // Absurd intrinsics or distortion (fx = 1e-30, a tag of 1e30 m, k1 = 1e20) may legitimately put t out of double range.
  const auto& o = det.options();
  const auto sane = [](double v, double lo, double hi) { return v >= lo && v <= hi; };
  const bool sane_camera = o.camera && sane(o.camera->fx, 1e-2, 1e6) && sane(o.camera->fy, 1e-2, 1e6) &&
                           sane(o.camera->cx, 0, 1e6) && sane(o.camera->cy, 0, 1e6) && sane(o.tag_size, 1e-4, 1e4);
  bool sane_distortion = true;
  if (o.distortion)
    for (const double k : *o.distortion) sane_distortion = sane_distortion && sane(k, -10, 10);
  for (const auto* p : {&d.pose, &d.pose_alternative})
    if (*p && sane_camera && sane_distortion) {
      FUZZ_CHECK((*p)->pose.R.allFinite() && (*p)->pose.t.allFinite(), "non-finite pose");
    }
}

bool same(const std::vector<tagbench::Detection>& a, const std::vector<tagbench::Detection>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].family != b[i].family || a[i].id != b[i].id || a[i].hamming != b[i].hamming ||
        a[i].rotation != b[i].rotation || a[i].homography != b[i].homography)
      return false;
    for (std::size_t k = 0; k < a[i].corners.size(); ++k)
      if (a[i].corners[k] != b[i].corners[k]) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool once = [] {
    cv::setNumThreads(1);  // OpenCV's conversions: no thread pool, reproducible runs
    return true;
  }();
  (void)once;

  fuzz::Reader in(data, size);
  const std::uint8_t o1 = in.u8(), o2 = in.u8();
  const int type = kTypes[o1 & 7];
  const int width = in.u16() % (kMaxSide + 1);
  int height = in.u16() % (kMaxSide + 1);
  if (width > 0 && static_cast<long>(width) * height > kMaxArea) height = static_cast<int>(kMaxArea / width);

  tagbench::DetectorOptions opt;
  opt.half_resolution = (o1 & 8) != 0;
  const int family_set = (o1 >> 4) & 3;
  opt.families = kFamilySets[static_cast<std::size_t>(family_set)];
  opt.max_hamming = (o1 >> 6) & 3;
  if (o2 & 4) opt.decode_sigma = 0.8;
  if (o2 & 8) opt.seg_sigma = 0;
  if (o2 & 64) opt.max_pixels = 1 + (o2 >> 7) * 15;  // 1 or 16 pixels
  std::string key = std::to_string(o1 & 0xf8) + "/" + std::to_string(o2 & (4 | 8 | 64 | 128));
  if (o2 & 1) {
    const float fx = in.f32(), fy = in.f32(), cx = in.f32(), cy = in.f32(), tag = in.f32();
    opt.camera = tagbench::CameraIntrinsics{fx, fy, cx, cy};
    opt.tag_size = tag;
    if (o2 & 2) {
      std::array<double, 5> k{};
      for (double& v : k) v = in.f32();
      opt.distortion = k;
    }
  }

  // Options with a camera come from the input's bytes: build that detector for this input only.
  std::unique_ptr<tagbench::Detector> own;
  const tagbench::Detector* det = nullptr;
  try {
    if (opt.camera) {
      own = std::make_unique<tagbench::Detector>(opt);
      det = own.get();
    } else {
      det = &cached(opt, key);
    }
  } catch (const std::invalid_argument&) {
    FUZZ_CHECK(opt.camera.has_value(), "the default-ish options were refused");
    return 0;  // camera, tag size or distortion out of range: refused, as documented
  }

  cv::Mat img;
  if (width > 0 && height > 0) {
    img.create(height, width, type);
    const std::size_t bytes = img.total() * img.elemSize();
    auto* dst = img.ptr<std::uint8_t>();  // create() allocates one continuous block
    const std::uint8_t* src = in.tail();
    const std::size_t n = in.left();
    for (std::size_t i = 0; i < bytes; ++i) dst[i] = n ? src[i % n] : 0;
  }

  const bool empty = img.empty();
  const bool too_big = !empty && static_cast<long long>(width) * height > opt.max_pixels;
  const bool should_throw = empty || too_big || !supported(type);
  std::vector<tagbench::Detection> found;
  try {
    tagbench::DetectorTrace trace;
    if (o2 & 16) {
      tagbench::DetectorWorkspace ws;
      found = detect(*det, img, ws, (o2 & 32) ? &trace : nullptr);
      const auto again = detect(*det, img, ws);
      FUZZ_CHECK(same(found, again), "a reused workspace changed the detections");
      const auto fresh = detect(*det, img);
      FUZZ_CHECK(same(found, fresh), "a workspace's detections differ from a fresh detection's");
    } else {
      found = detect(*det, img, (o2 & 32) ? &trace : nullptr);
    }
  } catch (const std::invalid_argument& e) {
    FUZZ_CHECK(should_throw, std::string("refused a valid image: ") + e.what());
    return 0;
  }
  FUZZ_CHECK(!should_throw, "accepted an empty, unsupported or oversized image");
  for (const auto& d : found) check_detection(d, *det);
  return 0;
}
