#pragma once
// <tagbench/detector.hpp>: the AprilTag detector, in three profiles: the 2011 paper's (E. Olson, ICRA 2011;
// DetectorOptions::paper()), the default profile (DetectorOptions{}) and the thorough profile
// (DetectorOptions::thorough(): the default with its quads from straight edges found at full
// resolution and a coarse pass, for small faint tags, at about twice the time).
//
// What a user needs, and nothing of OpenCV (cv::Mat input: <tagbench/opencv.hpp>):
//   tagbench::DetectorOptions  settings, each with its documented default; the defaults are the
//                              default profile, DetectorOptions::paper() the 2011 paper's detector,
//                              DetectorOptions::thorough() the default with the line quads;
//                              validate() names the first bad field in one line
//   tagbench::Detector         built once from the options (loads the families, validates), then
//                              detect(image) any number of times
//   tagbench::ImageU8View      a caller-owned 8-bit gray buffer {width, height, stride, data}, not copied
//   tagbench::ImageF           a float gray image in [0, 1]
//   tagbench::Detection        family, id, hamming, rotation, decision_margin, corners, center,
//                              homography, pose and pose_alternative (with a camera and a tag size)
//   tagbench::DetectorWorkspace per-thread buffers reused from frame to frame
//
//   tagbench::DetectorOptions opt;            // default profile: families {"36h11"}, max_hamming 3 (by family), ...
//   opt.camera = tagbench::CameraIntrinsics{fx, fy, cx, cy};
//   opt.tag_size = 0.166;                     // metres, the black square's edge
//   const tagbench::Detector detector(opt);   // throws std::invalid_argument on a bad option
//   tagbench::DetectorWorkspace ws;           // one per thread
//   for (const tagbench::Detection& d : detector.detect(tagbench::ImageU8View{w, h, stride, pixels}, ws)) ...
//
// Units and conventions:
//   - image coordinates in pixels, pixel centres at integer coordinates (pixel (x, y) covers
//     [x - 0.5, x + 0.5] x [y - 0.5, y + 0.5]); x right, y down;
//   - Detection::corners: the black square's outer corners in the order top-left, top-right,
//     bottom-right, bottom-left of the printed tag, wherever the tag is turned in the image;
//   - Detection::homography maps the tag square [-1, 1]^2 (printed axes: x right, y down) to pixels;
//   - camera frame x right, y down, z forward; tag frame origin at the tag centre, x toward the
//     printed right edge, y toward the bottom edge, z into the tag; a pose (R, t) maps tag points
//     into the camera frame, X_cam = R X_tag + t, in metres; tag size = the black square's edge;
//   - decision_margin in [0, 1]: 0 = some bit on its threshold, 1 = every bit clear.
//
// Thread safety: a Detector is immutable after construction; detect() is const and may be called
// from any number of threads at once, each with its own DetectorWorkspace (or none: a temporary).
// A workspace must never be used by two calls at once. No globals: the built-in families are built
// once on first use, thread-safely.
//
// Errors: std::invalid_argument with a one-line message (bad option, unknown family, empty image,
// image over DetectorOptions::max_pixels, stride below the width).
//
// The types are those of the library's stage headers (installed under tagbench/detail/, not to be
// included directly: their names and layout may change between minor versions, this header's
// names do not). DetectorOptions' nested structs (threshold_quads, segmentation, line_fit,
// quad_search, payload, ...) are the stages' tuning knobs, documented where they are declared.
#include <tagbench/detail/detect/detector.hpp>
#include <tagbench/detail/detect/image.hpp>
#include <tagbench/detail/detect/pose.hpp>
#include <tagbench/version.hpp>
