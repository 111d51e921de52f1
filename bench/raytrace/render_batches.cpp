// The frame cache's batch files and their clean-up (render_batches.hpp).
#include "raytrace/render_batches.hpp"

#include <cstring>
#include <fstream>
#include <map>
#include <optional>
#include <string_view>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "raytrace/render.hpp"
#include "tools/atomic_file.hpp"

namespace tagbench::bench {

namespace fs = std::filesystem;

namespace {

// A PNG file ends with its IEND chunk; a half-written one does not (and is not handed to the decoder,
// whose libpng would print an error line for it).
bool ends_with_iend(const fs::path& png) {
  static constexpr unsigned char kIend[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xAE, 0x42, 0x60, 0x82};
  std::ifstream in(png, std::ios::binary);
  if (!in.seekg(-12, std::ios::end)) return false;
  char tail[12];
  if (!in.read(tail, 12)) return false;
  return std::memcmp(tail, kIend, 12) == 0;
}

}  // namespace

bool decodes_as_frame(const fs::path& png) {
  std::error_code ec;
  if (!fs::is_regular_file(png, ec) || !ends_with_iend(png)) return false;
  const cv::Mat m = cv::imread(png.string(), cv::IMREAD_UNCHANGED);
  return !m.empty() && m.cols == kRenderWidth && m.rows == kRenderHeight;
}

void write_batch_keys(const fs::path& dir, const std::string& batch, std::span<const std::string> keys) {
  std::string text;
  for (const auto& k : keys) text += k + "\n";
  write_file_atomic(dir / ("batch-" + batch + ".keys"), text);
}

namespace {

// The frame number of tmp-ID-NNN.png, or nullopt when `name` is not one of batch ID's images.
std::optional<std::size_t> frame_number(std::string_view name, const std::string& id) {
  const std::string prefix = "tmp-" + id + "-";
  if (name.size() <= prefix.size() + 4 || name.substr(0, prefix.size()) != prefix || !name.ends_with(".png"))
    return std::nullopt;
  const std::string_view digits = name.substr(prefix.size(), name.size() - prefix.size() - 4);
  if (digits.size() > 9) return std::nullopt;
  std::size_t k = 0;
  for (const char c : digits) {
    if (c < '0' || c > '9') return std::nullopt;
    k = k * 10 + static_cast<std::size_t>(c - '0');
  }
  return k;
}

std::vector<std::string> read_keys(const fs::path& file) {
  std::vector<std::string> keys;
  std::string text;
  try {
    text = read_file(file);
  } catch (const std::exception&) {
    return keys;
  }
  for (std::size_t pos = 0; pos < text.size();) {
    const auto nl = text.find('\n', pos);
    if (nl == std::string::npos) break;  // an unfinished last line is no key
    keys.push_back(text.substr(pos, nl - pos));
    pos = nl + 1;
  }
  return keys;
}

bool is_key(const std::string& k) {
  if (k.size() != 16) return false;
  for (const char c : k)
    if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
  return true;
}

}  // namespace

DeadBatchCleanup clear_dead_batches(const fs::path& dir) {
  DeadBatchCleanup r;
  std::error_code ec;
  std::vector<fs::path> dead;                           // every file of a dead batch
  std::map<std::string, std::vector<std::string>> keys;  // dead batch ID -> its keys
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string n = it->path().filename().string();
    std::string rest;
    if (n.rfind("batch-", 0) == 0) rest = n.substr(6);
    else if (n.rfind("tmp-", 0) == 0) rest = n.substr(4);
    else continue;
    if (!owner_prefix_is_gone(rest)) continue;
    dead.push_back(it->path());
    if (n.rfind("batch-", 0) == 0 && n.ends_with(".keys")) keys[rest.substr(0, rest.size() - 5)] = read_keys(it->path());
  }
  for (const auto& p : dead) {
    const std::string n = p.filename().string();
    for (const auto& [id, list] : keys) {
      const auto k = frame_number(n, id);
      if (!k || *k == 0 || *k > list.size() || !is_key(list[*k - 1])) continue;
      const fs::path frame = dir / ("frame-" + list[*k - 1] + ".png");
      std::error_code rec;
      if (!decodes_as_frame(frame) && decodes_as_frame(p)) {
        fs::rename(p, frame, rec);
        if (!rec) ++r.frames_kept;
      }
      break;
    }
  }
  for (const auto& p : dead) {
    std::error_code rec;
    if (fs::remove(p, rec)) ++r.files_removed;
  }
  r.files_removed += remove_stale_temporaries(dir);
  return r;
}

}  // namespace tagbench::bench
