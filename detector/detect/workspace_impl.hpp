#pragma once
// The per-pixel buffers a DetectorWorkspace (detector.hpp) keeps between frames. Only the
// pipeline's stages (find_quads_in_image.hpp, detector.cpp) use this header; callers see the
// workspace through DetectorWorkspace's public interface.
#include <opencv2/core.hpp>

#include "detect/detector.hpp"
#include "detect/gradient.hpp"
#include "detect/image.hpp"
#include "detect/line_quads.hpp"
#include "detect/segmentation.hpp"
#include "detect/threshold_quads.hpp"

namespace tagbench {

struct DetectorWorkspace::Impl {
  ImageF gray;             // the float image (cv::Mat and ImageU8View input; ImageF input is read in place)
  cv::Mat colour;          // scaled colour image before the gray conversion
  ImageF blur_tmp;         // horizontal pass of the blurs
  ImageF seg_in, dec_in;   // segmentation input; optional separately blurred decoding image
  Gradients gradients;
  SegmentationScratch seg;
  Clusters clusters;
  ThresholdQuadWorkspace threshold_quads;  // the threshold quad finder's buffers (default profile)
  ThresholdQuadWorkspace coarse;          // the coarse pass's (coarse_pass.hpp; half-size buffers)
  DarkOutlineScratch dark_outlines;        // the joined outlines' (dark_outlines.hpp; off in every profile)
  LineQuadScratch line_quads;              // the line quads' (line_quads.hpp; off in both profiles)
  PhotometricWorkspace photometric;        // the photometric refinement's (default profile; per tag, not per pixel)
};

}  // namespace tagbench
