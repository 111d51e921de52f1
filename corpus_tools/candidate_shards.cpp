// Sharding a corpus (issue 5, section 4): shard ranges, the shard lines in a store's settings, a shard's
// extraction, and the merge of shard stores into the store of the whole corpus.
#include <algorithm>
#include <charconv>
#include <cstdio>
#include <limits>
#include <map>
#include <stdexcept>
#include <string_view>

#include "candidates.hpp"
#include "candidates_detail.hpp"
#include "tools/hash.hpp"

namespace fs = std::filesystem;

namespace tagbench::corpus {

using detail::clean;

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

}  // namespace tagbench::corpus
