// The Python module `tagbench`: the detector over numpy arrays (<tagbench/detector.hpp>), without
// copying the image: detect() wraps the array's buffer in an ImageU8View and releases the GIL while
// it runs, so Python threads detect in parallel. Conventions are the C++ API's (corners TL, TR, BR,
// BL of the printed tag; pixel centres at integer coordinates; poses in metres, camera x right,
// y down, z forward). Errors: bad options and images raise ValueError with the library's one-line
// message (pybind11 maps std::invalid_argument to ValueError).
#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include <tagbench/detector.hpp>
#include <tagbench/version.hpp>

namespace py = pybind11;

namespace tagbench::python {
namespace {

template <int R, int C>
py::array_t<double> to_numpy(const Eigen::Matrix<double, R, C>& m) {
  std::vector<py::ssize_t> shape = C == 1 ? std::vector<py::ssize_t>{R} : std::vector<py::ssize_t>{R, C};
  py::array_t<double> out(shape);
  double* p = out.mutable_data();
  for (int r = 0; r < R; ++r)
    for (int c = 0; c < C; ++c) p[r * C + c] = m(r, c);
  return out;
}

py::array_t<double> corners_array(const Corners& corners) {
  py::array_t<double> out({4, 2});
  auto a = out.mutable_unchecked<2>();
  for (int i = 0; i < 4; ++i) {
    a(i, 0) = corners[static_cast<std::size_t>(i)].x();
    a(i, 1) = corners[static_cast<std::size_t>(i)].y();
  }
  return out;
}

// The profiles by name (DetectorOptions::named_profile): "default", "thorough", "paper".
DetectorOptions profile_options(const std::string& profile) {
  if (auto o = DetectorOptions::named_profile(profile)) return *o;
  throw std::invalid_argument("profile = '" + profile + "': unknown (known: default, thorough, paper)");
}

DetectorOptions make_options(const std::vector<std::string>& families, const std::optional<int>& max_hamming, double min_decision_margin,
                             const std::optional<std::array<double, 4>>& camera,
                             const std::optional<std::array<double, 5>>& distortion, const std::optional<double>& tag_size,
                             bool half_resolution, const std::string& profile, double input_gamma) {
  DetectorOptions o = profile_options(profile);
  o.families = families;
  if (max_hamming) {  // as `tagbench detect --max-hamming K`: K bits for every family
    o.max_hamming = *max_hamming;
    o.hamming_by_family = false;
  }
  o.min_decision_margin = min_decision_margin;
  // As `tagbench detect`: a pose needs both, and either alone is a mistake worth naming.
  if (camera && !tag_size) throw std::invalid_argument("camera: poses need tag_size too (the black square's edge, metres)");
  if (tag_size && !camera) throw std::invalid_argument("tag_size: given without camera=(fx, fy, cx, cy)");
  if (camera) o.camera = CameraIntrinsics{(*camera)[0], (*camera)[1], (*camera)[2], (*camera)[3]};
  o.distortion = distortion;
  if (tag_size) o.tag_size = *tag_size;
  o.half_resolution = half_resolution;
  o.input_gamma = input_gamma;
  return o;  // Detector's constructor validates (DetectorOptions::validate)
}

// The array's buffer as an 8-bit view, not copied: 2-D uint8 with contiguous rows (column stride 1,
// any row stride: a C-contiguous array or a column slice of one).
ImageU8View view_of(const py::array& a) {
  if (a.ndim() != 2 || !py::isinstance<py::array_t<std::uint8_t>>(a) || a.dtype().kind() != 'u')
    throw std::invalid_argument("image: expected a 2-D uint8 (gray) array, got " + std::to_string(a.ndim()) +
                                "-D " + std::string(py::str(a.dtype())));
  if (a.size() == 0)  // the detector's own one-line error ("empty image")
    return ImageU8View{static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0)), static_cast<int>(a.shape(1)), nullptr};
  if (a.strides(1) != 1 || a.strides(0) < a.shape(1))
    throw std::invalid_argument("image: rows must be contiguous (column stride 1, row stride >= width; use "
                                "numpy.ascontiguousarray)");
  if (a.shape(0) > 0x7fffffff || a.shape(1) > 0x7fffffff)
    throw std::invalid_argument("image: dimensions over 2^31 - 1");
  if (a.strides(0) > 0x7fffffff)
    throw std::invalid_argument("image: a row stride over 2^31 - 1 bytes (copy the view: numpy.ascontiguousarray)");
  return ImageU8View{static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0)), static_cast<int>(a.strides(0)),
                     static_cast<const std::uint8_t*>(a.data())};
}

}  // namespace
}  // namespace tagbench::python

