#pragma once
// The `realistic` image set (issue 17, part 3): frames that behave like real JPEG photographs of small
// tags, so that detectors can be compared and tuned where users judge them. Each frame is a pinhole
// camera image (default 800 x 600, f = 800 px) of several tags of one family (black squares 12-40 px
// across, random oblique poses, not overlapping, wholly in view) on a procedural cluttered ground
// (edges, corners, rectangles, text-like marks, grids, tag-like decoys, multi-scale texture, gradients),
// rendered projectively at `supersample` x the resolution and box-averaged (exact area average of the
// supersamples), lit unevenly, then put through a camera: defocus (Gaussian PSF), optional motion blur,
// shot and read noise, gamma, 8-bit quantization and JPEG (OpenCV/libjpeg, quality drawn per frame).
//
// A frame is fully determined by (settings, index): every random draw comes from splitmix64 seeded by
// (settings.seed, index), never from std:: distributions (whose outputs are library-defined), so frames
// are reproducible and can be made in any order or subset, on any thread.
//
// Conventions (README "Conventions"): pixel centres at integer coordinates; camera x right, y down, z
// forward; tag frame origin at the black square's centre, x to the printed right edge, y to the bottom
// edge, z into the tag; corners TL, TR, BR, BL of the black square.
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "detect/homography.hpp"
#include "detect/pose.hpp"

namespace tagbench::bench {

struct Range {
  double lo = 0, hi = 0;  // a per-frame (or per-tag) value is drawn uniformly in [lo, hi]
};

// Defaults are the calibrated set (README "The realistic image set": how close it comes to photographs).
struct RealisticSettings {
  std::uint64_t seed = 1;
  std::string family = "36h11";  // a built-in family; libapriltag and aruco know 16h5, 25h9, 36h10, 36h11
  int width = 800, height = 600;
  double focal_px = 800;         // fx = fy; principal point at the image centre ((w-1)/2, (h-1)/2)
  int min_tags = 4, max_tags = 10;
  Range black_square_px{12, 40};  // sqrt of the projected black square's area, drawn uniformly per tag
  double max_tilt_deg = 65;       // angle between the tag's normal and the line of sight, uniform in [0, max]
  double tag_size_m = 0.05;       // edge of the black square (sets the distances; pixels do not depend on it)
  int supersample = 4;            // samples per pixel per axis (box-averaged down)
  // The camera. With degrade = false only the rendering, the lighting and 8-bit quantization are
  // applied (no blur, noise, gamma or JPEG): an ideal frame, for checking the geometry.
  bool degrade = true;
  Range blur_sigma_px{0.3, 1.4};   // defocus: Gaussian PSF sigma, pixels, per frame
  // A lens's defocus instead: a uniform disk of radius 2 x the drawn sigma (the same second moment),
  // with its sharper edges and wider reach (bench/experiments/photo_conditions.cpp; the set: off).
  bool disk_defocus = false;
  Range motion_blur_px{0, 1.5};    // motion blur: length of a line PSF, pixels (0 = none), per frame
  Range full_well_e{800, 4000};    // electrons at the exposure's white: shot noise, per frame
  Range read_noise_e{3, 12};       // read noise sigma, electrons, per frame
  Range jpeg_quality{70, 90};      // libjpeg quality, integer, per frame
  double gamma = 2.2;              // encoding gamma (value = linear^(1/gamma))
  // The camera's sharpening (an unsharp mask on the gamma-encoded image, as phone and compact-camera
  // processing applies before JPEG): value += amount x (value - Gaussian(value, sharpen_sigma_px)).
  Range sharpen_amount{0, 0};      // per frame
  double sharpen_sigma_px = 1.0;
  // The scene's light.
  Range exposure{0.55, 1.0};        // linear value of a fully lit white surface, per frame
  Range ink_reflectance{0.04, 0.5};    // the tag's black, per tag (worn, glossy, grey prints, glare)
  Range paper_reflectance{0.55, 0.9};  // the tag's white, per tag
  Range face_light{0.25, 1.0};         // light on the tag's face relative to the brightest ground (shade .. sun), per tag
  double unevenness = 0.5;             // depth of the smooth light variation across the frame, 0..1
  double shadow_probability = 0.6;     // a hard-edged shadow (penumbra ~2 px) across part of the frame
};

struct RealisticTag {
  std::string family;
  int id = 0;                     // distinct within a frame
  Corners corners;                // black square, TL, TR, BR, BL, pixels (centres at integers)
  double black_square_px = 0;     // sqrt of the projected black square's area
  double mean_edge_px = 0;        // mean of its four projected edges
  double tilt_deg = 0;            // angle between the tag's normal and the line of sight to its centre
  double tilt_axis_deg = 0, roll_deg = 0;  // as raytrace's ViewSpec
  Pose pose;                      // tag -> camera, metres
  double tag_size_m = 0;          // black square edge
  double ink = 0, paper = 0, light = 0;  // reflectances of black and white, light on the face
};

// What the camera did to the frame (all zero / 0 quality when settings.degrade is false).
struct CameraDegradation {
  double blur_sigma_px = 0;
  double motion_blur_px = 0, motion_angle_deg = 0;
  double full_well_e = 0, read_noise_e = 0;
  double sharpen_amount = 0;
  int jpeg_quality = 0;           // 0: no JPEG
  double gamma = 1;
  double exposure = 0;
  bool shadow = false;
};

struct RealisticFrame {
  int index = 0;
  std::uint64_t frame_seed = 0;   // derived from (settings.seed, index); every draw of the frame comes from it
  cv::Mat image;                  // 8-bit gray, width x height: what the detectors get (the decoded JPEG)
  std::vector<std::uint8_t> jpeg; // the encoded JPEG (empty when not degraded); image == imdecode(jpeg)
  CameraIntrinsics camera;
  std::vector<RealisticTag> tags;
  CameraDegradation degradation;
};

// Throws std::invalid_argument with a one-line message for settings out of range (an unknown family,
// sizes or counts not positive, lo > hi, a tilt outside [0, 85], tags that cannot fit, quality outside
// 1..100, ...).
void check_settings(const RealisticSettings& settings);

// The frame `index` (>= 0) of the set. Fully determined by (settings, index).
RealisticFrame make_realistic_frame(const RealisticSettings& settings, int index);

// The frame's ground truth and degradations as one JSON document (export, tests).
std::string frame_truth_json(const RealisticSettings& settings, const RealisticFrame& frame);

}  // namespace tagbench::bench
