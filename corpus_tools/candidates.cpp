#include "candidates.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <thread>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "detect/detector_opencv.hpp"
#include "detect/find_quads_in_image.hpp"
#include "detect/homography.hpp"
#include "detect/payload_decode.hpp"
#include "scan.hpp"
#include "sources.hpp"
#include "tools/atomic_file.hpp"
#include "tools/hash.hpp"

namespace fs = std::filesystem;

namespace tagbench::corpus {
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

std::string clean(std::string s) {
  for (char& c : s)
    if (c == '\t' || c == '\n' || c == '\r') c = ' ';
  return s;
}

const char* rule_name(CloseEnoughRule r) {
  switch (r) {
    case CloseEnoughRule::kPaper2011: return "paper2011";
    case CloseEnoughRule::kCode2010: return "code2010";
    case CloseEnoughRule::kCode2012: return "code2012";
  }
  return "?";
}

}  // namespace

std::vector<CandidateRecord> image_candidates(const ImageF& gray, std::uint32_t image_id, const DetectorOptions& opt,
                                              std::size_t* quad_count) {
  if (gray.empty()) throw std::invalid_argument("empty image");
  if (static_cast<long long>(gray.width) * gray.height > opt.max_pixels)
    throw std::invalid_argument("image " + std::to_string(gray.width) + "x" + std::to_string(gray.height) +
                                " is over the memory limit of " + std::to_string(opt.max_pixels) + " pixels");
  // The detector's stages 1-5, the same function Detector::detect calls.
  DetectorWorkspace workspace;
  const FoundQuads found = find_quads_in_image(gray, opt, workspace);
  const std::vector<Quad>& quads = found.quads;
  const ImageF& decode_image = *found.decode_image;
  if (quad_count) *quad_count = quads.size();

  // The detector's border pre-filter (PayloadOptions::quick_reject) is NOT applied here: the
  // paper's false-positive measurement counts every candidate quad whose payload can be read, so
  // every quad goes to read_payload. read_payload itself still refuses a quad whose cells leave
  // the image or whose border gives no usable (contrasting) model.
  const PayloadOptions& payload = opt.payload;
  std::vector<CandidateRecord> out;
  out.reserve(quads.size() * kCandidateWidths.size());
  for (const Quad& q : quads) {
    const auto H = tag_homography(q.corners);
    if (!H) continue;
    CandidateRecord r;
    r.image = image_id;
    for (std::size_t i = 0; i < 4; ++i)
      r.corners[i] = {static_cast<float>(q.corners[i].x()), static_cast<float>(q.corners[i].y())};
    for (const int d : kCandidateWidths) {
      const auto reading = read_payload(decode_image, *H, d, payload, false);
      if (!reading) continue;
      r.d = static_cast<std::uint8_t>(d);
      r.bits = reading->bits;
      r.margin = static_cast<float>(reading->margin);
      out.push_back(r);
    }
  }
  return out;
}

std::string candidate_settings(const DetectorOptions& o) {
  std::ostringstream s;
  s.precision(17);
  s << "stages=blur,gradient,segmentation,line_fit,quad_search,read_payload(no quick_reject)\n"
    << "widths=4,5,6\n"
    << "seg_sigma=" << o.seg_sigma << "\n"
    << "decode_sigma=" << o.decode_sigma << "\n"
    << "half_resolution=" << (o.half_resolution ? 1 : 0) << "\n"
    << "min_mag=" << o.segmentation.min_mag << "\n"
    << "max_edge_cost=" << o.segmentation.max_edge_cost << "\n"
    << "weight_scale=" << o.segmentation.weight_scale << "\n"
    << "k_theta=" << o.segmentation.k_theta << "\n"
    << "k_mag=" << o.segmentation.k_mag << "\n"
    << "min_cluster_size=" << o.segmentation.min_cluster_size << "\n"
    << "min_length=" << o.line_fit.min_length << "\n"
    << "close_enough=" << rule_name(o.quad_search.close_enough) << "\n"
    << "min_tag_size=" << o.quad_search.min_tag_size << "\n"
    << "max_aspect=" << o.quad_search.max_aspect << "\n"
    << "winding=" << o.quad_search.winding_min << "," << o.quad_search.winding_max << "\n"
    << "grid_cell=" << o.quad_search.grid_cell << "\n"
    << "max_quads=" << o.quad_search.max_quads << "\n"
    << "segments_on_sides=" << (o.quad_search.segments_on_sides ? 1 : 0) << "\n"
    << "min_contrast=" << o.payload.min_contrast << "\n";
  return s.str();
}

