// Writes the committed seed corpora, fuzz/corpus/<target>/ (a handful of tiny, valid or nearly
// valid inputs per target, from which libFuzzer mutates): `fuzz_make_seeds OUT_DIR`. Built on
// demand only (cmake --build DIR --target fuzz_make_seeds); deterministic, so rerunning it
// reproduces the committed files. The image seeds are tags drawn from the library's tag layout,
// the same pixels `tagbench render` writes; the bundles come from the tests' rcc writer.
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../corpus_tools/tests/rcc_writer.hpp"
#include "candidates.hpp"
#include "codes/families.hpp"
#include "codes/family_io.hpp"
#include "codes/lexicode.hpp"
#include "codes/tag_layout.hpp"
#include "sources.hpp"

namespace fs = std::filesystem;

namespace {

fs::path g_out;

void put(const std::string& target, const std::string& name, const std::string& bytes) {
  const fs::path dir = g_out / target;
  fs::create_directories(dir);
  std::ofstream(dir / name, std::ios::binary) << bytes;
}

// A tag of `family` as a gray 8-bit image, px pixels per cell, plus a white margin of one cell.
cv::Mat tag_image(const std::string& family, int id, int px) {
  const auto cells = tagbench::tag_cells(tagbench::builtin_family(family), id);
  const int n = cells.n + 2;
  cv::Mat m(n * px, n * px, CV_8UC1, cv::Scalar(255));
  for (int y = 0; y < cells.n; ++y)
    for (int x = 0; x < cells.n; ++x)
      if (!cells.at(y, x)) m(cv::Rect((x + 1) * px, (y + 1) * px, px, px)).setTo(0);
  return m;
}

std::string encode(const std::string& ext, const cv::Mat& m) {
  std::vector<std::uint8_t> buf;
  if (!cv::imencode(ext, m, buf)) throw std::runtime_error("cannot encode " + ext);
  return {buf.begin(), buf.end()};
}

std::string le16(std::uint16_t v) { return {static_cast<char>(v & 0xff), static_cast<char>(v >> 8)}; }
std::string f32(float v) {
  std::string s(4, '\0');
  std::memcpy(s.data(), &v, 4);
  return s;
}

// fuzz_detector's header (see fuzz_detector.cpp) followed by the pixels.
std::string detector_input(std::uint8_t o1, std::uint8_t o2, const cv::Mat& m, const std::string& camera = "") {
  std::string s;
  s += static_cast<char>(o1);
  s += static_cast<char>(o2);
  s += le16(static_cast<std::uint16_t>(m.cols)) + le16(static_cast<std::uint16_t>(m.rows)) + camera;
  if (!m.empty()) s.append(reinterpret_cast<const char*>(m.data), m.total() * m.elemSize());
  return s;
}

void detector_seeds() {
  const cv::Mat tag = tag_image("36h11", 0, 3);  // 36 x 36
  put("detector", "tag36h11_gray8", detector_input(0, 0, tag));
  cv::Mat t16;
  tag_image("16h5", 3, 3).convertTo(t16, CV_16U, 257);
  put("detector", "tag16h5_gray16", detector_input(1 | (1 << 4) | (2 << 6), 0, t16));
  cv::Mat bgr;
  cv::cvtColor(tag, bgr, cv::COLOR_GRAY2BGR);
  put("detector", "tag36h11_bgr_workspace", detector_input(2, 16 | 32, bgr));
  cv::Mat f;
  tag.convertTo(f, CV_32F, 1.0 / 255);
  put("detector", "tag36h11_float_half", detector_input(4 | 8, 4, f));
  const std::string camera = f32(60) + f32(60) + f32(18) + f32(18) + f32(0.1f);
  const std::string distortion = f32(0.1f) + f32(-0.05f) + f32(0) + f32(0) + f32(0);
  put("detector", "tag36h11_pose", detector_input(0, 1 | 2, tag, camera + distortion));
  put("detector", "thin_1x300", detector_input(0, 0, cv::Mat(300, 1, CV_8UC1, cv::Scalar(90))));
  put("detector", "one_pixel", detector_input(0, 0, cv::Mat(1, 1, CV_8UC1, cv::Scalar(0))));
  put("detector", "empty_0x0", detector_input(0, 0, cv::Mat()));
  put("detector", "over_max_pixels", detector_input(0, 64, tag));
}

void image_file_seeds() {
  const cv::Mat tag = tag_image("36h11", 7, 1);  // 12 x 12, 1 pixel per cell as `tagbench render`
  put("image_file", "tag.png", encode(".png", tag));
  put("image_file", "tag.pgm", encode(".pgm", tag));
  put("image_file", "tag.bmp", encode(".bmp", tag));
  put("image_file", "tag.tiff", encode(".tiff", tag));
  const std::string jpg = encode(".jpg", tag_image("36h11", 7, 2));
  put("image_file", "tag.jpg", jpg);
  put("image_file", "tag_truncated.jpg", jpg.substr(0, jpg.size() / 2));
  cv::Mat t16;
  tag.convertTo(t16, CV_16U, 257);
  put("image_file", "tag16.png", encode(".png", t16));
  cv::Mat bgra;
  cv::cvtColor(tag, bgra, cv::COLOR_GRAY2BGRA);
  put("image_file", "tag_rgba.png", encode(".png", bgra));
  cv::Mat f;
  tag.convertTo(f, CV_32F, 1.0 / 255);
  put("image_file", "tag.pfm", encode(".pfm", f));
}

void family_seeds() {
  put("family", "tag16h5.fam", tagbench::format_family(tagbench::builtin_family("16h5")));
  tagbench::FamilyInfo info;
  info.name = "9h3";
  info.bits = 9;
  info.min_hamming = 3;
  info.min_complexity = 2;
  info.seed = 90302;
  info.order = "lex";
  info.generator = "tagbench-lexicode 1";
  put("family", "tag9h3.fam", tagbench::format_family(tagbench::TagFamily(info, {0x1f, 0x0a3}, true),
                                                      {"total: candidates=512 wall_seconds=0.0"}));
  tagbench::LexicodeParams params;
  params.bits = 16;
  params.min_hamming = 5;
  params.min_complexity = 5;
  tagbench::LexicodeState state;
  state.next_index = 1234;
  state.codes = {0x231b, 0x2ea5};
  state.elapsed_seconds = 1.5;
  put("family", "partial.ckpt", tagbench::format_checkpoint(params, state));
}

std::string words(const std::vector<std::string>& w) {
  std::string s;
  for (std::size_t i = 0; i < w.size(); ++i) s += (i ? std::string(1, '\0') : "") + w[i];
  return s;
}

void args_seeds() {
  // Specs (count, then name index and flags per spec; see fuzz_args.cpp): detect's options.
  const std::string detect_specs = std::string("\x06", 1) + std::string("\x00\x03", 2) + "\x01\x01" + "\x02\x01" +
                                   "\x03\x01" + std::string("\x04\x00", 2) + "\x08\x05";
  put("args", "detect", detect_specs + words({"img.png", "--family", "36h11", "--family=16h5", "--max-hamming", "2",
                                              "--camera", "500,500,319.5,239.5", "--tag-size=0.166", "--half-res",
                                              "-o", "out.json", "--", "--not-an-option"}));
  put("args", "unknown_option", detect_specs + words({"--bogus", "1"}));
  put("args", "missing_value", detect_specs + words({"--max-hamming"}));
  put("args", "no_specs", std::string("\x00", 1) + words({"a", "b", "-", "--"}));
  // Numbers fill DetectorOptions' fields in fuzz_args.cpp's table order: valid values, then bad ones.
  put("args", "detector_options",
      std::string("\x00", 1) + words({"1", "0.5", "0.8", "0", "0.004", "0.5", "100", "100", "1200", "4", "4", "2",
                                       "6", "32", "-7", "-5", "10", "200000", "0.02", "500", "500", "319.5",
                                       "239.5", "0.166", "-0.2", "0.05", "0.001", "0.001", "0.01", "1000000"}));
  put("args", "detector_options_bad", std::string("\x00", 1) + words({"11", "nan", "-1", "inf", "1e300"}));
}

void manifest_seeds() {
  std::vector<tagbench::corpus::ManifestRow> rows = {
      {"stills/cimg-postcards/postcard1.png", "cimg-postcards", "cimg-doc", "3.2.1+dfsg-1",
       "/usr/share/doc/cimg-dev/html/img/postcard1.jpg", "CeCILL-C", std::string(64, 'a'), "still", -1},
      {"video/vtest/vtest_f10.png", "vtest", "opencv-doc", "4.6.0+dfsg-12",
       "/usr/share/doc/opencv-doc/examples/data/vtest.avi", "BSD-3-Clause", std::string(64, '0'), "video-frame", 10}};
  put("manifest", "manifest.tsv", tagbench::corpus::manifest_tsv(rows));
  put("manifest", "photo_sources.tsv",
      "group\tdebian_package\tversion\tpath_in_package\tlicense\n"
      "cimg-postcards\tcimg-doc\t3.2.1+dfsg-1\t/usr/share/doc/cimg-dev/html/img/postcard1.jpg\tCeCILL-C\n"
      "gcompris\tgcompris-qt-data\t3.1-1\t/_rcc/usr/share/gcompris-qt/rcc/a.rcc/x/y.webp\tGPL-3+\n");
  put("manifest", "video_sources.tsv",
      "group\tdebian_package\tversion\tpath_in_package\tframe_step\tlicense\n"
      "vtest\topencv-doc\t4.6.0+dfsg-12\t/usr/share/doc/opencv-doc/examples/data/vtest.avi\t10\tBSD-3-Clause\n"
      "frames\tsome-doc\t1.0-1\t/usr/share/doc/x/frame*.png\t2\tCC0\r\n");
}

void rcc_seeds() {
  rcctest::Writer w;
  w.add("images/plain.txt", "plain bytes");
  w.add("images/sub/zlib.bin", std::string(200, 'z'), rcctest::Pack::zlib);
  w.add("images/sub/zstd.bin", std::string(200, 's'), rcctest::Pack::zstd);
  w.add("\xc3\xa9t\xc3\xa9.png", "\x89PNG");
  for (std::uint32_t v = 1; v <= 3; ++v) put("rcc", "bundle_v" + std::to_string(v) + ".rcc", w.bytes(v));
  rcctest::Writer one;
  one.add("a", "x");
  put("rcc", "one_file_v1.rcc", one.bytes(1));
}

void candidate_seeds() {
  using namespace tagbench::corpus;
  CandidateStore s;
  s.settings = "detector=tagbench\nsigma=0.8\n";
  s.images.resize(2);
  s.images[0] = {"stills/a/one.png", "a", "still", 64, 48, 2, "ok", ""};
  s.images[1] = {"video/b/two_f3.png", "b", "video-frame", 0, 0, 0, "unreadable", "cannot decode"};
  s.quads = 2;
  CandidateRecord r;
  r.image = 0;
  r.d = 4;
  r.bits = 0xbeef;
  r.margin = 0.25f;
  r.corners = {{{1, 2}, {30, 2}, {30, 29}, {1, 29}}};
  s.records.push_back(r);
  r.d = 6;
  r.bits = 0xfffffffffULL;
  r.margin = 0.5f;
  s.records.push_back(r);
  put("candidates", "store.bin", encode_candidates(s));
  put("candidates", "index.tsv", candidate_index_tsv(s.images));
  const ShardInfo info{{1, 3}, 5, 12, 0x0123456789abcdefULL, 0xfedcba9876543210ULL};
  s.settings += shard_settings_lines(info);
  put("candidates", "shard_store.bin", encode_candidates(s));
  put("candidates", "shard.txt", "1/3");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT_DIR   (writes OUT_DIR/<target>/...)\n", argv[0]);
    return 2;
  }
  g_out = argv[1];
  detector_seeds();
  image_file_seeds();
  family_seeds();
  args_seeds();
  manifest_seeds();
  rcc_seeds();
  candidate_seeds();
  return 0;
}
