#include "detect/defocus_read.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "detect/decode_quads.hpp"
#include "detect/detector.hpp"
#include "detect/homography.hpp"
#include "detect/payload_decode.hpp"
#include "detect/photometric_refine.hpp"  // move_detection_to

namespace tagbench {

std::vector<double> detail::disk_cell_fractions(double x, double y, double rho, int g) {
  std::vector<double> w(static_cast<std::size_t>(g) * static_cast<std::size_t>(g), 0.0);
  const auto add = [&](double px, double py, double weight) {
    const int c = std::clamp(static_cast<int>(std::floor(px)), 0, g - 1);
    const int r = std::clamp(static_cast<int>(std::floor(py)), 0, g - 1);
    w[static_cast<std::size_t>(r * g + c)] += weight;
  };
  if (!(rho > 0)) {
    add(x, y, 1);
    return w;
  }
  // Midpoint integration over the disk's bounding square: fine enough for fractions to 1e-3.
  constexpr int kSteps = 48;
  double total = 0;
  for (int a = 0; a < kSteps; ++a)
    for (int b = 0; b < kSteps; ++b) {
      const double dx = rho * (2.0 * (a + 0.5) / kSteps - 1), dy = rho * (2.0 * (b + 0.5) / kSteps - 1);
      if (dx * dx + dy * dy > rho * rho) continue;
      add(x + dx, y + dy, 1);
      total += 1;
    }
  for (double& v : w) v /= total;
  return w;
}

namespace {

// The padded grid: g = d + 6 cells a side (one assumed-white cell, the white ring, the black border,
// the payload); the black square's n = d + 2 cells start at grid index 2.
int grid_size(int d) { return d + 6; }

// Kernel rows for the black square's cells at m x m samples each (row-major over the (n m)^2
// samples), and the linear system's solution matrix: unknowns a, b, b p_i.
void build(int d, double rho, int m, double regularization, Eigen::MatrixXd& kernel, Eigen::MatrixXd& solve) {
  const int g = grid_size(d), n = d + 2, side = n * m, samples = side * side, unknowns = 2 + d * d;
  // A sample's fractions depend only on where in its cell it lies (m x m places): each is integrated
  // once over a window of cells round it that holds the whole disk, then placed for every cell (the
  // grid's edge cells taking what falls past them, as disk_cell_fractions does).
  const int reach = static_cast<int>(std::ceil(rho)) + 1, window = 2 * reach + 1;
  std::vector<std::vector<double>> at_place(static_cast<std::size_t>(m * m));
  for (int sr = 0; sr < m; ++sr)
    for (int sc = 0; sc < m; ++sc)
      at_place[static_cast<std::size_t>(sr * m + sc)] =
          detail::disk_cell_fractions(reach + (sc + 0.5) / m, reach + (sr + 0.5) / m, rho, window);
  kernel = Eigen::MatrixXd::Zero(samples, g * g);
  for (int jr = 0; jr < side; ++jr)
    for (int jc = 0; jc < side; ++jc) {
      const std::vector<double>& w = at_place[static_cast<std::size_t>((jr % m) * m + jc % m)];
      const int r0 = 2 + jr / m - reach, c0 = 2 + jc / m - reach;  // the window's first cell in the grid
      for (int wr = 0; wr < window; ++wr)
        for (int wc = 0; wc < window; ++wc) {
          const double v = w[static_cast<std::size_t>(wr * window + wc)];
          if (v == 0) continue;
          const int r = std::clamp(r0 + wr, 0, g - 1), c = std::clamp(c0 + wc, 0, g - 1);
          kernel(jr * side + jc, r * g + c) += v;
        }
    }
  // Rows: one per sample, then one regularisation row per payload cell (scaled by m, so that its
  // weight against the cell's m^2 sample rows does not change with m).
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(samples + d * d, unknowns);
  for (int j = 0; j < samples; ++j) {
    A(j, 0) = 1;
    for (int r = 0; r < g; ++r)
      for (int c = 0; c < g; ++c) {
        const double k = kernel(j, r * g + c);
        if (r < 2 || r > d + 3 || c < 2 || c > d + 3) A(j, 1) += k;                          // white
        else if (r >= 3 && r <= d + 2 && c >= 3 && c <= d + 2) A(j, 2 + (r - 3) * d + (c - 3)) = k;  // payload
      }
  }
  for (int i = 0; i < d * d; ++i) {
    A(samples + i, 2 + i) = regularization * m;
    A(samples + i, 1) = -0.5 * regularization * m;
  }
  solve = (A.transpose() * A).ldlt().solve(A.transpose()).leftCols(samples);
}

// The black square's cells sampled at m x m points each through the quad (corners clockwise on
// screen; corner 0 at the tag square's (-1, -1)); false when a sample falls outside the image.
bool sample_square(const ImageF& img, const Corners& q, int n, int m, Eigen::VectorXd& y) {
  const auto H = tag_homography(q);
  if (!H) return false;
  const int side = n * m;
  y.resize(side * side);
  const double step = 2.0 / side;
  const double xmax = img.width - 1, ymax = img.height - 1;
  for (int jr = 0; jr < side; ++jr) {
    const double v = -1 + step * (jr + 0.5);
    int jc = 0;
#if defined(__SSE2__)
    // Two samples at a time: the same doubles and floats as the scalar loop below (the pair
    // functions' own guarantee), and false exactly when it would return false.
    if (img.width >= 2 && img.height >= 2)
      for (; jc + 2 <= side; jc += 2) {
        __m128d qx, qy;
        apply_homography_pair(*H, _mm_set_pd(-1 + step * (jc + 1.5), -1 + step * (jc + 0.5)), _mm_set1_pd(v), qx, qy);
        alignas(16) double px[2], py[2];
        _mm_store_pd(px, qx);
        _mm_store_pd(py, qy);
        for (int i = 0; i < 2; ++i)
          if (!(px[i] >= 0) || !(py[i] >= 0) || px[i] > xmax || py[i] > ymax) return false;
        alignas(16) float out[2];
        sample_bilinear_inside_pair(img, qx, qy, out);
        y(jr * side + jc) = out[0];
        y(jr * side + jc + 1) = out[1];
      }
#endif
    for (; jc < side; ++jc) {
      const Eigen::Vector2d p = apply_homography(*H, Eigen::Vector2d(-1 + step * (jc + 0.5), v));
      if (!(p.x() >= 0) || !(p.y() >= 0) || p.x() > xmax || p.y() > ymax) return false;
      y(jr * side + jc) = sample_bilinear_inside(img, p);  // sample_bilinear's value, its test made above
    }
  }
  return true;
}

// The payload solved from the samples: its bits (MSB = the first cell, row-major, 1 = white) and
// the decision margin (the weakest cell's distance from b / 2, over b / 2, clamped to [0, 1]);
// nullopt without contrast.
struct Solved {
  Code bits = 0;
  double margin = 0;
};
std::optional<Solved> solve_payload(const Eigen::MatrixXd& solve, const Eigen::VectorXd& y, int d) {
  const Eigen::VectorXd x = solve * y;
  const double b = x(1);
  if (!(b > 0.02)) return std::nullopt;  // under 5 grey levels of contrast: nothing to read
  Solved s;
  s.margin = 1;
  for (int i = 0; i < d * d; ++i) {
    const double v = x(2 + i) / b - 0.5;
    s.bits = (s.bits << 1) | (v > 0 ? 1u : 0u);
    s.margin = std::min(s.margin, std::min(1.0, 2 * std::abs(v)));
  }
  return s;
}

// The model's pattern for a code read in the quad's frame: white outside the black square, black
// border, the code's payload.
Eigen::VectorXd pattern(Code word, int d) {
  const int g = grid_size(d);
  Eigen::VectorXd p = Eigen::VectorXd::Ones(g * g);
  for (int r = 2; r <= d + 3; ++r)
    for (int c = 2; c <= d + 3; ++c) p(r * g + c) = 0;
  for (int i = 0; i < d * d; ++i)
    if ((word >> (d * d - 1 - i)) & 1u) p((3 + i / d) * g + 3 + i % d) = 1;
  return p;
}

// Mean squared residual per cell over b^2 once a and b are fitted (least squares) to y ~ a + b e;
// +inf without positive contrast.
double model_cost(const Eigen::VectorXd& y, const Eigen::VectorXd& e, int cells) {
  const double n = static_cast<double>(y.size());
  const double se = e.sum(), sy = y.sum(), see = e.squaredNorm(), sey = e.dot(y);
  const double den = n * see - se * se;
  if (!(den > 1e-12)) return HUGE_VAL;
  const double b = (n * sey - se * sy) / den, a = (sy - b * se) / n;
  if (!(b > 0.02)) return HUGE_VAL;
  return (y.array() - a - b * e.array()).square().sum() / (b * b) * cells / n;
}

// One family's hypothesis, placement and test for one quad; the detection if it holds.
std::optional<Detection> try_family(const ImageF& gray, const Quad& quad, const TagFamily& family,
                                    const DefocusModels::Width& w, int m, int corrected,
                                    const DefocusReadOptions& opt) {
  const int d = family.payload_width(), n = d + 2, cells = n * n;
  Eigen::VectorXd y;
  if (!sample_square(gray, quad.corners, n, 1, y)) return std::nullopt;
  // 1. Hypothesis.
  // The first radius whose reading is nearest a code (fewest bits). A later radius must come strictly
  // nearer, so each search is bounded by the best so far, and a reading seen already is not searched.
  NearestWord best;
  std::size_t best_radius = 0;
  std::vector<Code> seen;
  for (std::size_t k = 0; k < w.radii.size() && best.distance > 0; ++k) {
    const auto s = solve_payload(w.radii[k].solve, y, d);
    if (!s || std::find(seen.begin(), seen.end(), s->bits) != seen.end()) continue;
    seen.push_back(s->bits);
    const NearestWord nw = family.nearest_word(s->bits, std::min(opt.max_hypothesis_bits, best.distance - 1));
    if (nw.index >= 0 && nw.distance < best.distance) best = nw, best_radius = k;
  }
  if (best.index < 0) return std::nullopt;
  const Code word = family.rotated_words()[static_cast<std::size_t>(best.index)];
  const Eigen::VectorXd p = pattern(word, d);
  if (!(model_cost(y, w.radii[best_radius].kernel * p, cells) <= opt.max_hypothesis_cost)) return std::nullopt;
  // 2. Placement: coordinate descent over the 8 corner coordinates and the radius. Each radius's
  // model of the pattern is computed once, when first asked for (the descent asks for the
  // neighbouring radii's again after every round that moved something).
  std::vector<Eigen::VectorXd> models(w.radii.size());
  const auto model = [&](std::size_t r) -> const Eigen::VectorXd& {
    if (models[r].size() == 0) models[r] = w.radii[r].fine_kernel * p;
    return models[r];
  };
  Corners q = quad.corners;
  std::size_t k = best_radius;
  Eigen::VectorXd yf;
  if (!sample_square(gray, q, n, m, yf)) return std::nullopt;
  double cost = model_cost(yf, model(k), cells);
  Eigen::VectorXd trial;
  for (double step = opt.initial_step_px; step >= opt.final_step_px; step *= 0.5) {
    for (bool improved = true; improved;) {
      improved = false;
      for (int ci = 0; ci < 8; ++ci)
        for (const int sign : {1, -1}) {
          Corners t = q;
          t[static_cast<std::size_t>(ci / 2)][ci % 2] += sign * step;
          if ((t[static_cast<std::size_t>(ci / 2)] - quad.corners[static_cast<std::size_t>(ci / 2)]).norm() >
              opt.max_corner_shift_px)
            continue;
          if (!sample_square(gray, t, n, m, trial)) continue;
          const double c = model_cost(trial, model(k), cells);
          if (c < cost - 1e-9) cost = c, q = t, std::swap(yf, trial), improved = true;
        }
      for (const int dk : {-1, 1}) {
        const long k2 = static_cast<long>(k) + dk;
        if (k2 < 0 || k2 >= static_cast<long>(w.radii.size())) continue;
        const double c = model_cost(yf, model(static_cast<std::size_t>(k2)), cells);
        if (c < cost - 1e-9) cost = c, k = static_cast<std::size_t>(k2), improved = true;
      }
    }
  }
  // The placement must keep a convex quad of the same winding (a corner may not cross a side).
  if (!(twice_signed_area(q) * twice_signed_area(quad.corners) > 0)) return std::nullopt;
  // 3. Test.
  const auto s = solve_payload(w.radii[k].fine_solve, yf, d);
  if (!s) return std::nullopt;
  const auto dec = family.decode(s->bits, corrected - opt.spare_bits);
  if (!dec || 4 * dec->id + dec->rotation != best.index) return std::nullopt;
  Detection det;
  det.family = family.name();
  det.id = dec->id;
  det.hamming = dec->hamming;
  det.rotation = dec->rotation;
  det.decision_margin = s->margin;
  det.observed_perimeter = quad.observed_perimeter;
  if (!move_detection_to(det, printed_corners(q, dec->rotation))) return std::nullopt;
  return det;
}

}  // namespace

DefocusModels::DefocusModels(std::span<const TagFamily> families, const DefocusReadOptions& opt)
    : m_(std::max(1, opt.samples_per_cell)) {
  for (const TagFamily& f : families) {
    const int d = f.payload_width();
    if (f.min_hamming() < opt.min_family_hamming || width(d)) continue;  // never tried, or built already
    Width w;
    w.d = d;
    for (const double rho : opt.radii_cells) {
      Radius r;
      r.rho = rho;
      build(d, rho, 1, opt.regularization, r.kernel, r.solve);
      build(d, rho, m_, opt.regularization, r.fine_kernel, r.fine_solve);
      w.radii.push_back(std::move(r));
    }
    widths_.push_back(std::move(w));
  }
}

const DefocusModels::Width* DefocusModels::width(int d) const {
  for (const Width& w : widths_)
    if (w.d == d) return &w;
  return nullptr;
}

std::vector<Detection> read_defocused_quads(const ImageF& gray, const DefocusModels& models,
                                            std::span<const Quad> quads, std::span<QuadOutcome> outcomes,
                                            std::span<const Detection> decoded, std::span<const TagFamily> families,
                                            int max_hamming, bool hamming_by_family, const DefocusReadOptions& opt) {
  if (!opt.enabled || gray.empty()) return {};
  return retry_undecoded_quads(
      quads, outcomes, decoded, families, opt.min_side_px, opt.max_side_px, opt.min_family_hamming, true,
      [&](std::size_t qi, const TagFamily& f) -> std::optional<Detection> {
        const DefocusModels::Width* w = models.width(f.payload_width());
        if (!w || w->radii.empty()) return std::nullopt;
        const int corrected = bits_corrected_for(f.min_hamming(), max_hamming, hamming_by_family);
        return try_family(gray, quads[qi], f, *w, models.samples_per_cell(), corrected, opt);
      });
}

}  // namespace tagbench
