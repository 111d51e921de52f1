#include "experiments/small_tag_pipeline.hpp"

#include <sstream>
#include <stdexcept>

#include "detect/detector_opencv.hpp"
#include "detect/blur.hpp"
#include "detect/gradient.hpp"
#include "detect/line_fit.hpp"
#include "detect/quad_search.hpp"
#include "detect/segmentation.hpp"

namespace tagbench::bench::experiments {
namespace {

double perimeter(const Corners& c) {
  double p = 0;
  for (std::size_t i = 0; i < 4; ++i) p += (c[(i + 1) % 4] - c[i]).norm();
  return p;
}

// Bilinear 2x upsampling: output pixel X sits at input coordinate (X - 0.5) / 2.
ImageF upsample2(const ImageF& in) {
  ImageF out(in.width * 2, in.height * 2);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      const double sx = std::clamp((x - 0.5) / 2, 0.0, in.width - 1.0), sy = std::clamp((y - 0.5) / 2, 0.0, in.height - 1.0);
      out.at(x, y) = *sample_bilinear(in, Eigen::Vector2d(sx, sy));
    }
  return out;
}

}  // namespace

Variant parse_variant(const std::string& spec) {
  Variant v;
  const auto colon = spec.find(':');
  v.name = spec.substr(0, colon);
  if (v.name.empty()) throw std::invalid_argument("variant '" + spec + "': no name");
  if (colon == std::string::npos) return v;
  std::stringstream ss(spec.substr(colon + 1));
  std::string kv;
  while (std::getline(ss, kv, ',')) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos) throw std::invalid_argument("variant '" + spec + "': '" + kv + "' is not key=value");
    const std::string key = kv.substr(0, eq);
    double val = 0;
    try {
      val = std::stod(kv.substr(eq + 1));
    } catch (const std::exception&) {
      throw std::invalid_argument("variant '" + spec + "': '" + kv + "' has no number");
    }
    if (key == "sigma") v.seg_sigma = val;
    else if (key == "up") v.upsample = val != 0;
    else if (key == "both") v.both_scales = val != 0;
    else if (key == "magscale") v.min_mag_scale = val;
    else if (key == "refine") v.refine_edges = val != 0;
    else if (key == "area") v.area_payload = val != 0;
    else if (key == "k") v.area.samples_per_side = static_cast<int>(val);
    else if (key == "extent") v.area.sample_extent = val;
    else if (key == "sharp") v.area.sharpening = val;
    else if (key == "h") v.max_hamming = static_cast<int>(val);
    else if (key == "range") v.edge.max_range_px = val;
    else if (key == "gamma") v.edge.gamma = val;
    else throw std::invalid_argument("variant '" + spec + "': unknown key '" + key + "'");
  }
  return v;
}

std::optional<PayloadReading> read_with(const ImageF& gray, const Corners& corners, int d, const Variant& v) {
  const auto H = tag_homography(corners);
  if (!H) return std::nullopt;
  if (v.area_payload) return read_payload_area(gray, *H, d, v.area);
  PayloadOptions p;
  p.quick_reject = false;
  return read_payload(gray, *H, d, p);
}

namespace {

std::vector<Quad> quads_at(const ImageF& gray, const Variant& v, bool upsample) {
  const ImageF seg_base = upsample ? upsample2(gray) : gray;
  const ImageF seg_in = gaussian_blur(seg_base, v.seg_sigma);
  SegmentationOptions seg_opt;
  seg_opt.min_mag *= static_cast<float>(upsample ? v.min_mag_scale : 1.0);
  const Gradients g = compute_gradients(seg_in, seg_opt.min_mag);
  const Clusters clusters = segment_clusters(g, seg_opt);
  LineFitOptions lf;
  if (upsample) lf.min_length *= 2;  // the same length in input pixels
  std::vector<Segment> segments = fit_segments(clusters, lf);
  if (upsample)
    for (auto& s : segments) {  // upsampled X -> input (X - 0.5) / 2
      s.p0 = (s.p0.array() - 0.5) / 2;
      s.p1 = (s.p1.array() - 0.5) / 2;
      s.length /= 2;
    }
  return find_quads(segments, QuadSearchOptions{});
}

}  // namespace

PipelineResult run_pipeline(const ImageF& gray, const TagFamily& family, const Variant& v) {
  std::vector<Quad> quads = quads_at(gray, v, v.upsample);
  if (v.upsample && v.both_scales) {
    std::vector<Quad> more = quads_at(gray, v, false);
    quads.insert(quads.end(), more.begin(), more.end());
  }
  const int d = family.payload_width();
  PipelineResult out;
  std::vector<PipelineDetection> found;
  std::vector<double> found_perimeter;
  for (const Quad& q : quads) {
    QuadOutcome o;
    o.corners = o.used = q.corners;
    if (border_contrast_plausible(gray, q.corners, d, PayloadOptions{}.min_contrast)) {
      if (v.refine_edges) {
        EdgeRefineOptions eo = v.edge;
        eo.cells_across = d + 2;
        if (const auto r = refine_quad_edges(gray, q.corners, eo)) {
          o.used = *r;
          o.refined = true;
        }
      }
      o.reading = read_with(gray, o.used, d, v);
      if (o.reading) o.decoded = family.decode(o.reading->bits, v.max_hamming);
    }
    if (o.decoded) {
      PipelineDetection det;
      det.id = o.decoded->id;
      det.hamming = o.decoded->hamming;
      det.margin = o.reading->margin;
      for (std::size_t i = 0; i < 4; ++i) det.corners[i] = o.used[(i + static_cast<std::size_t>(o.decoded->rotation)) % 4];
      det.center = apply_homography(*tag_homography(det.corners), Eigen::Vector2d::Zero());
      // Duplicates as the detector merges them: same id, centres closer than 1/16 of the summed
      // perimeters; the lower hamming (then the larger quad) is kept.
      bool merged = false;
      for (std::size_t k = 0; k < found.size() && !merged; ++k) {
        if (found[k].id != det.id) continue;
        if ((found[k].center - det.center).norm() >= (perimeter(found[k].corners) + perimeter(det.corners)) / 16) continue;
        merged = true;
        if (det.hamming < found[k].hamming ||
            (det.hamming == found[k].hamming && q.observed_perimeter > found_perimeter[k])) {
          found[k] = det;
          found_perimeter[k] = q.observed_perimeter;
        }
      }
      if (!merged) {
        found.push_back(det);
        found_perimeter.push_back(q.observed_perimeter);
      }
    }
    out.quads.push_back(std::move(o));
  }
  out.detections = std::move(found);
  return out;
}

}  // namespace tagbench::bench::experiments
