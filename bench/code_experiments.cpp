#include "code_experiments.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "codes/families.hpp"
#include "codes/tag_family.hpp"
#include "tools/format.hpp"

namespace tagbench::bench {

std::vector<CodeScheme> paper_code_schemes() {
  return {
      {"ARToolkit+ (simple)", "artoolkitplus-simple", 512, 4},
      {"ARToolkit+ (BCH)", "artoolkitplus-bch", 4096, 2},
      {"ARTag", "artag-2046", 2046, 4},
      {"ARTag (1023 words without complements)", "artag", std::nullopt, std::nullopt},
      {"Proposed (36h9)", "36h9", 4164, 9},
      {"Proposed (36h10)", "36h10", 2221, 10},
      {"36h11", "36h11", std::nullopt, std::nullopt},
      {"25h9", "25h9", std::nullopt, std::nullopt},
      {"16h5", "16h5", std::nullopt, std::nullopt},
  };
}

std::vector<CodeTableRow> code_table(int threads) {
  std::vector<CodeTableRow> rows;
  const auto shipped = builtin_family_names();
  for (const auto& s : paper_code_schemes()) {
    CodeTableRow r;
    r.scheme = s;
    if (std::find(shipped.begin(), shipped.end(), s.family) == shipped.end()) {
      rows.push_back(r);  // not available until its generator run completes
      continue;
    }
    const TagFamily& f = builtin_family(s.family);
    const DistanceStats st = distance_stats(f.codes(), f.payload_width(), threads);
    r.available = true;
    r.bits = f.bits();
    r.codes = f.size();
    r.min_hamming_rotations = st.min_with_rotations;
    r.min_hamming_plain = st.min_plain;
    r.min_complexity = min_complexity_of(f.codes(), f.payload_width());
    r.histogram = st.histogram;
    rows.push_back(std::move(r));
  }
  return rows;
}

double hamming_ball_volume(int n, int k) {
  double sum = 0, c = 1;  // C(n, 0)
  for (int i = 0; i <= k && i <= n; ++i) {
    sum += c;
    c = c * (n - i) / (i + 1);
  }
  return sum;
}

std::vector<FpTheoryRow> fp_theory() {
  // The paper's table (section V-B), percent; N/A entries are absent.
  const std::vector<std::pair<std::string, std::vector<std::optional<double>>>> paper = {
      {"36h10", {0.000001, 0.000041, 0.000744, 0.008714, 0.074459, 0.495232, std::nullopt, std::nullopt}},
      {"36h15", {0.000000, 0.000002, 0.000029, 0.000341, 0.002912, 0.019370, 0.104403, 0.468827}},
  };
  std::vector<FpTheoryRow> rows;
  const auto shipped = builtin_family_names();
  for (const auto& [name, values] : paper) {
    if (std::find(shipped.begin(), shipped.end(), name) == shipped.end()) continue;  // not generated yet
    const TagFamily& f = builtin_family(name);
    const double space = std::ldexp(1.0, f.bits());
    for (int k = 0; k < 8; ++k) {
      FpTheoryRow r;
      r.family = name;
      r.codes = f.size();
      r.bits = f.bits();
      r.min_hamming = f.min_hamming();
      r.bits_corrected = k;
      r.correctable = k <= (f.min_hamming() - 1) / 2;
      const double ball = hamming_ball_volume(f.bits(), k);
      r.words_accepted = 4.0 * static_cast<double>(f.size()) * ball;
      r.fp_percent = 100.0 * r.words_accepted / space;
      r.fp_percent_one_rotation = r.fp_percent / 4;
      r.paper_fp_percent = values[static_cast<std::size_t>(k)];
      if (r.paper_fp_percent && *r.paper_fp_percent > 0) r.paper_implied_words = *r.paper_fp_percent / 100 * space / ball;
      rows.push_back(r);
    }
  }
  return rows;
}

namespace {
std::string opt(const std::optional<int>& v) { return v ? std::to_string(*v) : ""; }
}  // namespace

std::string code_table_csv(const std::vector<CodeTableRow>& rows) {
  std::ostringstream o;
  o << "scheme,family,status,bits,codes,min_hamming_with_rotations,min_hamming_without_rotations,min_complexity,"
       "paper_codes,paper_min_hamming\n";
  for (const auto& r : rows) {
    o << '"' << r.scheme.scheme << "\"," << r.scheme.family << ',' << (r.available ? "ok" : "generation-in-progress")
      << ',';
    if (r.available)
      o << r.bits << ',' << r.codes << ',' << r.min_hamming_rotations << ',' << r.min_hamming_plain << ','
        << r.min_complexity;
    else
      o << ",,,,";
    o << ',' << opt(r.scheme.paper_codes) << ',' << opt(r.scheme.paper_min_hamming) << '\n';
  }
  return o.str();
}

std::string fig5_csv(const std::vector<CodeTableRow>& rows) {
  std::ostringstream o;
  o << "scheme,family,codes,pairs_total,distance,pairs,fraction\n";
  for (const auto& r : rows) {
    if (!r.available) continue;
    const double total = static_cast<double>(r.codes) * static_cast<double>(r.codes - 1) / 2;
    for (std::size_t k = 0; k < r.histogram.size(); ++k)
      o << '"' << r.scheme.scheme << "\"," << r.scheme.family << ',' << r.codes << ','
        << static_cast<unsigned long long>(total) << ',' << k << ',' << r.histogram[k] << ','
        << format_number(static_cast<double>(r.histogram[k]) / total, "%.6g") << '\n';
  }
  return o.str();
}

std::string fp_theory_csv(const std::vector<FpTheoryRow>& rows) {
  std::ostringstream o;
  o << "family,codes,bits,min_hamming,bits_corrected,status,words_accepted_4_rotations,fp_percent_4_rotations,"
       "fp_percent_1_rotation,paper_fp_percent,paper_implied_words,paper_implied_codes_4_rotations\n";
  for (const auto& r : rows) {
    o << r.family << ',' << r.codes << ',' << r.bits << ',' << r.min_hamming << ',' << r.bits_corrected << ','
      << (r.correctable ? "ok" : "N/A: beyond floor((h-1)/2)") << ',';
    if (r.correctable)
      o << format_number(r.words_accepted, "%.0f") << ',' << format_number(r.fp_percent, "%.6e") << ','
        << format_number(r.fp_percent_one_rotation, "%.6e");
    else
      o << ",,";
    o << ',' << (r.paper_fp_percent ? format_number(*r.paper_fp_percent, "%.6f") : std::string("N/A")) << ','
      << (r.paper_implied_words ? format_number(*r.paper_implied_words, "%.1f") : "") << ','
      << (r.paper_implied_words ? format_number(*r.paper_implied_words / 4, "%.1f") : "") << '\n';
  }
  return o.str();
}

}  // namespace tagbench::bench