PYBIND11_MODULE(tagbench, m) {
  using namespace tagbench;
  using namespace tagbench::python;
  m.doc() = "tagbench: the AprilTag detector of the 2011 paper (E. Olson, ICRA 2011), tag families and poses.";
  m.attr("__version__") = TAGBENCH_VERSION_STRING;

  py::class_<PoseSolution>(m, "Pose", "A tag pose: X_cam = R X_tag + t (metres); camera x right, y down, z forward.")
      .def_property_readonly("R", [](const PoseSolution& p) { return to_numpy(p.pose.R); }, "3x3 rotation")
      .def_property_readonly("t", [](const PoseSolution& p) { return to_numpy(p.pose.t); }, "translation (3,), metres")
      .def_readonly("error", &PoseSolution::reprojection_rms_px, "RMS reprojection error of the corners, pixels")
      .def_readonly("pattern_correlation", &PoseSolution::pattern_correlation,
                    "correlation of the decoded pattern projected by this pose with the image (NaN: not judged)")
      .def("__repr__", [](const PoseSolution& p) {
        return "tagbench.Pose(t=[" + std::to_string(p.pose.t.x()) + ", " + std::to_string(p.pose.t.y()) + ", " +
               std::to_string(p.pose.t.z()) + "], error=" + std::to_string(p.reprojection_rms_px) + ")";
      });

  py::class_<Detection>(m, "Detection", "One detected tag.")
      .def_readonly("family", &Detection::family)
      .def_readonly("id", &Detection::id)
      .def_readonly("hamming", &Detection::hamming, "bits corrected")
      .def_readonly("rotation", &Detection::rotation, "clockwise quarter turns of the observed code")
      .def_readonly("decision_margin", &Detection::decision_margin, "0 = a bit on its threshold, 1 = every bit clear")
      .def_property_readonly("corners", [](const Detection& d) { return corners_array(d.corners); },
                             "4x2 pixels: the black square's corners TL, TR, BR, BL of the printed tag")
      .def_property_readonly("center", [](const Detection& d) { return to_numpy(d.center); }, "(2,) pixels")
      .def_property_readonly("homography", [](const Detection& d) { return to_numpy(d.homography); },
                             "3x3: tag square [-1,1]^2 (printed axes) -> pixels")
      .def_readonly("pose", &Detection::pose, "best Pose (with camera and tag_size), else None")
      .def_readonly("pose_alternative", &Detection::pose_alternative, "the planar ambiguity's other Pose, or None")
      .def_readonly("pose_ambiguous", &Detection::pose_ambiguous,
                    "True when the image could not tell pose from pose_alternative (either may be right)")
      .def("__repr__", [](const Detection& d) {
        return "tagbench.Detection(family='" + d.family + "', id=" + std::to_string(d.id) +
               ", hamming=" + std::to_string(d.hamming) + ", center=[" + std::to_string(d.center.x()) + ", " +
               std::to_string(d.center.y()) + "])";
      });

  py::class_<Detector>(m, "Detector",
                       "Detector(families=['36h11'], max_hamming=None, min_decision_margin=0, camera=None, "
                       "distortion=None, tag_size=None, half_resolution=False, profile='default', input_gamma=1). profile: 'default' "
                       "(DetectorOptions{}), 'thorough' (DetectorOptions::thorough(): the default with its quads from "
                       "straight edges found at full resolution and a coarse pass, more of the small faint tags for "
                       "about twice the time) or 'paper' "
                       "(DetectorOptions::paper(), the 2011 paper's detector). "
                       "max_hamming: None = the profile's bits (default: by family, 36h11 3, 25h9 2, 16h5 1; paper: 1), "
                       "K = K bits for every family. The "
                       "other keywords are set on top of the profile's options. camera: "
                       "(fx, fy, cx, cy) pixels; tag_size: the black square's edge, metres (poses need both); "
                       "distortion: OpenCV's (k1, k2, p1, p2, k3). input_gamma: the images' encoding gamma (1, the "
                       "default: the image as it is, linear cameras, renders, raw data; 2.2: camera JPEGs/PNGs, "
                       "sRGB-like, corners about 5 % nearer the truth), used to place a found tag's sides on "
                       "linear intensities; a wrong value costs more than the right one gains. ValueError names a bad option.")
      .def(py::init([](const std::vector<std::string>& families, const std::optional<int>& max_hamming,
                       double min_decision_margin, const std::optional<std::array<double, 4>>& camera,
                       const std::optional<std::array<double, 5>>& distortion, const std::optional<double>& tag_size,
                       bool half_resolution, const std::string& profile, double input_gamma) {
             return Detector(make_options(families, max_hamming, min_decision_margin, camera, distortion, tag_size,
                                          half_resolution, profile, input_gamma));
           }),
           py::kw_only(), py::arg("families") = std::vector<std::string>{"36h11"}, py::arg("max_hamming") = py::none(),
           py::arg("min_decision_margin") = 0.0, py::arg("camera") = py::none(), py::arg("distortion") = py::none(),
           py::arg("tag_size") = py::none(), py::arg("half_resolution") = false, py::arg("profile") = "default",
           py::arg("input_gamma") = 1.0)
      .def(
          "detect",
          [](const Detector& detector, const py::array& image) {
            const ImageU8View view = view_of(image);  // `image` keeps the buffer alive during the call
            py::gil_scoped_release release;
            return detector.detect(view);
          },
          py::arg("image"),
          "Detections in a 2-D uint8 gray array (not copied; rows contiguous). Releases the GIL: threads "
          "detect in parallel. ValueError for an empty image, one over the pixel limit, or a wrong array.")
      .def_property_readonly("families", [](const Detector& d) { return d.options().families; })
      .def_property_readonly("max_hamming", [](const Detector& d) { return d.options().max_hamming; })
      .def_property_readonly("hamming_by_family", [](const Detector& d) { return d.options().hamming_by_family; },
                             "True: a family corrects at most min(max_hamming, (h - 1) / 3) bits");

  bind_families(m);
}
