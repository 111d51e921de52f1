// The realistic image set (realistic_set.hpp): tags placed and rendered projectively on the ground.
#include "realistic/realistic_set.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>

#include "codes/families.hpp"
#include "codes/tag_layout.hpp"
#include "raytrace/render.hpp"
#include "realistic/realistic_parts.hpp"
#include "tools/json.hpp"

namespace tagbench::bench {

namespace rp = realistic_parts;

namespace {

void check_range(const char* name, const Range& r, double lo, double hi) {
  if (!(std::isfinite(r.lo) && std::isfinite(r.hi) && r.lo <= r.hi && r.lo >= lo && r.hi <= hi))
    throw std::invalid_argument(std::string("realistic set: ") + name + " must satisfy " + json_number(lo) +
                                " <= lo <= hi <= " + json_number(hi) + " (got " + json_number(r.lo) + ".." +
                                json_number(r.hi) + ")");
}

double polygon_area(const std::vector<Eigen::Vector2d>& p) {
  double a = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto& u = p[i];
    const auto& w = p[(i + 1) % p.size()];
    a += u.x() * w.y() - w.x() * u.y();
  }
  return std::abs(a) / 2;
}

Eigen::Vector2d project(const Pose& pose, const CameraIntrinsics& K, const Eigen::Vector3d& p) {
  const Eigen::Vector3d c = pose.R * p + pose.t;
  return {K.fx * c.x() / c.z() + K.cx, K.fy * c.y() / c.z() + K.cy};
}

// Where a tag will be, before rendering.
struct Placement {
  RealisticTag tag;
  std::vector<Eigen::Vector2d> plate;  // the plate's corners in the image (the tag's surround)
  double plate_half_m = 0;             // half the plate's edge, metres
  double plate_reflectance = 0;
  Eigen::Vector2d centre;
  double radius = 0;                   // of a circle round the plate
};

std::optional<Placement> place_tag(const RealisticSettings& st, const CameraIntrinsics& K, int n_cells, rp::Draws& dr) {
  Placement p;
  RealisticTag& t = p.tag;
  const double target = dr.uniform(st.black_square_px);
  t.tilt_deg = dr.uniform(0, st.max_tilt_deg);
  t.tilt_axis_deg = dr.uniform(0, 360);
  t.roll_deg = dr.uniform(0, 360);
  const Eigen::Vector2d pixel(dr.uniform(0, st.width - 1), dr.uniform(0, st.height - 1));
  const double margin_cells = dr.uniform(0.3, 3.0);  // the cube face (or card) round the printed tag
  p.plate_reflectance = dr.uniform(0.15, 0.9);
  t.ink = dr.uniform(st.ink_reflectance);
  t.paper = dr.uniform(st.paper_reflectance);
  t.light = dr.uniform(st.face_light);
  t.tag_size_m = st.tag_size_m;
  // Distance for the target sqrt(area): start from the face-on size, then correct twice (perspective
  // makes area ~ 1 / z^2 only nearly).
  double z = K.fx * st.tag_size_m / target / std::sqrt(std::cos(t.tilt_deg * M_PI / 180));
  for (int it = 0; it < 3; ++it) {
    ViewSpec v;
    v.distance = z;
    v.phi_deg = t.tilt_deg;
    v.tilt_axis_deg = t.tilt_axis_deg;
    v.roll_deg = t.roll_deg;
    v.pixel = pixel;
    t.pose = view_pose(v, K);
    t.corners = project_tag_corners(t.pose, K, st.tag_size_m);
    const std::vector<Eigen::Vector2d> sq(t.corners.begin(), t.corners.end());
    t.black_square_px = std::sqrt(polygon_area(sq));
    z *= t.black_square_px / target;
  }
  double edges = 0;
  for (std::size_t i = 0; i < 4; ++i) edges += (t.corners[(i + 1) % 4] - t.corners[i]).norm();
  t.mean_edge_px = edges / 4;
  // The plate: the printed tag (n cells; the black square is n - 2) plus the margin.
  p.plate_half_m = st.tag_size_m / 2 * (n_cells + 2 * margin_cells) / (n_cells - 2);
  const double h = p.plate_half_m;
  p.centre.setZero();
  for (const auto& [sx, sy] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
    const Eigen::Vector3d q(sx * h, sy * h, 0);
    if ((t.pose.R * q + t.pose.t).z() <= 0) return std::nullopt;
    p.plate.push_back(project(t.pose, K, q));
    const auto& c = p.plate.back();
    if (c.x() < 2 || c.y() < 2 || c.x() > st.width - 3 || c.y() > st.height - 3) return std::nullopt;  // wholly in view
    p.centre += c / 4;
  }
  for (const auto& c : p.plate) p.radius = std::max(p.radius, (c - p.centre).norm());
  return p;
}

// Writes the tag and its plate into the supersampled image `big` (reflectance x light on the face).
void render_tag(cv::Mat& big, int ss, const Placement& p, const TagCells& cells, const CameraIntrinsics& K) {
  const RealisticTag& t = p.tag;
  // Image point (pixel centres at integers) -> tag plane (metres): the inverse of K [r1 r2 t].
  Eigen::Matrix3d H;
  H.col(0) = t.pose.R.col(0);
  H.col(1) = t.pose.R.col(1);
  H.col(2) = t.pose.t;
  Eigen::Matrix3d Km;
  Km << K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1;
  const Eigen::Matrix3d Hinv = (Km * H).inverse();
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (const auto& c : p.plate) {
    x0 = std::min(x0, c.x());
    y0 = std::min(y0, c.y());
    x1 = std::max(x1, c.x());
    y1 = std::max(y1, c.y());
  }
  const int u0 = std::max(0, static_cast<int>(std::floor((x0 + 0.5) * ss)) - 1);
  const int v0 = std::max(0, static_cast<int>(std::floor((y0 + 0.5) * ss)) - 1);
  const int u1 = std::min(big.cols - 1, static_cast<int>(std::ceil((x1 + 0.5) * ss)) + 1);
  const int v1 = std::min(big.rows - 1, static_cast<int>(std::ceil((y1 + 0.5) * ss)) + 1);
  const double cell_m = t.tag_size_m / (cells.n - 2), half_tag = cells.n / 2.0;
  const auto ink = static_cast<float>(t.ink * t.light), paper = static_cast<float>(t.paper * t.light);
  const auto plate = static_cast<float>(p.plate_reflectance * t.light);
  for (int v = v0; v <= v1; ++v) {
    float* row = big.ptr<float>(v);
    const double y = (v + 0.5) / ss - 0.5;
    for (int u = u0; u <= u1; ++u) {
      const double x = (u + 0.5) / ss - 0.5;
      const Eigen::Vector3d q = Hinv * Eigen::Vector3d(x, y, 1);
      const double X = q.x() / q.z(), Y = q.y() / q.z();
      if (std::abs(X) > p.plate_half_m || std::abs(Y) > p.plate_half_m) continue;
      const double cx = X / cell_m + half_tag, cy = Y / cell_m + half_tag;
      if (cx >= 0 && cy >= 0 && cx < cells.n && cy < cells.n)
        row[u] = cells.at(static_cast<int>(cy), static_cast<int>(cx)) ? paper : ink;
      else
        row[u] = plate;
    }
  }
}

}  // namespace