std::vector<CandidateImage> corpus_images(const fs::path& dir) {
  if (!fs::is_directory(dir)) throw std::runtime_error(dir.string() + ": no such directory");
  std::vector<CandidateImage> out;
  const fs::path manifest = dir / "manifest.tsv";
  if (fs::exists(manifest)) {
    for (const auto& row : parse_manifest(read_file(manifest), manifest.string())) {
      CandidateImage i;
      i.file = row.file;
      i.group = row.group;
      i.kind = row.kind;
      out.push_back(std::move(i));
    }
    return out;
  }
  // Listed, not decoded: the extraction decodes each image anyway (and records its size), and every
  // shard lists the whole folder, so a decoding scan would cost each shard as much as the work.
  const FolderScan scan = list_image_files(dir);
  for (const auto& s : scan.images) {
    CandidateImage i;
    i.file = fs::relative(s.file, dir).generic_string();
    i.kind = "still";
    out.push_back(std::move(i));
  }
  for (const auto& u : scan.unreadable) {  // listed, so the index accounts for every file
    CandidateImage i;
    i.file = fs::relative(u.file, dir).generic_string();
    i.kind = "still";
    i.status = "unreadable";
    i.reason = u.reason;
    out.push_back(std::move(i));
  }
  // Files named corpus_candidates* at the top are this program's own (the default stores and their
  // temporaries). Shards running at once into the folder would otherwise list a temporary that has
  // vanished by the time it is opened as an unreadable row the other shards lack.
  std::erase_if(out, [](const CandidateImage& i) {
    return i.file.find('/') == std::string::npos && i.file.rfind("corpus_candidates", 0) == 0;
  });
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.file < b.file; });
  return out;
}

CandidateStore extract_candidates(const fs::path& dir, std::vector<CandidateImage> images, const DetectorOptions& opt,
                                  int jobs, const std::function<void(const ExtractProgress&)>& progress) {
  if (images.size() > std::numeric_limits<std::uint32_t>::max()) throw std::runtime_error("too many images");
  CandidateStore store;
  store.settings = candidate_settings(opt);
  const std::size_t n = images.size();
  std::vector<std::vector<CandidateRecord>> per(n);
  std::atomic<std::size_t> next{0}, done{0};
  std::mutex mu;
  std::condition_variable wake;
  std::atomic<std::uint64_t> quads{0};
  auto work = [&] {
    for (;;) {
      const std::size_t i = next.fetch_add(1);
      if (i >= n) return;
      CandidateImage& im = images[i];
      if (im.status == "ok") {
        try {
          const cv::Mat m = cv::imread((dir / im.file).string(), cv::IMREAD_UNCHANGED);
          if (m.empty()) throw std::runtime_error("cannot be decoded");
          im.width = m.cols;
          im.height = m.rows;
          std::size_t q = 0;
          per[i] = image_candidates(to_float_image(m), static_cast<std::uint32_t>(i), opt, &q);
          im.quads = q;
          quads += q;
        } catch (const std::exception& e) {
          im.status = "unreadable";
          im.reason = e.what();
          per[i].clear();
        }
      }
      {
        const std::lock_guard<std::mutex> lock(mu);
        ++done;
      }
      wake.notify_all();
    }
  };
  // `jobs` workers; the calling thread only reports progress.
  std::vector<std::thread> pool;
  for (int t = 0; t < std::max(1, jobs); ++t) pool.emplace_back(work);
  if (progress) {
    std::unique_lock<std::mutex> lock(mu);
    while (done.load() < n) {
      progress({done.load(), n, quads.load()});
      wake.wait_for(lock, std::chrono::milliseconds(250), [&] { return done.load() == n; });
    }
    lock.unlock();
    progress({n, n, quads.load()});
  }
  for (auto& t : pool) t.join();
  std::size_t total = 0;
  for (const auto& v : per) total += v.size();
  store.records.reserve(total);
  for (auto& v : per) {
    store.records.insert(store.records.end(), v.begin(), v.end());
    std::vector<CandidateRecord>().swap(v);
  }
  store.quads = quads.load();
  store.images = std::move(images);
  return store;
}

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

