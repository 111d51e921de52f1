// Fuzz target: the corpus's text lists (corpus_tools/sources.hpp): the built corpus's manifest.tsv
// (read by `tagbench corpus candidates` and the rebuild check) and the source lists
// photo_sources.tsv / video_sources.tsv (`corpus build --lists`). The whole input is given to both.
//
// What must hold: each parser returns rows or throws std::runtime_error "NAME:LINE: problem" (one
// line, naming the input); accepted manifest rows are written back by manifest_tsv() and read
// again unchanged; accepted source rows have the properties the build relies on (absolute path
// without "/../", a group that is one folder name, frame_step >= 1 exactly for video lists).
#include <cstdint>
#include <stdexcept>
#include <string>

#include "fuzz_util.hpp"
#include "sources.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tagbench::corpus;
  const std::string text(reinterpret_cast<const char*>(data), size);

  try {
    const auto rows = parse_manifest(text, "manifest.tsv");
    for (const auto& r : rows) {
      FUZZ_CHECK(!r.file.empty() && r.file[0] != '/' && r.file.find("..") == std::string::npos,
                 "file '" + r.file + "' escapes the corpus");
      FUZZ_CHECK((r.kind == "video-frame") == (r.frame >= 0), "kind and frame disagree");
    }
    std::string written;
    try {
      written = manifest_tsv(rows);
    } catch (const std::runtime_error&) {
      // A field holding '\r' is read (only a trailing one is stripped) but refused on writing.
      bool has_cr = false;
      for (const auto& r : rows)
        for (const auto* s : {&r.file, &r.group, &r.package, &r.version, &r.path, &r.licence})
          has_cr = has_cr || s->find('\r') != std::string::npos;
      FUZZ_CHECK(has_cr, "manifest_tsv refused rows parse_manifest accepted");
      return 0;
    }
    try {
      FUZZ_CHECK(parse_manifest(written, "again") == rows, "manifest rows changed through manifest_tsv");
    } catch (const std::runtime_error& e) {
      fuzz::check_failed("parse_manifest(manifest_tsv(rows))", __FILE__, __LINE__, e.what());
    }
  } catch (const std::runtime_error& e) {
    fuzz::check_error_names(e, "manifest.tsv");
  }

  try {
    const auto sources = parse_sources(text, "sources.tsv");
    for (const auto& s : sources) {
      FUZZ_CHECK(!s.path.empty() && s.path[0] == '/' && s.path.find("/../") == std::string::npos,
                 "path '" + s.path + "' escapes the package");
      FUZZ_CHECK(!s.group.empty() && s.group.find('/') == std::string::npos && s.group[0] != '.',
                 "group '" + s.group + "' is not a folder name");
      FUZZ_CHECK(s.frame_step >= 0, "negative frame step");
    }
  } catch (const std::runtime_error& e) {
    fuzz::check_error_names(e, "sources.tsv");
  }
  return 0;
}
