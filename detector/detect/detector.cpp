#include "detect/detector.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "codes/families.hpp"
#include "detect/bent_decode.hpp"
#include "detect/decode_quads.hpp"
#include "detect/edge_refine.hpp"
#include "detect/linear_corners.hpp"
#include "detect/estimate_poses.hpp"
#include "detect/find_quads_in_image.hpp"
#include "detect/homography.hpp"
#include "detect/stage_clock.hpp"
#include "detect/find_threshold_quads_in_image.hpp"
#include "detect/photometric_refine.hpp"
#include "detect/printed_square.hpp"
#include "detect/line_quads.hpp"
#include "detect/payload_decode.hpp"
#include "detect/ring_quads.hpp"
#include "detect/suppress_duplicates.hpp"
#include "detect/workspace_impl.hpp"

namespace tagbench {

DetectorWorkspace::DetectorWorkspace() : impl_(std::make_unique<Impl>()) {}
DetectorWorkspace::~DetectorWorkspace() = default;
DetectorWorkspace::DetectorWorkspace(DetectorWorkspace&&) noexcept = default;
DetectorWorkspace& DetectorWorkspace::operator=(DetectorWorkspace&&) noexcept = default;

DetectorWorkspace::Impl& DetectorWorkspace::impl() {
  if (!impl_) impl_ = std::make_unique<Impl>();  // a moved-from workspace is usable again
  return *impl_;
}

std::vector<DetectorWorkspace::Buffer> DetectorWorkspace::buffers() const {
  if (!impl_) return {};  // moved from
  const Impl& w = *impl_;
  auto of = [](const char* name, const auto& v) {
    return Buffer{name, v.data(), v.capacity() * sizeof(v[0])};
  };
  return {of("gray", w.gray.data),
          Buffer{"colour", w.colour.data, w.colour.empty() ? 0 : w.colour.total() * w.colour.elemSize()},
          of("blur_tmp", w.blur_tmp.data),
          of("seg_in", w.seg_in.data),
          of("dec_in", w.dec_in.data),
          of("gradient_mag", w.gradients.mag),
          of("gradient_theta", w.gradients.theta),
          of("edges", w.seg.edges),
          of("edges_sorted", w.seg.sorted),
          of("weight_start", w.seg.weight_start),
          of("union_find_parent", w.seg.parent),
          of("union_find_stats", w.seg.stats),
          of("cluster_of", w.seg.cluster_of),
          of("cluster_count", w.seg.count),
          of("cluster_fill", w.seg.fill),
          of("cluster_pixels", w.clusters.pixels),
          of("cluster_offsets", w.clusters.offsets),
          of("threshold_half", w.threshold_quads.half.data),
          of("coarse_half", w.coarse.half.data)};
}

std::size_t DetectorWorkspace::capacity_bytes() const {
  std::size_t sum = 0;
  for (const Buffer& b : buffers()) sum += b.capacity_bytes;
  return sum;
}

void DetectorWorkspace::release() {
  if (impl_) *impl_ = Impl();  // fresh members: the old storage is freed
}

namespace {

// occlusion_refit.hpp on every detection: corners (and homography, centre) replaced, or withdrawn
// (then copied, as decoded, to `withdrawn` if given). Returns, per detection kept, its hidden sides.
std::vector<HiddenSides> refit_occluded(std::vector<Detection>& dets, const ImageF& gray,
                                        const std::vector<TagFamily>& families, const OcclusionRefitOptions& opt,
                                        std::vector<Detection>* withdrawn) {
  std::vector<HiddenSides> hidden;
  std::vector<Detection> kept;
  for (Detection& d : dets) {
    const auto f = std::find_if(families.begin(), families.end(), [&](const TagFamily& x) { return x.name() == d.family; });
    OcclusionRefitResult r;
    if (f != families.end()) {
      r = refit_occluded_sides(gray, d.corners, f->payload_width() + 2, opt);
      // Withdrawn when the refit fails or its corners give no homography (d is then still as decoded).
      if (!r.corners || (r.sides_refitted > 0 && !move_detection_to(d, r.corners))) {
        if (withdrawn) withdrawn->push_back(d);
        continue;
      }
    }
    hidden.push_back(r.hidden);
    kept.push_back(std::move(d));
  }
  dets = std::move(kept);
  return hidden;
}

}  // namespace

Detector::Detector(DetectorOptions options) : opt_(std::move(options)), find_quads_(&find_quads_in_image) {
  for (const auto& f : opt_.families) families_.push_back(load_family(f));
  opt_.validate(families_);
  // The refinement's border check (ThresholdQuadOptions::refine_check) asks what the decoder's
  // pre-filter will: the thinnest rings of the families searched, the payload's contrast floor.
  auto& check = opt_.threshold_quads.refine_check;
  check.payload_width = std::max(1, max_payload_width(families_));
  check.min_contrast = opt_.payload.min_contrast;
  check.enabled = check.enabled && opt_.payload.quick_reject && opt_.decode_sigma == 0;  // the image it reads
  // The edge locators after decoding read linear intensities: the input's encoding.
  opt_.occlusion.gamma = opt_.input_gamma;
  opt_.photometric.gamma = opt_.input_gamma;
  if (opt_.quad_finder == QuadFinderKind::kThreshold) find_quads_ = &find_threshold_quads_in_image;
  if (opt_.defocus_read.enabled) defocus_models_ = DefocusModels(families_, opt_.defocus_read);
}

void Detector::check_size(long long width, long long height) const {
  if (width * height <= opt_.max_pixels) return;
  throw std::invalid_argument("image " + std::to_string(width) + "x" + std::to_string(height) + " (" +
                              std::to_string(width * height) + " pixels) is over the detector's limit of " +
                              std::to_string(opt_.max_pixels) + " pixels (DetectorOptions::max_pixels)");
}

std::vector<Detection> Detector::detect(const ImageU8View& image, DetectorTrace* trace,
                                        StageTimings* timings) const {
  DetectorWorkspace ws;
  return detect(image, ws, trace, timings);
}

std::vector<Detection> Detector::detect(const ImageF& gray, DetectorTrace* trace, StageTimings* timings) const {
  DetectorWorkspace ws;
  return detect(gray, ws, trace, timings);
}

std::vector<Detection> Detector::detect(const ImageU8View& image, DetectorWorkspace& ws, DetectorTrace* trace,
                                        StageTimings* timings) const {
  if (image.width < 1 || image.height < 1 || image.data == nullptr) throw std::invalid_argument("empty image");
  check_size(image.width, image.height);  // before the conversion allocates anything
  DetectorWorkspace::Impl& w = ws.impl();
  to_float_image(image, w.gray);
  return run(w.gray, ws, trace, timings);
}

std::vector<Detection> Detector::detect(const ImageF& gray, DetectorWorkspace& ws, DetectorTrace* trace,
                                        StageTimings* timings) const {
  if (gray.empty()) throw std::invalid_argument("empty image");
  check_size(gray.width, gray.height);
  // Every stage indexes data[y * width + x]: a short vector would be read past its end.
  if (gray.data.size() != static_cast<std::size_t>(gray.width) * static_cast<std::size_t>(gray.height))
    throw std::invalid_argument("image data has " + std::to_string(gray.data.size()) + " values, not " +
                                std::to_string(gray.width) + "x" + std::to_string(gray.height));
  return run(gray, ws, trace, timings);
}

std::vector<Detection> Detector::run(const ImageF& gray, DetectorWorkspace& workspace, DetectorTrace* trace,
                                     StageTimings* timings) const {
  using Clock = detail::StageClock;
  const auto ms_since = detail::lap_ms;
  StageTimings tm;
  const auto t_start = Clock::now();

  // 1-5. Blur, gradients, clusters, segments, quads (each stage times itself).
  const FoundQuads found = find_quads_(gray, opt_, workspace, &tm, trace);
  auto t = Clock::now();

  // 6. Payloads, decoded against every family; one detection per tag; the margin filter.
  // The bent-tag second chance (bent_decode.hpp) needs every quad's outcome, traced or not.
  std::vector<QuadOutcome> own_outcomes;
  const bool second_look = opt_.second_look.enabled && opt_.quad_finder == QuadFinderKind::kThreshold &&
                           (!opt_.half_resolution || opt_.second_look.at_half_resolution);
  const bool printed_square = opt_.printed_square.enabled && opt_.quad_finder == QuadFinderKind::kThreshold;
  std::vector<QuadOutcome>* outcomes =
      trace ? &trace->quad_outcomes
            : (opt_.bent.enabled || second_look || printed_square || opt_.code_refit.enabled || opt_.defocus_read.enabled ||
               opt_.corner_completion.enabled)
                ? &own_outcomes
                : nullptr;
  const std::size_t first_outcome = outcomes ? outcomes->size() : 0;
  std::vector<Detection> decoded = decode_quads(*found.decode_image, found.quads, families_, opt_.max_hamming,
                                                opt_.payload,
                                                opt_.payload_reader == PayloadReaderKind::kArea ? &opt_.payload_area
                                                                                                : nullptr,
                                                trace ? &trace->readings : nullptr, outcomes, opt_.hamming_by_family,
                                                &opt_.soft_decode);
  if (opt_.bent.enabled) {
    auto bent = decode_bent_quads(gray, *found.decode_image, found.quads,
                                  std::span(*outcomes).subspan(first_outcome), families_, opt_.max_hamming,
                                  opt_.hamming_by_family, opt_.payload_area, opt_.payload.min_contrast, opt_.bent);
    decoded.insert(decoded.end(), std::make_move_iterator(bent.begin()), std::make_move_iterator(bent.end()));
  }
  // Every quad decoded so far, parallel to outcomes[first_outcome...] (for the code refit).
  std::vector<Quad> all_quads;
  const bool keep_quads = opt_.code_refit.enabled || opt_.defocus_read.enabled || opt_.corner_completion.enabled;
  if (keep_quads) all_quads.assign(found.quads.begin(), found.quads.end());
  // Quads found after the first decoding (the second look, the group look), decoded and traced alike.
  const auto decode_more = [&](const std::vector<Quad>& quads) {
    if (keep_quads) all_quads.insert(all_quads.end(), quads.begin(), quads.end());
    auto more = decode_quads(*found.decode_image, quads, families_, opt_.max_hamming, opt_.payload,
                             opt_.payload_reader == PayloadReaderKind::kArea ? &opt_.payload_area : nullptr,
                             trace ? &trace->readings : nullptr, outcomes, opt_.hamming_by_family, &opt_.soft_decode);
    if (trace) trace->quads.insert(trace->quads.end(), quads.begin(), quads.end());
    decoded.insert(decoded.end(), std::make_move_iterator(more.begin()), std::make_move_iterator(more.end()));
  };
  std::vector<Quad> again;  // the second look's quads (their outcomes follow found.quads')
  if (second_look) {  // second_look.hpp: the quads that did not decode, looked at again
    std::vector<bool> look(found.quads.size());
    for (std::size_t i = 0; i < look.size(); ++i) {
      const QuadOutcome::Fate fate = (*outcomes)[first_outcome + i].fate;
      look[i] = wants_second_look(fate == QuadOutcome::Fate::kDecoded, fate == QuadOutcome::Fate::kBorderRejected,
                                  opt_.second_look);
    }
    again = second_look_quads(gray, found.quads, look, opt_.threshold_quads, opt_.second_look);
    decode_more(again);
    if (opt_.group_look.enabled && !opt_.half_resolution)  // group_look.hpp: groups that gave no quad
      decode_more(group_look_quads(gray, workspace.impl().threshold_quads.pass.groups, found.quads, look, again,
                                   opt_.threshold_quads, opt_.second_look, opt_.group_look));
  }
  // The corners of every tag decoded so far: the later candidate sources skip quads centred inside one.
  const auto covered = [&] {
    std::vector<Corners> c;
    for (const Detection& d : decoded) c.push_back(d.corners);
    return c;
  };
  if (opt_.dark_outlines.enabled && opt_.quad_finder == QuadFinderKind::kThreshold && !opt_.half_resolution) {
    auto& tq = workspace.impl().threshold_quads;  // dark_outlines.hpp: a dark component's groups joined
    decode_more(dark_outline_quads(tq.pass.groups, tq.pass.components, gray, covered(), opt_.threshold_quads.fit,
                                   opt_.threshold_quads.refine, opt_.dark_outlines, tq.fit,
                                   workspace.impl().dark_outlines, opt_.threshold_quads.refine_check, tq.gave_quad));
  }
  if (opt_.coarse_pass.enabled && opt_.quad_finder == QuadFinderKind::kThreshold && !opt_.half_resolution)
    decode_more(coarse_pass_quads(gray, opt_.threshold_quads, covered(), opt_.coarse_pass,  // coarse_pass.hpp
                                  workspace.impl().coarse));
  // Quads read as printed squares (printed_square.hpp): the black square inside each decoded; the
  // inner squares are placed only as well as the outer quad was, so the few that decode are refined
  // on the full-resolution image like every threshold quad (after decoding: refining every candidate
  // first cost 6-10 % more time).
  std::vector<int> widths;  // the families' payload widths, for reading printed squares
  for (const TagFamily& f : families_) widths.push_back(f.payload_width());
  // The detections from decoded[first_new] on, edge-refined on the full-resolution image.
  const auto refine_since = [&](std::size_t first_new) {
    for (std::size_t i = first_new; i < decoded.size(); ++i)
      move_detection_to(decoded[i], refine_quad_edges(gray, decoded[i].corners, opt_.threshold_quads.refine));
  };
  const auto decode_printed = [&](const std::vector<Quad>& quads, const std::vector<bool>& look) {
    const std::size_t first_new = decoded.size();
    decode_more(black_squares_in_printed_squares(quads, look, widths));
    if (opt_.printed_square.refine_edges) refine_since(first_new);
  };
  if (printed_square) {
    // The first pass's quads and the second look's, each looked at when it was read but not decoded:
    // not when the border pre-filter refused it, as a printed square's outer cells (the grey paper)
    // are darker than the lighter card round it, which is what the pre-filter asks of a black square.
    std::vector<Quad> quads(found.quads.begin(), found.quads.end());
    quads.insert(quads.end(), again.begin(), again.end());
    std::vector<bool> look(quads.size());
    for (std::size_t i = 0; i < look.size(); ++i) {
      const QuadOutcome::Fate fate = (*outcomes)[first_outcome + i].fate;
      look[i] = fate != QuadOutcome::Fate::kDecoded && fate != QuadOutcome::Fate::kBorderRejected;
    }
    decode_printed(quads, look);
  }
  if (opt_.ring_quads.enabled && opt_.quad_finder == QuadFinderKind::kThreshold && !opt_.half_resolution) {
    // ring_quads.hpp: white rings on a darker card, light inside, read as printed squares
    auto& tq = workspace.impl().threshold_quads;
    const std::vector<Quad> rings = ring_quads(tq.pass.groups, tq.pass.components, gray, opt_.threshold_quads.fit,
                                                 opt_.ring_quads, tq.fit);
    decode_printed(rings, std::vector<bool>(rings.size(), true));
  }
  // Inferred quads (the line quads, the corner completions) are read with a stricter test: a tag
  // from them must be spare_bits closer to its code than its family corrects. Each is border
  // pre-filtered and refined before reading (refine_first) or only the tags it gives, after reading.
  const int max_d = max_payload_width(families_);
  const auto refined = [&](const std::vector<Quad>& quads, bool inner, bool check_first) {
    std::vector<Quad> out;
    const ImageF& img = *found.decode_image;
    const double contrast = opt_.payload.min_contrast;
    for (const Quad& q : quads)
      if (check_first && opt_.payload.quick_reject &&
          !border_worth_refining(img, q.corners, max_d, contrast, inner && opt_.line_quads.inner_check_slack ? 4 : 0))
        continue;
      else if (auto r = refine_quad_edges(gray, q.corners, opt_.threshold_quads.refine)) {
        out.push_back(q);
        out.back().corners = *r;
      }
    return out;
  };
  const auto read_inferred = [&](const std::vector<Quad>& quads, bool refine_first, bool inner, bool check_first,
                                 int spare_bits) {
    const std::size_t first_new = decoded.size();
    const std::size_t first_read = outcomes ? outcomes->size() : 0;
    decode_more(refine_first ? refined(quads, inner, check_first) : quads);
    // Hundreds of such quads a frame are read: a tag from them must be spare_bits closer to its code
    // than a family corrects (a 36h11 false detection on the corpus and a misplaced quad on the
    // realistic set were both 2 bits off).
    const auto too_far = [&](const std::string& family, int hamming) {
      if (hamming == 0 && opt_.line_quads.keep_exact) return false;
      for (const TagFamily& f : families_)
        if (f.name() == family)
          return hamming > bits_corrected_for(f.min_hamming(), opt_.max_hamming, opt_.hamming_by_family) - spare_bits;
      return false;
    };
    decoded.erase(std::remove_if(decoded.begin() + static_cast<std::ptrdiff_t>(first_new), decoded.end(),
                                 [&](const Detection& d) { return too_far(d.family, d.hamming); }),
                  decoded.end());
    if (outcomes)  // the same judgement on the quads' outcomes, for explaining a lost tag
      for (std::size_t i = first_read; i < outcomes->size(); ++i) {
        QuadOutcome& o = (*outcomes)[i];
        if (o.fate == QuadOutcome::Fate::kDecoded && too_far(o.family, o.hamming))
          o.fate = QuadOutcome::Fate::kTooFarForItsSource;
      }
    if (!refine_first) refine_since(first_new);
  };
  if (opt_.line_quads.enabled && opt_.quad_finder == QuadFinderKind::kThreshold &&
      (!opt_.half_resolution || opt_.line_quads.at_half_resolution)) {
    // line_quads.hpp: quads of straight edges where no tag was found, each read as the black square,
    // then (those still uncovered) as printed squares.
    const int spare = opt_.line_quads.spare_bits;
    const bool check = opt_.line_quads.check_before_refining;
    std::vector<Quad> lq = line_quads(gray, covered(), opt_.line_quads, workspace.impl().line_quads);
    read_inferred(lq, opt_.line_quads.refine_black, false, check, spare);
    const std::vector<Corners> now = covered();
    std::vector<bool> look(lq.size());
    for (std::size_t i = 0; i < lq.size(); ++i) look[i] = !centre_covered(lq[i], now);
    read_inferred(black_squares_in_printed_squares(lq, look, widths), opt_.line_quads.refine_inner, true, check, spare);
  }
  if (opt_.code_refit.enabled) {  // code_refit.hpp: the quads still undecoded, placed by their likeliest code
    PayloadAreaOptions area = opt_.payload_area;
    area.min_contrast = opt_.payload.min_contrast;
    auto refit = refit_to_nearest_codes(gray, *found.decode_image, all_quads,
                                        std::span(*outcomes).subspan(first_outcome), decoded, families_,
                                        opt_.max_hamming, opt_.hamming_by_family, area, opt_.code_refit,
                                        &workspace.impl().photometric);
    decoded.insert(decoded.end(), std::make_move_iterator(refit.begin()), std::make_move_iterator(refit.end()));
  }
  if (opt_.defocus_read.enabled) {  // defocus_read.hpp: the quads still undecoded, read through a lens's blur
    auto more = read_defocused_quads(gray, defocus_models_, all_quads, std::span(*outcomes).subspan(first_outcome),
                                     decoded, families_, opt_.max_hamming, opt_.hamming_by_family, opt_.defocus_read);
    decoded.insert(decoded.end(), std::make_move_iterator(more.begin()), std::make_move_iterator(more.end()));
  }
  // corner_completion.hpp: a cut corner made up, last, so that the completions the reading refuses
  // are not also offered to the code refit and the defocus reading (+15-23 % time when they were).
  if (opt_.corner_completion.enabled) {
    const std::vector<Quad> completed = completed_quads(*found.decode_image, max_d, all_quads,
                                                        std::span(*outcomes).subspan(first_outcome), covered(),
                                                        opt_.corner_completion);
    read_inferred(completed, true, false, true, opt_.corner_completion.spare_bits);
  }
  std::vector<Detection> out = suppress_duplicates(std::move(decoded));
  if (opt_.suppress_overlaps) out = suppress_overlaps(std::move(out));
  drop_below_margin(out, opt_.min_decision_margin);
  if (opt_.linear_corners.enabled)
    refine_corners_linear(out, gray, families_, opt_.input_gamma, opt_.threshold_quads.refine, opt_.linear_corners);
  std::vector<HiddenSides> hidden;
  if (opt_.occlusion_refit)
    hidden = refit_occluded(out, gray, families_, opt_.occlusion, trace ? &trace->withdrawn : nullptr);
  if (opt_.photometric.enabled && !opt_.distortion)  // a homography cannot fit a distorted tag
    refine_detections_photometric_guarded(out, gray, families_, opt_.photometric, opt_.photometric_guard, hidden,
                                          &workspace.impl().photometric);
  tm.decode = ms_since(t);

  // 7. Poses.
  if (opt_.camera) estimate_poses(out, *opt_.camera, opt_.tag_size, opt_.distortion, opt_.refine_pose);
  if (opt_.camera && opt_.refine_pose)  // under a lens only with pose_choice.with_lens
    choose_poses_photometric(out, gray, families_, *opt_.camera, opt_.tag_size, opt_.pose_choice, opt_.distortion);
  tm.pose = ms_since(t);
  tm.total = std::chrono::duration<double, std::milli>(Clock::now() - t_start).count();
  for (auto& d : out) d.timings = tm;
  if (timings) *timings = tm;
  return out;
}

}  // namespace tagbench
