// Fuzz target: the Qt resource bundle reader (corpus_tools/rcc.hpp) that `tagbench corpus build`
// runs on the .rcc files of gcompris-qt-data; the whole input is the bundle.
//
// What must hold: RccArchive either opens or throws std::runtime_error "NAME: corrupt Qt resource
// bundle: ..." (one line); an opened bundle lists paths that start with '/' and have no empty,
// "." or ".." component, and reading them (entries(), read()) gives each file's bytes or the same
// kind of error, never more than the documented per-entry limit.
#include <cstdint>
#include <stdexcept>
#include <string>

#include "fuzz_util.hpp"
#include "rcc.hpp"

namespace {

void check_error(const std::runtime_error& e) {
  const std::string what = e.what();
  FUZZ_CHECK(what.rfind("fuzz.rcc: corrupt Qt resource bundle: ", 0) == 0, "unexpected error: " + what);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using tagbench::corpus::RccArchive;
  std::optional<RccArchive> rcc;
  try {
    rcc.emplace(std::string(reinterpret_cast<const char*>(data), size), "fuzz.rcc");
  } catch (const std::runtime_error& e) {
    check_error(e);
    return 0;
  }
  const auto paths = rcc->paths();
  for (const auto& p : paths) {
    FUZZ_CHECK(!p.empty() && p[0] == '/', "path '" + p + "' is not absolute");
    FUZZ_CHECK(p.find("//") == std::string::npos && p.find("/./") == std::string::npos &&
                   p.find("/../") == std::string::npos && !p.ends_with("/.") && !p.ends_with("/.."),
               "path '" + p + "' has an empty, '.' or '..' component");
  }
  try {
    const auto entries = rcc->entries();
    FUZZ_CHECK(entries.size() == paths.size(), "entries() and paths() disagree");
    if (!entries.empty()) {
      const auto first = rcc->read(entries.front().path);
      FUZZ_CHECK(first.has_value(), "read() misses a listed path");
      // read() returns the first file of that path; a bundle may list one path twice.
      FUZZ_CHECK(*first == entries.front().data, "read() and entries() disagree");
    }
  } catch (const std::runtime_error& e) {
    check_error(e);
  }
  FUZZ_CHECK(!rcc->read("/no such path/\x01").has_value(), "read() found a path that cannot exist");
  return 0;
}