Shard parse_shard(const std::string& text) {
  const auto bad = [&](const std::string& why) -> void { throw std::invalid_argument("'" + text + "': " + why); };
  const auto slash = text.find('/');
  const auto number = [&](std::string_view part) {
    std::uint64_t v = 0;
    // Digits only (no sign, space or trailing text); from_chars then fails only on overflow.
    const bool digits =
        !part.empty() && std::all_of(part.begin(), part.end(), [](char c) { return c >= '0' && c <= '9'; });
    const auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), v);
    if (!digits || ec != std::errc() || end != part.data() + part.size())
      bad("not of the form i/N (shard i of N, counted from 0)");
    return v;
  };
  if (slash == std::string::npos) bad("not of the form i/N (shard i of N, counted from 0)");
  const std::string_view all(text);
  Shard s{number(all.substr(0, slash)), number(all.substr(slash + 1))};
  if (s.count < 1) bad("N must be at least 1");
  if (s.index >= s.count) bad("i must be below N (shards are numbered 0 to N-1)");
  return s;
}

std::pair<std::size_t, std::size_t> shard_range(std::size_t images, Shard s) {
  if (s.count < 1 || s.index >= s.count)
    throw std::invalid_argument("shard " + std::to_string(s.index) + "/" + std::to_string(s.count) + " out of range");
  // 128-bit products: i * M can exceed 64 bits for absurd N, and the block edges must be exact.
  const auto edge = [&](std::uint64_t i) {
    return static_cast<std::size_t>(static_cast<unsigned __int128>(i) * images / s.count);
  };
  return {edge(s.index), edge(s.index + 1)};
}

std::uint64_t image_list_hash(const std::vector<CandidateImage>& images, std::size_t first, std::size_t last) {
  if (first > last || last > images.size()) throw std::invalid_argument("image_list_hash: rows out of range");
  // Hashed as the index stores the fields (clean), so a list read back from a .tsv hashes the same.
  std::string text;
  for (std::size_t i = first; i < last; ++i)
    text += images[i].file + "\t" + clean(images[i].group) + "\t" + clean(images[i].kind) + "\n";
  return fnv1a64(text);
}

namespace {
constexpr std::array<const char*, 5> kShardKeys = {"shard", "shard_first_row", "corpus_images", "corpus_list_fnv1a",
                                                   "shard_list_fnv1a"};

std::string hex64(std::uint64_t v) {
  char b[17];
  std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(v));
  return b;
}
}  // namespace

std::string shard_settings_lines(const ShardInfo& i) {
  return std::string(kShardKeys[0]) + "=" + std::to_string(i.shard.index) + "/" + std::to_string(i.shard.count) +
         "\n" + kShardKeys[1] + "=" + std::to_string(i.first_row) + "\n" + kShardKeys[2] + "=" +
         std::to_string(i.corpus_images) + "\n" + kShardKeys[3] + "=" + hex64(i.corpus_list) + "\n" + kShardKeys[4] +
         "=" + hex64(i.shard_list) + "\n";
}

std::optional<ShardInfo> parse_shard_settings(const std::string& settings, const std::string& name,
                                              std::string* detector_settings) {
  // The shard lines are the tail of the settings, starting at the line "shard=...".
  std::size_t at = settings.rfind("\nshard=");
  at = at != std::string::npos ? at + 1 : settings.rfind("shard=", 0) == 0 ? 0 : std::string::npos;
  if (at == std::string::npos) return std::nullopt;
  const auto fail = [&](const std::string& why) -> void {
    throw std::runtime_error(name + ": malformed shard lines in the settings (" + why + ")");
  };
  std::vector<std::string> values;
  std::istringstream in(settings.substr(at));
  std::string line;
  while (std::getline(in, line)) {
    if (values.size() == kShardKeys.size()) fail("unexpected line '" + line + "'");
    const std::string key = std::string(kShardKeys[values.size()]) + "=";
    if (line.rfind(key, 0) != 0) fail("expected " + key + "..., found '" + line + "'");
    values.push_back(line.substr(key.size()));
  }
  if (values.size() != kShardKeys.size() || settings.back() != '\n') fail("incomplete");
  const auto number = [&](const std::string& v, int base) {
    std::uint64_t x = 0;
    const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), x, base);
    if (v.empty() || ec != std::errc() || end != v.data() + v.size() || v[0] == '-' || v[0] == '+')
      fail("bad number '" + v + "'");
    return x;
  };
  ShardInfo info;
  try {
    info.shard = parse_shard(values[0]);
  } catch (const std::invalid_argument& e) {
    fail(std::string("shard=") + e.what());
  }
  info.first_row = number(values[1], 10);
  info.corpus_images = number(values[2], 10);
  info.corpus_list = number(values[3], 16);
  info.shard_list = number(values[4], 16);
  if (detector_settings) *detector_settings = settings.substr(0, at);
  return info;
}

