#pragma once
// The sweep's external detectors (external/external_detector.hpp): each runs once on every rendered
// frame of the sweep, as the built-in detectors get it, written as a PNG into a temporary folder that
// is removed afterwards.
#include <vector>

#include "raytrace/sweeps.hpp"

namespace tagbench::bench::sweep_detail {

// Per external detector (settings.external order), per frame of `frames` (empty for those that failed
// to render): its detections and time. Throws std::runtime_error (one line naming the detector and
// the image) when one fails.
std::vector<std::vector<DetectorOutput>> run_external_detectors(const SweepSettings& settings,
                                                                const std::vector<SweepFrame>& frames,
                                                                const RenderReport& report);

}  // namespace tagbench::bench::sweep_detail