void check_settings(const RealisticSettings& s) {
  const TagFamily& fam = builtin_family(s.family);  // throws for an unknown name
  const auto bad = [](const std::string& m) { throw std::invalid_argument("realistic set: " + m); };
  if (s.width < 64 || s.height < 64 || s.width > 8192 || s.height > 8192) bad("width and height must be in 64..8192");
  if (!(s.focal_px > 0) || !std::isfinite(s.focal_px)) bad("focal_px must be > 0");
  if (s.min_tags < 1 || s.max_tags < s.min_tags || s.max_tags > 100) bad("need 1 <= min_tags <= max_tags <= 100");
  if (static_cast<std::size_t>(s.max_tags) > fam.size()) bad("max_tags exceeds the family's size (ids are distinct)");
  check_range("black_square_px", s.black_square_px, 4, std::min(s.width, s.height) / 4.0);
  if (!(s.max_tilt_deg >= 0 && s.max_tilt_deg <= 85)) bad("max_tilt_deg must be in [0, 85]");
  if (!(s.tag_size_m > 0) || !std::isfinite(s.tag_size_m)) bad("tag_size_m must be > 0");
  if (s.supersample < 1 || s.supersample > 8) bad("supersample must be in 1..8");
  check_range("blur_sigma_px", s.blur_sigma_px, 0, 10);
  check_range("motion_blur_px", s.motion_blur_px, 0, 20);
  check_range("full_well_e", s.full_well_e, 1, 1e7);
  check_range("read_noise_e", s.read_noise_e, 0, 1e4);
  check_range("jpeg_quality", s.jpeg_quality, 1, 100);
  if (!(s.gamma >= 1 && s.gamma <= 4)) bad("gamma must be in [1, 4]");
  check_range("sharpen_amount", s.sharpen_amount, 0, 10);
  if (!(s.sharpen_sigma_px > 0 && s.sharpen_sigma_px <= 10)) bad("sharpen_sigma_px must be in (0, 10]");
  check_range("exposure", s.exposure, 0.01, 1);
  check_range("ink_reflectance", s.ink_reflectance, 0, 1);
  check_range("paper_reflectance", s.paper_reflectance, 0, 1);
  check_range("face_light", s.face_light, 0, 1);
  if (!(s.unevenness >= 0 && s.unevenness <= 1)) bad("unevenness must be in [0, 1]");
  if (!(s.shadow_probability >= 0 && s.shadow_probability <= 1)) bad("shadow_probability must be in [0, 1]");
}