CandidateStore extract_candidate_shard(const fs::path& dir, const std::vector<CandidateImage>& images, Shard s,
                                       const DetectorOptions& opt, int jobs,
                                       const std::function<void(const ExtractProgress&)>& progress) {
  // Ids of the merged store are u32 rows of the whole list, so the whole list must fit, not just the block.
  if (images.size() > std::numeric_limits<std::uint32_t>::max()) throw std::runtime_error("too many images");
  const auto [first, last] = shard_range(images.size(), s);
  const ShardInfo info{s, first, images.size(), image_list_hash(images, 0, images.size()),
                       image_list_hash(images, first, last)};
  CandidateStore store = extract_candidates(
      dir, std::vector<CandidateImage>(images.begin() + static_cast<std::ptrdiff_t>(first),
                                       images.begin() + static_cast<std::ptrdiff_t>(last)),
      opt, jobs, progress);
  store.settings += shard_settings_lines(info);
  return store;
}

CandidateStore merge_candidates(std::vector<CandidateStore> shards, const std::vector<std::string>& names) {
  const auto name = [&](std::size_t k) { return k < names.size() ? names[k] : "shard store " + std::to_string(k + 1); };
  const auto fail = [&](std::size_t k, const std::string& why) -> void {
    throw std::runtime_error(name(k) + ": " + why);
  };
  const auto shard_text = [](const Shard& s) { return std::to_string(s.index) + "/" + std::to_string(s.count); };
  if (shards.empty()) throw std::runtime_error("no shard stores to merge");

  std::vector<ShardInfo> info(shards.size());
  std::string base;
  for (std::size_t k = 0; k < shards.size(); ++k) {
    std::string settings;
    const auto i = parse_shard_settings(shards[k].settings, name(k), &settings);
    if (!i) fail(k, "not a shard store (no shard= line in its settings; made without --shard)");
    info[k] = *i;
    if (k == 0) {
      base = std::move(settings);
      continue;
    }
    const ShardInfo& a = info[0];
    if (settings != base) {
      // Name the first line that differs, so the user sees which option was changed.
      const auto lines = [](const std::string& t) {
        std::vector<std::string> v;
        std::istringstream in(t);
        for (std::string l; std::getline(in, l);) v.push_back(l);
        return v;
      };
      const auto lx = lines(settings), ly = lines(base);
      std::size_t d = 0;
      while (d < lx.size() && d < ly.size() && lx[d] == ly[d]) ++d;
      const auto at = [&](const std::vector<std::string>& v) { return d < v.size() ? "'" + v[d] + "'" : "no line"; };
      fail(k, "detector settings differ from " + name(0) + "'s (" + at(lx) + " against " + at(ly) + ")");
    }
    if (i->shard.count != a.shard.count)
      fail(k, "shard " + shard_text(i->shard) + ", but " + name(0) + " is shard " + shard_text(a.shard));
    if (i->corpus_images != a.corpus_images || i->corpus_list != a.corpus_list)
      fail(k, "made from a corpus list of " + std::to_string(i->corpus_images) + " images (list " +
                  hex64(i->corpus_list) + "), " + name(0) + " from one of " + std::to_string(a.corpus_images) +
                  " (list " + hex64(a.corpus_list) + "); the corpus changed between the shards' runs");
  }
  const std::uint64_t n = info[0].shard.count, total = info[0].corpus_images;
  if (total > std::numeric_limits<std::uint32_t>::max())
    fail(0, "corpus_images=" + std::to_string(total) + " is more than the store can index");

  // Each shard index once; the map keeps them in order whatever order the files came in.
  std::map<std::uint64_t, std::size_t> by_index;
  for (std::size_t k = 0; k < shards.size(); ++k) {
    const auto [it, fresh] = by_index.emplace(info[k].shard.index, k);
    if (!fresh) fail(k, "shard " + shard_text(info[k].shard) + " is also given as " + name(it->second));
  }
  if (by_index.size() != n) {
    std::uint64_t missing = 0;  // the first index without a store: the first gap in the ordered keys
    for (const auto& [index, k] : by_index) {
      if (index != missing) break;
      ++missing;
    }
    std::string given;
    for (std::size_t k = 0; k < shards.size() && k < 3; ++k) given += (k ? ", " : "") + name(k);
    if (shards.size() > 3) given += ", ...";
    throw std::runtime_error("shard " + std::to_string(missing) + "/" + std::to_string(n) + " is missing" +
                             (n - by_index.size() > 1 ? " (and " + std::to_string(n - by_index.size() - 1) + " more)"
                                                      : std::string()) +
                             ": " + std::to_string(by_index.size()) + " of " + std::to_string(n) +
                             " shards given (" + given + ")");
  }

  CandidateStore out;
  out.settings = base;
  out.images.reserve(static_cast<std::size_t>(total));
  std::size_t records = 0;
  for (const auto& s : shards) records += s.records.size();
  out.records.reserve(records);
  for (const auto& [index, k] : by_index) {
    CandidateStore& s = shards[k];
    const ShardInfo& i = info[k];
    const auto [first, last] = shard_range(static_cast<std::size_t>(total), i.shard);
    if (i.first_row != first || s.images.size() != last - first)
      fail(k, "shard " + shard_text(i.shard) + " of " + std::to_string(total) + " images must hold rows " +
                  std::to_string(first) + " to " + std::to_string(last) + " (exclusive); it holds " +
                  std::to_string(s.images.size()) + " images from row " + std::to_string(i.first_row));
    if (image_list_hash(s.images, 0, s.images.size()) != i.shard_list)
      fail(k, "its image index (.tsv) does not list the images the store was made from");
    std::uint64_t quads = 0;
    for (const auto& im : s.images) quads += im.quads;
    if (quads != s.quads)
      fail(k, "its image index counts " + std::to_string(quads) + " quads, the store " + std::to_string(s.quads));
    for (CandidateRecord r : s.records) {
      r.image += static_cast<std::uint32_t>(first);  // local row -> row of the whole list
      out.records.push_back(r);
    }
    std::vector<CandidateRecord>().swap(s.records);  // the merge would otherwise hold every record twice
    out.images.insert(out.images.end(), std::make_move_iterator(s.images.begin()),
                      std::make_move_iterator(s.images.end()));
    out.quads += s.quads;
  }
  // The blocks each matched their own hash; this guards the whole against a collision in the parts.
  if (image_list_hash(out.images, 0, out.images.size()) != info[0].corpus_list)
    fail(0, "the shards' images together are not the corpus list they were made from");
  return out;
}

