// Frames' geometry and scenes (render.hpp): the render camera, the scene templates, a view's pose and
// a frame's ground truth; and what names a frame in the cache and what it puts into the batch scene
// (render_detail.hpp), which render_frames (render_frames.cpp) renders.
#include "raytrace/render.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>

#include <Eigen/Dense>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "raytrace/render_detail.hpp"
#include "tools/format.hpp"
#include "tools/hash.hpp"

namespace tagbench::bench {

std::filesystem::path default_render_cache() {
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return std::filesystem::path(x) / "tagbench" / "raytrace";
  if (const char* h = std::getenv("HOME"); h && *h) return std::filesystem::path(h) / ".cache" / "tagbench" / "raytrace";
  return std::filesystem::temp_directory_path() / "tagbench-raytrace-cache";
}

extern const char kScene_plain[];
extern const char kScene_realistic[];

using namespace render_detail;

namespace {

namespace fs = std::filesystem;

std::string hex64(std::uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

std::string cells_text(const TagCells& c) {
  std::string s = std::to_string(c.n) + ":";
  for (const auto w : c.white) s += w ? '1' : '0';
  return s;
}

bool finite_pose(const Pose& p) { return p.R.allFinite() && p.t.allFinite(); }

const TagFamily& family_for(std::map<std::string, TagFamily>& cache, const std::string& name) {
  auto it = cache.find(name);
  if (it == cache.end()) it = cache.emplace(name, load_family(name)).first;
  return it->second;
}

}  // namespace

CameraIntrinsics render_camera() {
  return {kRenderFocalPx, kRenderFocalPx, (kRenderWidth - 1) / 2.0, (kRenderHeight - 1) / 2.0};
}

const std::string& scene_template(SceneKind kind) {
  static const std::string plain = kScene_plain, realistic = kScene_realistic;
  return kind == SceneKind::kPlain ? plain : realistic;
}

const char* scene_name(SceneKind kind) { return kind == SceneKind::kPlain ? "plain" : "realistic"; }

Pose view_pose(const ViewSpec& v, const CameraIntrinsics& K) {
  if (!(v.distance > 0) || !std::isfinite(v.distance))
    throw std::invalid_argument("view distance must be > 0 (got " + exact_number(v.distance) + ")");
  if (!(v.phi_deg >= 0 && v.phi_deg < 90))
    throw std::invalid_argument("view angle phi must be in [0, 90) degrees (got " + exact_number(v.phi_deg) + ")");
  const double deg = M_PI / 180;
  const Eigen::Vector3d d =
      Eigen::Vector3d((v.pixel.x() - K.cx) / K.fx, (v.pixel.y() - K.cy) / K.fy, 1.0).normalized();
  // Face-on frame: z along the viewing ray, x as close to the camera's x as possible.
  const Eigen::Vector3d x = (Eigen::Vector3d::UnitX() - d.x() * d).normalized();
  Eigen::Matrix3d R0;
  R0.col(0) = x;
  R0.col(1) = d.cross(x);
  R0.col(2) = d;
  const Eigen::Vector3d axis(std::cos(v.tilt_axis_deg * deg), std::sin(v.tilt_axis_deg * deg), 0);
  Pose p;
  p.R = R0 * Eigen::AngleAxisd(v.roll_deg * deg, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
        Eigen::AngleAxisd(v.phi_deg * deg, axis).toRotationMatrix();
  p.t = v.distance * d;
  return p;
}

GroundTruth ground_truth(const FramePose& f) {
  GroundTruth g;
  g.pose = f.pose;
  g.corners = project_tag_corners(f.pose, render_camera(), f.tag_size);
  double sum = 0;
  for (int i = 0; i < 4; ++i) sum += (g.corners[static_cast<std::size_t>((i + 1) % 4)] - g.corners[static_cast<std::size_t>(i)]).norm();
  g.black_square_px = sum / 4;
  return g;
}

cv::Mat read_frame_gray(const fs::path& png) {
  const cv::Mat m = cv::imread(png.string(), cv::IMREAD_GRAYSCALE);
  if (m.empty()) throw std::runtime_error(png.string() + ": not a readable image");
  return m;
}

namespace render_detail {

// Cache keys: 64-bit FNV-1a as 16 hex digits (for 10^5 frames the chance of any collision is ~3e-10).
std::string key_of(std::string_view text) { return hex64(fnv1a64(text)); }

FrameScene frame_scene(const FramePose& f, const TagCells& cells) {
  return {"tag-" + key_of(cells_text(cells)) + ".png", f.tag_size * cells.n / (cells.n - 2)};
}

std::string frame_case(int number, const FramePose& f, const FrameScene& scene) {
  const Eigen::Matrix3d S = Eigen::Vector3d(1, -1, 1).asDiagonal();
  const Eigen::Matrix3d Rp = S * f.pose.R * S;
  const Eigen::Vector3d tp = S * f.pose.t;
  std::string m;  // `matrix` takes row vectors: the columns of R_pov, then t_pov
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) m += exact_number(Rp(r, c)) + ", ";
  m += exact_number(tp.x()) + ", " + exact_number(tp.y()) + ", " + exact_number(tp.z());
  std::string s = "#case (" + std::to_string(number) + ")\n";
  s += "  #declare TagPng = \"" + scene.tag_png + "\";\n";
  s += "  #declare TagWidth = " + exact_number(scene.tag_width) + ";\n";
  s += "  #declare TagSize = " + exact_number(f.tag_size) + ";\n";
  s += "  #declare TagPosition = <" + exact_number(tp.x()) + ", " + exact_number(tp.y()) + ", " + exact_number(tp.z()) +
       ">;\n";
  s += "  #declare TagPose = transform { matrix <" + m + "> }\n";
  if (!f.extra_sdl.empty()) s += f.extra_sdl + "\n";
  s += "  #break\n";
  return s;
}

// Everything that determines a frame's pixels, as text: the render flags, the template, the tag's
// cells, and the frame's #case as it goes into the scene (pose, sizes, extra SDL), numbered 0.
std::string frame_key_text(const FramePose& f, const std::string& template_key, const TagCells& cells) {
  std::string s = "tagbench-raytrace-frame 1\nflags";
  for (const char* q : kRenderFlags) s += std::string(" ") + q;
  s += "\ntemplate " + template_key + "\nfamily " + f.family + "\nid " + std::to_string(f.id) + "\ncells " +
       cells_text(cells) + "\n" + frame_case(0, f, frame_scene(f, cells));
  return s;
}

void check_frame(const FramePose& f, std::size_t index) {
  const std::string where = "frame " + std::to_string(index) + ": ";
  if (!(f.tag_size > 0) || !std::isfinite(f.tag_size))
    throw std::invalid_argument(where + "tag size must be > 0 (got " + exact_number(f.tag_size) + ")");
  if (!finite_pose(f.pose)) throw std::invalid_argument(where + "the pose is not finite");
  if (!(f.pose.R.transpose() * f.pose.R).isApprox(Eigen::Matrix3d::Identity(), 1e-6) || f.pose.R.determinant() < 0)
    throw std::invalid_argument(where + "R is not a rotation");
  if (!(f.pose.t.z() > 0)) throw std::invalid_argument(where + "the tag is not in front of the camera (t.z <= 0)");
}

TagCells cells_for(std::map<std::string, TagFamily>& families, const FramePose& f, std::size_t index) {
  try {
    return tag_cells(family_for(families, f.family), f.id);
  } catch (const std::out_of_range& e) {
    throw std::invalid_argument("frame " + std::to_string(index) + ": " + e.what());
  }
}

}  // namespace render_detail

std::string frame_cache_key(const FramePose& frame, const std::string& scene_template) {
  std::map<std::string, TagFamily> families;
  return key_of(frame_key_text(frame, key_of(scene_template), cells_for(families, frame, 0)));
}

}  // namespace tagbench::bench