RealisticFrame make_realistic_frame(const RealisticSettings& st, int index) {
  check_settings(st);
  if (index < 0) throw std::invalid_argument("realistic set: frame index must be >= 0");
  const TagFamily& fam = builtin_family(st.family);
  RealisticFrame f;
  f.index = index;
  f.frame_seed = rp::frame_seed(st.seed, index);
  f.camera = CameraIntrinsics{st.focal_px, st.focal_px, (st.width - 1) / 2.0, (st.height - 1) / 2.0};
  // Independent streams per stage, so that changing one stage's draws leaves the others' frames alone.
  rp::Draws tags_dr{f.frame_seed ^ 0x1111}, ground_dr{f.frame_seed ^ 0x2222}, light_dr{f.frame_seed ^ 0x3333},
      cam_dr{f.frame_seed ^ 0x4444};
  const int n_cells = tag_cells(fam, 0).n;
  const int want = st.min_tags + tags_dr.below(st.max_tags - st.min_tags + 1);
  std::vector<Placement> placed;
  for (int attempt = 0; static_cast<int>(placed.size()) < want && attempt < 400; ++attempt) {
    auto p = place_tag(st, f.camera, n_cells, tags_dr);
    if (!p) continue;
    bool overlap = false;
    for (const auto& q : placed) overlap = overlap || (p->centre - q.centre).norm() < p->radius + q.radius + 2;
    if (overlap) continue;
    p->tag.family = st.family;
    for (;;) {  // distinct ids, so a detection's id names one tag
      p->tag.id = tags_dr.below(static_cast<int>(fam.size()));
      bool used = false;
      for (const auto& q : placed) used = used || q.tag.id == p->tag.id;
      if (!used) break;
    }
    placed.push_back(std::move(*p));
  }
  const int ss = st.supersample;
  cv::Mat big = rp::make_ground(st.width, st.height, ss, ground_dr);
  for (const auto& p : placed) {
    render_tag(big, ss, p, tag_cells(fam, p.tag.id), f.camera);
    f.tags.push_back(p.tag);
  }
  cv::Mat linear;
  cv::resize(big, linear, cv::Size(st.width, st.height), 0, 0, cv::INTER_AREA);  // integer factor: box average
  f.degradation.exposure = light_dr.uniform(st.exposure);
  const cv::Mat light = rp::make_light(st.width, st.height, st.unevenness, st.shadow_probability, light_dr, f.degradation.shadow);
  linear = linear.mul(light) * f.degradation.exposure;
  f.image = rp::apply_camera(linear, st, cam_dr, f.degradation, f.jpeg);
  return f;
}