FamilyScore score_family(const std::vector<CandidateRecord>& records, const TagFamily& family, int max_k, int jobs) {
  if (max_k < 0 || max_k > family.bits()) throw std::invalid_argument("max bits corrected out of range");
  const int d = family.payload_width();
  const std::size_t K = static_cast<std::size_t>(max_k);
  if (jobs <= 0) jobs = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const std::size_t n = records.size();
  const std::size_t chunk = 1 << 14;
  std::vector<std::vector<std::uint64_t>> hist(static_cast<std::size_t>(jobs), std::vector<std::uint64_t>(K + 2, 0));
  std::atomic<std::size_t> next{0};
  auto work = [&](std::vector<std::uint64_t>& h) {
    for (;;) {
      const std::size_t b = next.fetch_add(chunk);
      if (b >= n) return;
      const std::size_t e = std::min(n, b + chunk);
      for (std::size_t i = b; i < e; ++i) {
        const auto& r = records[i];
        if (r.d != d) continue;
        ++h[K + 1];  // records of this width
        // decode with max_k returns the nearest code's distance (the only one in reach when
        // max_k <= (h-1)/2), so decode(bits, k) accepts exactly when that distance is <= k.
        if (const auto dec = family.decode(r.bits, max_k)) ++h[static_cast<std::size_t>(dec->hamming)];
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < jobs; ++t) pool.emplace_back(work, std::ref(hist[static_cast<std::size_t>(t)]));
  work(hist[0]);
  for (auto& t : pool) t.join();
  FamilyScore s;
  s.accepted.assign(K + 1, 0);
  for (const auto& h : hist) {
    s.quads += h[K + 1];
    for (std::size_t k = 0; k <= K; ++k) s.accepted[k] += h[k];
  }
  for (std::size_t k = 1; k <= K; ++k) s.accepted[k] += s.accepted[k - 1];
  return s;
}

}  // namespace tagbench::corpus
