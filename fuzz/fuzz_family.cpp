// Fuzz target: family files (detector/codes/family_io.hpp), the input being the file's text, as
// `tagbench family check FILE`, `--family FILE` and the detector read it; and, when the text says
// "partial", the same text as a generator checkpoint (`family generate --checkpoint FILE --resume`,
// read_checkpoint, which shares the header format and reads from a file).
//
// What must hold: parse_family() returns a family or throws std::invalid_argument with one line
// that names the input; an accepted family's numbers are the file's numbers (no silent
// truncation), it survives format_family() -> parse_family() unchanged, and every code decodes to
// itself at every rotation. The same for read_checkpoint(): its error names the file, its numbers
// (next_index included) are the file's, and format_checkpoint() -> read_checkpoint() keeps it.
#include <unistd.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>

#include "codes/bits.hpp"
#include "codes/family_io.hpp"
#include "codes/lexicode.hpp"
#include "fuzz_util.hpp"

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

// The value of `key` as the file states it, verbatim (trimmed); nullopt if absent.
std::optional<std::string> stated_text(const std::string& text, const std::string& key) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    line = trim(line);
    const auto colon = line.find(':');
    if (line.empty() || line[0] == '#' || colon == std::string::npos || trim(line.substr(0, colon)) != key) continue;
    return trim(line.substr(colon + 1));
  }
  return std::nullopt;
}

// The value of header key `key` as the file states it ("key: value", spaces around either), read
// independently of the parser, when it is a decimal integer.
std::optional<long long> stated(const std::string& text, const std::string& key) {
  const auto v = stated_text(text, key);
  if (!v) return std::nullopt;
  long long x = 0;
  const auto r = std::from_chars(v->data(), v->data() + v->size(), x);
  if (r.ec != std::errc() || r.ptr != v->data() + v->size()) return std::nullopt;
  return x;
}

void write(const std::filesystem::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << text;
  out.close();
  if (!out) fuzz::check_failed("write", __FILE__, __LINE__, "cannot write " + p.string());
}

// The checkpoint file of this process, removed when it goes out of scope (every fuzz run left one in
// the temporary folder).
struct CheckpointFile {
  std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("tagbench-fuzz-" + std::to_string(::getpid()) + ".ckpt");
  CheckpointFile() = default;
  CheckpointFile(const CheckpointFile&) = delete;
  CheckpointFile& operator=(const CheckpointFile&) = delete;
  ~CheckpointFile() {
    std::error_code ec;
    std::filesystem::remove(path, ec);
  }
};

void check_checkpoint(const std::string& text) {
  // Removed after each input (libFuzzer can end the process with _Exit, which runs no destructor).
  const CheckpointFile file;
  const std::filesystem::path& path = file.path;
  write(path, text);
  std::optional<tagbench::Checkpoint> c;
  try {
    c.emplace(tagbench::read_checkpoint(path));
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    FUZZ_CHECK(what.rfind(path.string(), 0) == 0 && what.find('\n') == std::string::npos,
               "the checkpoint error does not name the file on one line: " + what);
    return;
  }
  FUZZ_CHECK(stated(text, "bits") == c->params.bits, "checkpoint bits read as " + std::to_string(c->params.bits));
  FUZZ_CHECK(stated(text, "hamming") == c->params.min_hamming, "checkpoint hamming misread");
  FUZZ_CHECK(stated(text, "complexity") == c->params.min_complexity, "checkpoint complexity misread");
  std::string index = stated_text(text, "next_index").value_or("");
  index.erase(0, std::min(index.find_first_not_of('0'), index.size() - (index.empty() ? 0 : 1)));
  FUZZ_CHECK(index == tagbench::to_decimal(c->state.next_index),
             "next_index '" + index + "' read as " + tagbench::to_decimal(c->state.next_index));
  write(path, tagbench::format_checkpoint(c->params, c->state));
  try {
    const tagbench::Checkpoint again = tagbench::read_checkpoint(path);
    FUZZ_CHECK(again.params.bits == c->params.bits && again.params.min_hamming == c->params.min_hamming &&
                   again.params.seed == c->params.resolved_seed() && again.params.order == c->params.order &&
                   again.state.next_index == c->state.next_index && again.state.codes == c->state.codes,
               "the checkpoint changed through format_checkpoint and read_checkpoint");
    // Written as whole milliseconds.
    const double e = c->state.elapsed_seconds;
    FUZZ_CHECK(std::abs(again.state.elapsed_seconds - e) <= 1e-3 + 1e-12 * e,
               "elapsed_seconds " + std::to_string(e) + " written back as " + std::to_string(again.state.elapsed_seconds));
  } catch (const std::invalid_argument& e) {
    fuzz::check_failed("read_checkpoint(format_checkpoint(c))", __FILE__, __LINE__, e.what());
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::string source = "fuzz.fam";
  if (text.find("partial") != std::string::npos) check_checkpoint(text);
  std::optional<tagbench::TagFamily> fam;
  try {
    fam.emplace(tagbench::parse_family(text, source));
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    FUZZ_CHECK(what.rfind(source, 0) == 0, "the error does not name the input: " + what);
    return 0;
  }
  const auto& info = fam->info();
  FUZZ_CHECK(stated(text, "bits") == info.bits, "bits read as " + std::to_string(info.bits));
  FUZZ_CHECK(stated(text, "hamming") == info.min_hamming, "hamming read as " + std::to_string(info.min_hamming));
  FUZZ_CHECK(stated(text, "complexity") == info.min_complexity,
             "complexity read as " + std::to_string(info.min_complexity));

  const std::string written = tagbench::format_family(*fam);
  tagbench::TagFamily again = [&] {
    try {
      return tagbench::parse_family(written, "rewritten");
    } catch (const std::invalid_argument& e) {
      fuzz::check_failed("parse_family(format_family(f))", __FILE__, __LINE__, e.what());
    }
  }();
  FUZZ_CHECK(again.codes() == fam->codes() && again.info().name == info.name && again.bits() == info.bits &&
                 again.min_hamming() == info.min_hamming && again.info().seed == info.seed &&
                 again.info().order == info.order && again.info().generator == info.generator,
             "the family changed through format_family and parse_family");
  (void)tagbench::format_family_cpp(*fam);

  const int d = fam->payload_width();
  for (std::size_t id = 0; id < fam->size(); ++id) {
    tagbench::Code c = fam->codes()[id];
    for (int r = 0; r < 4; ++r, c = tagbench::rotate90(c, d)) {
      const auto hit = fam->decode(c, 0);
      FUZZ_CHECK(hit && hit->hamming == 0, "code " + std::to_string(id) + " does not decode");
      // With h = 0 a code may equal another's rotation (or its own), so only h >= 1 fixes id and rotation.
      if (fam->min_hamming() >= 1) {
        FUZZ_CHECK(static_cast<std::size_t>(hit->id) == id && hit->rotation == r,
                   "code " + std::to_string(id) + " rotation " + std::to_string(r) + " decodes as id " +
                       std::to_string(hit->id) + " rotation " + std::to_string(hit->rotation));
      }
    }
  }
  return 0;
}
