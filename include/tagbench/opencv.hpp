#pragma once
// <tagbench/opencv.hpp>: cv::Mat input for the detector (<tagbench/detector.hpp>). The only public
// header that needs OpenCV: link tagbench::opencv (find_package(tagbench CONFIG COMPONENTS opencv))
// or pkg-config's tagbench-opencv, which add OpenCV's core.
//
//   tagbench::detect(detector, mat[, workspace])  8- or 16-bit, or float in [0, 1]; gray, BGR or BGRA
//   tagbench::to_float_image(mat)                 the conversion it applies (BGR->gray 0.299/0.587/0.114)
//
// Same conventions, errors and thread safety as Detector::detect (one workspace per thread).
#include <tagbench/detector.hpp>
#include <tagbench/detail/detect/detector_opencv.hpp>