std::string frame_truth_json(const RealisticSettings& st, const RealisticFrame& f) {
  const auto pt = [](const Eigen::Vector2d& p) {
    std::string s = "[";  // appended, not "[" + ...: GCC 12 warns (-Wrestrict) on that falsely
    s += json_number(p.x());
    s += ", ";
    s += json_number(p.y());
    s += "]";
    return s;
  };
  const CameraDegradation& d = f.degradation;
  std::string j = "{\"set\": \"realistic\", \"seed\": " + std::to_string(st.seed) + ", \"index\": " +
                  std::to_string(f.index) + ", \"frame_seed\": " + std::to_string(f.frame_seed) +
                  ",\n \"width\": " + std::to_string(f.image.cols) + ", \"height\": " + std::to_string(f.image.rows) +
                  ", \"camera\": {\"fx\": " + json_number(f.camera.fx) + ", \"fy\": " + json_number(f.camera.fy) +
                  ", \"cx\": " + json_number(f.camera.cx) + ", \"cy\": " + json_number(f.camera.cy) +
                  ", \"pixels\": \"centres at integer coordinates\"}" +
                  ",\n \"degradation\": {\"degraded\": " + (st.degrade ? "true" : "false") +
                  ", \"blur_sigma_px\": " + json_number(d.blur_sigma_px) +
                  (st.degrade && st.disk_defocus ? ", \"defocus\": \"disk\"" : "") + ", \"motion_blur_px\": " +
                  json_number(d.motion_blur_px) + ", \"motion_angle_deg\": " + json_number(d.motion_angle_deg) +
                  ", \"full_well_e\": " + json_number(d.full_well_e) + ", \"read_noise_e\": " +
                  json_number(d.read_noise_e) + ", \"gamma\": " + json_number(d.gamma) + ", \"sharpen_amount\": " + json_number(d.sharpen_amount) + ", \"jpeg_quality\": " +
                  std::to_string(d.jpeg_quality) + ", \"exposure\": " + json_number(d.exposure) +
                  ", \"shadow\": " + (d.shadow ? "true" : "false") + "},\n \"tags\": [";
  for (std::size_t i = 0; i < f.tags.size(); ++i) {
    const RealisticTag& t = f.tags[i];
    j += std::string(i ? "," : "") + "\n  {\"family\": " + json_string(t.family) + ", \"id\": " + std::to_string(t.id) +
         ", \"corners\": [" + pt(t.corners[0]) + ", " + pt(t.corners[1]) + ", " + pt(t.corners[2]) + ", " +
         pt(t.corners[3]) + "], \"black_square_px\": " + json_number(t.black_square_px) + ", \"mean_edge_px\": " +
         json_number(t.mean_edge_px) + ", \"tilt_deg\": " + json_number(t.tilt_deg) + ", \"tilt_axis_deg\": " +
         json_number(t.tilt_axis_deg) + ", \"roll_deg\": " + json_number(t.roll_deg) + ", \"tag_size_m\": " +
         json_number(t.tag_size_m) + ", \"R\": [";
    for (int r = 0; r < 3; ++r)
      j += std::string(r ? ", " : "") + "[" + json_number(t.pose.R(r, 0)) + ", " + json_number(t.pose.R(r, 1)) + ", " +
           json_number(t.pose.R(r, 2)) + "]";
    j += "], \"t\": [" + json_number(t.pose.t.x()) + ", " + json_number(t.pose.t.y()) + ", " +
         json_number(t.pose.t.z()) + "], \"ink\": " + json_number(t.ink) + ", \"paper\": " + json_number(t.paper) +
         ", \"light\": " + json_number(t.light) + "}";
  }
  j += f.tags.empty() ? "]}\n" : "\n ]}\n";
  return j;
}

}  // namespace tagbench::bench
