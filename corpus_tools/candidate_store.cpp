// The candidate store: its .bin encoding and decoding, the .tsv image index, reading and writing the pair.
#include <bit>
#include <charconv>
#include <cstring>
#include <stdexcept>
#include <string_view>

#include "candidates.hpp"
#include "candidates_detail.hpp"
#include "tools/atomic_file.hpp"
#include "tools/hash.hpp"

namespace fs = std::filesystem;

namespace tagbench::corpus {

using detail::clean;

namespace {

static_assert(std::endian::native == std::endian::little, "the store is written little-endian");

constexpr char kMagic[8] = {'T', 'B', 'C', 'A', 'N', 'D', 'S', '\0'};
constexpr std::size_t kHeaderSize = 8 + 4 + 4 + 8 + 8 + 8 + 8 + 4;  // up to the settings text
constexpr std::size_t kRecordSize = 4 + 1 + 3 + 8 + 4 + 8 * 4;

template <class T>
void put(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out.append(b, sizeof(T));
}
template <class T>
T get(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

}  // namespace

std::string encode_candidates(const CandidateStore& s) {
  if (s.images.size() > kMaxCandidateImages)
    throw std::runtime_error("candidate store: " + std::to_string(s.images.size()) + " images, over the limit of " +
                             std::to_string(kMaxCandidateImages));
  std::string body;
  body.reserve(s.settings.size() + s.records.size() * kRecordSize);
  body += s.settings;
  for (const auto& r : s.records) {
    put<std::uint32_t>(body, r.image);
    put<std::uint8_t>(body, r.d);
    body.append(3, '\0');
    put<std::uint64_t>(body, r.bits);
    put<float>(body, r.margin);
    for (const auto& c : r.corners) {
      put<float>(body, c[0]);
      put<float>(body, c[1]);
    }
  }
  std::string out;
  out.reserve(kHeaderSize + body.size());
  out.append(kMagic, sizeof kMagic);
  put<std::uint32_t>(out, kCandidatesVersion);
  put<std::uint32_t>(out, static_cast<std::uint32_t>(kRecordSize));
  put<std::uint64_t>(out, s.images.size());
  put<std::uint64_t>(out, s.quads);
  put<std::uint64_t>(out, s.records.size());
  put<std::uint64_t>(out, fnv1a64(body));
  put<std::uint32_t>(out, static_cast<std::uint32_t>(s.settings.size()));
  out += body;
  return out;
}

CandidateStore decode_candidates(const std::string& bytes, const std::string& name) {
  const auto fail = [&](const std::string& why) -> void { throw std::runtime_error(name + ": " + why); };
  if (bytes.size() < kHeaderSize || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    fail(bytes.size() < kHeaderSize ? "too short for a candidate store header (" + std::to_string(bytes.size()) +
                                          " bytes)"
                                    : "not a candidate store (bad magic)");
  const char* p = bytes.data() + 8;
  const auto version = get<std::uint32_t>(p);
  const auto record_size = get<std::uint32_t>(p + 4);
  const auto n_images = get<std::uint64_t>(p + 8);
  const auto n_quads = get<std::uint64_t>(p + 16);
  const auto n_records = get<std::uint64_t>(p + 24);
  const auto checksum = get<std::uint64_t>(p + 32);
  const auto settings_len = get<std::uint32_t>(p + 40);
  if (version != kCandidatesVersion)
    fail("version " + std::to_string(version) + ", this program reads version " + std::to_string(kCandidatesVersion));
  if (record_size != kRecordSize)
    fail("record size " + std::to_string(record_size) + ", expected " + std::to_string(kRecordSize));
  const std::uint64_t avail = bytes.size() - kHeaderSize;
  if (settings_len > avail || n_records > (avail - settings_len) / kRecordSize ||
      settings_len + n_records * kRecordSize != avail)
    fail("size " + std::to_string(bytes.size()) + " bytes does not match the header (" + std::to_string(n_records) +
         " records of " + std::to_string(kRecordSize) + " bytes); truncated or damaged");
  if (fnv1a64(std::string_view(bytes.data() + kHeaderSize, avail)) != checksum)
    fail("checksum mismatch; the file is damaged");
  if (n_images > kMaxCandidateImages)
    fail("image count " + std::to_string(n_images) + " is over the limit of " + std::to_string(kMaxCandidateImages));
  CandidateStore s;
  s.settings.assign(bytes.data() + kHeaderSize, settings_len);
  s.images.resize(static_cast<std::size_t>(n_images));
  s.quads = n_quads;
  s.records.resize(static_cast<std::size_t>(n_records));
  const char* r = bytes.data() + kHeaderSize + settings_len;
  for (std::size_t i = 0; i < s.records.size(); ++i, r += kRecordSize) {
    CandidateRecord& c = s.records[i];
    c.image = get<std::uint32_t>(r);
    c.d = get<std::uint8_t>(r + 4);
    c.bits = get<std::uint64_t>(r + 8);
    c.margin = get<float>(r + 16);
    for (std::size_t k = 0; k < 4; ++k) c.corners[k] = {get<float>(r + 20 + 8 * k), get<float>(r + 24 + 8 * k)};
    const bool ok_d = std::find(kCandidateWidths.begin(), kCandidateWidths.end(), c.d) != kCandidateWidths.end();
    bool finite = std::isfinite(c.margin);
    for (const auto& k : c.corners) finite = finite && std::isfinite(k[0]) && std::isfinite(k[1]);
    if (!ok_d || c.image >= n_images || r[5] || r[6] || r[7] || (ok_d && (c.bits & ~low_mask(c.d * c.d))) || !finite ||
        (i > 0 && c.image < s.records[i - 1].image))
      fail("record " + std::to_string(i) + " is invalid");
  }
  return s;
}

std::string candidate_index_tsv(const std::vector<CandidateImage>& images) {
  std::string out = "id\tfile\tgroup\tkind\twidth\theight\tquads\tstatus\treason\n";
  for (std::size_t i = 0; i < images.size(); ++i) {
    const auto& m = images[i];
    if (m.file.find_first_of("\t\n\r") != std::string::npos)
      throw std::runtime_error("file name with a tab or newline: " + clean(m.file));
    out += std::to_string(i) + "\t" + m.file + "\t" + clean(m.group) + "\t" + clean(m.kind) + "\t" +
           std::to_string(m.width) + "\t" + std::to_string(m.height) + "\t" + std::to_string(m.quads) + "\t" +
           m.status + "\t" + clean(m.reason) + "\n";
  }
  return out;
}

std::vector<CandidateImage> parse_candidate_index(const std::string& text, const std::string& name) {
  std::vector<CandidateImage> out;
  std::istringstream in(text);
  std::string line;
  int lineno = 0;
  const auto fail = [&](const std::string& why) -> void {
    throw std::runtime_error(name + ":" + std::to_string(lineno) + ": " + why);
  };
  while (std::getline(in, line)) {
    ++lineno;
    std::vector<std::string> f;
    std::size_t start = 0;
    for (;;) {
      const auto tab = line.find('\t', start);
      f.push_back(line.substr(start, tab == std::string::npos ? std::string::npos : tab - start));
      if (tab == std::string::npos) break;
      start = tab + 1;
    }
    if (f.size() != 9) fail("expected 9 columns, found " + std::to_string(f.size()));
    if (lineno == 1) {
      if (f[0] != "id" || f[1] != "file") fail("not a candidate index header");
      continue;
    }
    try {
      if (std::stoull(f[0]) != out.size()) fail("id " + f[0] + " out of sequence");
      CandidateImage m;
      m.file = f[1];
      m.group = f[2];
      m.kind = f[3];
      m.width = std::stoi(f[4]);
      m.height = std::stoi(f[5]);
      m.quads = std::stoull(f[6]);
      m.status = f[7];
      m.reason = f[8];
      if (m.status != "ok" && m.status != "unreadable") fail("bad status '" + m.status + "'");
      out.push_back(std::move(m));
    } catch (const std::logic_error&) {
      fail("bad number");
    }
  }
  if (lineno == 0) fail("empty index");
  return out;
}

fs::path candidate_index_path(const fs::path& bin) {
  fs::path p = bin;
  p.replace_extension(".tsv");
  if (p == bin) p += ".tsv";
  return p;
}

void write_candidates(const fs::path& bin, const CandidateStore& s) {
  // As a pair: a failed write (a full disk) must not leave a new index beside an old or missing store.
  write_files_atomic({{candidate_index_path(bin), candidate_index_tsv(s.images)}, {bin, encode_candidates(s)}});
}

CandidateStore read_candidates(const fs::path& bin, bool with_index) {
  CandidateStore s = decode_candidates(read_file(bin), bin.string());
  if (with_index) {
    const fs::path idx = candidate_index_path(bin);
    auto images = parse_candidate_index(read_file(idx), idx.string());
    if (images.size() != s.images.size())
      throw std::runtime_error(idx.string() + ": " + std::to_string(images.size()) + " images, the store says " +
                               std::to_string(s.images.size()));
    s.images = std::move(images);
  }
  return s;
}

}  // namespace tagbench::corpus
