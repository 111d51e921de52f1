// Fuzz target: the candidate store (corpus_tools/candidates.hpp) that `tagbench corpus score`,
// `corpus merge` and the false-positive experiments read: the binary store (decode_candidates),
// its image index (parse_candidate_index), the shard lines of its settings (parse_shard_settings)
// and the --shard option (parse_shard). The whole input is given to each.
//
// What must hold: each reader returns or throws its documented exception (std::runtime_error,
// std::invalid_argument for parse_shard) with one line naming the input; a store that decodes is
// encoded back to the same bytes; an index that parses is written back (candidate_index_tsv) and
// read again unchanged, or refused on writing for a file name holding '\r'.
#include <cstdint>
#include <stdexcept>
#include <string>

#include "candidates.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tagbench::corpus;
  const std::string bytes(reinterpret_cast<const char*>(data), size);

  try {
    const CandidateStore s = decode_candidates(bytes, "fuzz.bin");
    FUZZ_CHECK(encode_candidates(s) == bytes, "the store does not encode back to its bytes");
    for (const auto& r : s.records) FUZZ_CHECK(r.image < s.images.size(), "record of an image out of range");
    try {
      std::string detector_settings;
      if (const auto info = parse_shard_settings(s.settings, "fuzz.bin", &detector_settings)) {
        FUZZ_CHECK(info->shard.index < info->shard.count, "shard index out of range");
        FUZZ_CHECK(s.settings.starts_with(detector_settings), "detector settings are not the settings' head");
      }
    } catch (const std::runtime_error& e) {
      fuzz::check_error_names(e, "fuzz.bin");
    }
  } catch (const std::runtime_error& e) {
    fuzz::check_error_names(e, "fuzz.bin");
  }

  try {
    const auto images = parse_candidate_index(bytes, "fuzz.tsv");
    std::string written;
    try {
      written = candidate_index_tsv(images);
    } catch (const std::runtime_error&) {
      bool has_cr = false;
      for (const auto& m : images) has_cr = has_cr || m.file.find('\r') != std::string::npos;
      FUZZ_CHECK(has_cr, "candidate_index_tsv refused an index parse_candidate_index accepted");
      return 0;
    }
    // The writer blanks tabs and line ends in the text fields; a '\r' (the only one a line can
    // hold) becomes a space, so compare with that applied.
    auto expect = images;
    for (auto& m : expect)
      for (auto* f : {&m.group, &m.kind, &m.reason})
        for (char& c : *f)
          if (c == '\r') c = ' ';
    try {
      FUZZ_CHECK(parse_candidate_index(written, "again") == expect, "the index changed through candidate_index_tsv");
    } catch (const std::runtime_error& e) {
      fuzz::check_failed("parse_candidate_index(candidate_index_tsv(images))", __FILE__, __LINE__, e.what());
    }
  } catch (const std::runtime_error& e) {
    fuzz::check_error_names(e, "fuzz.tsv");
  }

  try {
    const std::string settings(bytes.data(), bytes.size());
    if (const auto info = parse_shard_settings(settings, "fuzz.settings"))
      FUZZ_CHECK(info->shard.index < info->shard.count, "shard index out of range");
  } catch (const std::runtime_error& e) {
    fuzz::check_error_names(e, "fuzz.settings");
  }

  try {
    const Shard s = parse_shard(bytes);
    FUZZ_CHECK(s.count >= 1 && s.index < s.count, "parse_shard accepted an out-of-range shard");
    const auto [first, last] = shard_range(1000, s);
    FUZZ_CHECK(first <= last && last <= 1000, "shard_range out of the list");
  } catch (const std::invalid_argument& e) {
    FUZZ_CHECK(std::string(e.what()).rfind("'", 0) == 0, std::string("unexpected error: ") + e.what());
  }
  return 0;
}
