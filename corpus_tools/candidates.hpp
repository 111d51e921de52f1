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
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "codes/bits.hpp"
#include "codes/tag_family.hpp"
#include "detect/detector.hpp"
#include "detect/image.hpp"

namespace tagbench::corpus {

inline constexpr std::uint32_t kCandidatesVersion = 1;
// The most images a store may count (2^22 = 4194304). A store is read whole into memory, with a
// default CandidateImage per counted image, so the reader refuses a larger count before
// allocating (a damaged count field would otherwise ask for up to 2^32 entries, about 700 GB), and
// the writer refuses to write a store it could not read back.
inline constexpr std::uint64_t kMaxCandidateImages = std::uint64_t{1} << 22;
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
                                              const DetectorOptions& opt = DetectorOptions::paper(), std::size_t* quads = nullptr);

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

// The images of a corpus: DIR/manifest.tsv if there is one, else every image file under DIR
// (list_image_files, scan.hpp: by extension and signature, nothing decoded; width and height are
// filled in by extract_candidates, which decodes each image once) but for files named
// corpus_candidates* directly in DIR (the stores this program writes there). Files that already
// fail the listing (no image signature, cannot be opened) are rows with status "unreadable".
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

// The .bin bytes (images: only their count). Throws std::runtime_error for more than
// kMaxCandidateImages images.
std::string encode_candidates(const CandidateStore& s);
std::string candidate_index_tsv(const std::vector<CandidateImage>& images);
// Writes `bin` and the index beside it (bin with extension .tsv) atomically as a pair: on failure
// neither is written (write_files_atomic).
void write_candidates(const std::filesystem::path& bin, const CandidateStore& s);
std::filesystem::path candidate_index_path(const std::filesystem::path& bin);

// Reads a store; `name` for errors. Throws std::runtime_error with one line "NAME: problem" when
// the magic, version, sizes, checksum, image count (over kMaxCandidateImages) or a record is wrong. The images are only counted (their
// entries are default), unless the index is read too (read_candidates with the path).
CandidateStore decode_candidates(const std::string& bytes, const std::string& name);
CandidateStore read_candidates(const std::filesystem::path& bin, bool with_index = true);
std::vector<CandidateImage> parse_candidate_index(const std::string& text, const std::string& name);

// Sharding (issue 5, section 4): a corpus too big for one machine is split into N shards, shard i
// being the contiguous block of rows [i*M/N, (i+1)*M/N) of corpus_images' M rows, so the shards in
// order are the whole list. A shard store is an ordinary store of its block (image ids local to it)
// whose settings text ends with these lines, which let a merge prove the shards fit together:
//   shard=i/N
//   shard_first_row=ROW          the block's first row in the corpus list
//   corpus_images=M
//   corpus_list_fnv1a=HEX        FNV-1a 64 of all M rows' "file TAB group TAB kind LF": same corpus?
//   shard_list_fnv1a=HEX         the same over the block's rows: does the .tsv index belong to it?
// merge_candidates checks them and re-bases the ids; its store is byte for byte the unsharded run's.
struct Shard {
  std::uint64_t index = 0, count = 1;  // shard `index` of `count`, 0 <= index < count
  bool operator==(const Shard&) const = default;
};
// "i/N" (decimal, 0 <= i < N); throws std::invalid_argument with a one-line reason.
Shard parse_shard(const std::string& text);
// The rows [first, second) of shard s of a list of `images` rows. Throws std::invalid_argument for
// a shard out of range.
std::pair<std::size_t, std::size_t> shard_range(std::size_t images, Shard s);

struct ShardInfo {
  Shard shard;
  std::uint64_t first_row = 0;
  std::uint64_t corpus_images = 0;
  std::uint64_t corpus_list = 0;  // hashes as described above
  std::uint64_t shard_list = 0;
  bool operator==(const ShardInfo&) const = default;
};
// FNV-1a 64 of rows [first, last) of `images` (file, group, kind; as the index stores them).
std::uint64_t image_list_hash(const std::vector<CandidateImage>& images, std::size_t first, std::size_t last);
// The shard lines above, to append to the detector settings.
std::string shard_settings_lines(const ShardInfo& info);
// Splits a store's settings: nullopt when there is no shard= line (an unsharded store); otherwise
// the shard's lines, and the detector settings before them into `detector_settings` if given.
// Throws std::runtime_error "NAME: problem" when the shard lines are malformed.
std::optional<ShardInfo> parse_shard_settings(const std::string& settings, const std::string& name,
                                              std::string* detector_settings = nullptr);

// extract_candidates over shard s of `images` (the whole corpus list), the shard lines appended
// to the settings.
CandidateStore extract_candidate_shard(const std::filesystem::path& dir, const std::vector<CandidateImage>& images,
                                       Shard s, const DetectorOptions& opt, int jobs,
                                       const std::function<void(const ExtractProgress&)>& progress = {});

// Joins shard stores (read with their index; any order) into the store of the whole corpus.
// Throws std::runtime_error with one line naming the file (names[k], or "shard store k+1" when
// names is short) when a store is not a shard, the detector settings, N, M or the corpus list
// differ, a shard is duplicated or missing, or a shard's rows or index do not fit its lines.
CandidateStore merge_candidates(std::vector<CandidateStore> shards, const std::vector<std::string>& names = {});

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
