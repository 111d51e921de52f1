#pragma once
// <tagbench/tagbench.hpp>: the whole public API without OpenCV: the detector, the families and the
// version. cv::Mat input is <tagbench/opencv.hpp>.
#include <tagbench/detector.hpp>
#include <tagbench/family.hpp>
#include <tagbench/version.hpp>
