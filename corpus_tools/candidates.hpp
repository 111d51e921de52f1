#pragma once
// Candidate quads and their payloads (issue 5, section 2): the detector's stages up to and
// including the quad search on every corpus image, and for every candidate quad the d x d payload
// grid read for d = 4, 5 and 6 with the detector's spatially varying threshold. Stored once per
// corpus; any family is then scored from the stored bits in seconds (the paper's Figs. 6 and 7).
//
// The store (corpus_candidates.bin), all integers and floats little-endian:
//   header  "TBCANDS\0" magic, u32 version, u32 record size, u64 images, u64 quads, u64 records,
//           u64 FNV-1a 64 of everything after the header, u32 settings length, settings text
//   records fixed size: u32 image, u8 d, 3 zero bytes, u64 bits, f32 margin, 8 x f32 corners (x, y)
// and beside it an index of the images (corpus_candidates.tsv): id, file, group, kind, width,
// height, quads, status, reason.
#include <array>
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "codes/bits.hpp"
#include "codes/tag_family.hpp"
#include "detect/detector.hpp"
#include "detect/image.hpp"

namespace tagbench::corpus {

inline constexpr std::uint32_t kCandidatesVersion = 1;
inline constexpr std::array<int, 3> kCandidateWidths = {4, 5, 6};

struct CandidateRecord {
  std::uint32_t image = 0;  // row of the image index
  std::uint8_t d = 0;       // payload width read
  Code bits = 0;            // AprilTag 1 order as seen from corner 0 (payload_decode.hpp)
  float margin = 0;         // PayloadReading::margin
  std::array<std::array<float, 2>, 4> corners{};  // the quad's corners (quad_search.hpp order), pixels
  bool operator==(const CandidateRecord&) const = default;
};

// The candidate records of one image (already grey, [0, 1]): blur, gradients, segmentation, line
// fit and quad search exactly as Detector::detect with `opt`, then read_payload for d = 4, 5, 6
// (quads whose payload cannot be read at some d get no record for that d). `quads`, if given,
// receives the number of candidate quads.
std::vector<CandidateRecord> image_candidates(const ImageF& gray, std::uint32_t image_id,
                                              const DetectorOptions& opt = {}, std::size_t* quads = nullptr);

// The detector settings that shape the candidates, as "key=value" lines (stored in the header).
std::string candidate_settings(const DetectorOptions& opt);

struct CandidateImage {
  std::string file;                 // relative to the corpus folder
  std::string group, kind;          // from the manifest ("" and "still" for a scanned folder)
  int width = 0, height = 0;
  std::uint64_t quads = 0;
  std::string status = "ok";        // "ok" or "unreadable"
  std::string reason;
  bool operator==(const CandidateImage&) const = default;
};

struct CandidateStore {
  std::string settings;
  std::vector<CandidateImage> images;
  std::vector<CandidateRecord> records;  // sorted by image, then quad, then d
  std::uint64_t quads = 0;               // candidate quads over all images
};

// The images of a corpus: DIR/manifest.tsv if there is one, else every image under DIR (scan.hpp).
std::vector<CandidateImage> corpus_images(const std::filesystem::path& dir);

struct ExtractProgress {
  std::size_t images_done = 0, images_total = 0;
  std::uint64_t quads = 0;
};

// Runs image_candidates over the images on `jobs` threads. The result does not depend on `jobs`.
// `progress`, if given, is called from the calling thread now and then.
CandidateStore extract_candidates(const std::filesystem::path& dir, std::vector<CandidateImage> images,
                                  const DetectorOptions& opt, int jobs,
                                  const std::function<void(const ExtractProgress&)>& progress = {});

std::string encode_candidates(const CandidateStore& s);  // the .bin bytes (images: only their count)
std::string candidate_index_tsv(const std::vector<CandidateImage>& images);
// Writes `bin` and the index beside it (bin with extension .tsv), both atomically.
void write_candidates(const std::filesystem::path& bin, const CandidateStore& s);
std::filesystem::path candidate_index_path(const std::filesystem::path& bin);

// Reads a store; `name` for errors. Throws std::runtime_error with one line "NAME: problem" when
// the magic, version, sizes, checksum or a record is wrong. The images are only counted (their
// entries are default), unless the index is read too (read_candidates with the path).
CandidateStore decode_candidates(const std::string& bytes, const std::string& name);
CandidateStore read_candidates(const std::filesystem::path& bin, bool with_index = true);
std::vector<CandidateImage> parse_candidate_index(const std::string& text, const std::string& name);

// Scoring: for k = 0..max_k, how many records of payload width family.payload_width() decode with
// hamming <= k, exactly TagFamily::decode(bits, k) != nullopt. One decode per record with max_k,
// bucketed by the returned hamming. For k <= (h-1)/2 at most one code is in reach, so bucketing is
// exact; above that decode picks the nearest code (lowest id on ties), whose distance is still the
// smallest, so "within k" remains decode(bits, k) != nullopt.
struct FamilyScore {
  std::uint64_t quads = 0;                // records of this payload width
  std::vector<std::uint64_t> accepted;    // accepted[k], cumulative in k
};
FamilyScore score_family(const std::vector<CandidateRecord>& records, const TagFamily& family, int max_k,
                         int jobs = 0);

}  // namespace tagbench::corpus
