#pragma once
// The family file format, read by every `tagbench family` command and written by the generator.
//
//   # tagbench family file            (lines starting with # are comments)
//   name: 36h11
//   bits: 36
//   hamming: 11
//   complexity: 10
//   seed: 361110                      (generated families)
//   order: prime                      (generated families: prime | lex)
//   generator: tagbench-lexicode 1
//   count: 587
//   0xd5d628584                       (then one hex code a line, 0x optional, AprilTag 1 order)
//
// A lexicode checkpoint has the same shape plus `status: partial`, `next_index` and
// `elapsed_seconds`; it is never accepted as a family.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "codes/lexicode.hpp"
#include "codes/tag_family.hpp"

namespace tagbench {

// Parses a family; `source` names the input in errors ("FILE:LINE: problem"). Checks count,
// range, duplicates and the minimum distance.
TagFamily parse_family(const std::string& text, const std::string& source);
TagFamily read_family_file(const std::filesystem::path& path);

// The family as a file; `comments` are written as "# " lines after the first (generation records).
std::string format_family(const TagFamily& family, const std::vector<std::string>& comments = {});
// The family as a C++ source fragment (a constexpr array in AprilTag 1 order).
std::string format_family_cpp(const TagFamily& family);

// Checkpoints of a generator run.
std::string format_checkpoint(const LexicodeParams& params, const LexicodeState& state);
struct Checkpoint {
  LexicodeParams params;
  LexicodeState state;
};
Checkpoint read_checkpoint(const std::filesystem::path& path);

// "0x1f" or "1f" -> value; nullopt if not a hex number that fits in 64 bits.
std::optional<Code> parse_hex_code(const std::string& token);

}  // namespace tagbench
