// The replay test (ctest fuzz_replay_<target>): feeds every file of the given folders to the
// target's LLVMFuzzerTestOneInput, the way libFuzzer runs one input, without libFuzzer, so the
// normal (gcc) and sanitizer builds check the committed seed corpus and every crash regression.
// usage: replay_<target> CORPUS_DIR [REGRESSION_DIR...]
// The corpus folder must exist and hold at least one input (a misnamed folder must not pass as an
// empty one); the regression folders may be absent. A crash, a sanitizer report or a failed
// FUZZ_CHECK aborts the program, which fails the test; the input being run is printed first.
// libFuzzer also reports out-of-memory and timeouts; so that those regressions fail here too, an
// input that takes the process's peak memory over kMaxRssMb or runs longer than kMaxSeconds fails
// the test (the inputs are tiny: only a bug such as an allocation sized by a corrupt header gets
// near either).
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace fs = std::filesystem;

namespace {

constexpr long kMaxRssMb = 1024;
constexpr double kMaxSeconds = 60;

long peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024;  // Linux: kilobytes
}

std::vector<fs::path> inputs_in(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && !name.empty() && name[0] != '.') out.push_back(e.path());  // .gitkeep etc.
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR [REGRESSION_DIR...]\n", argv[0]);
    return 2;
  }
  std::size_t total = 0;
  for (int a = 1; a < argc; ++a) {
    const fs::path dir = argv[a];
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) {
      if (a == 1) {
        std::fprintf(stderr, "replay: corpus folder %s does not exist\n", dir.c_str());
        return 1;
      }
      continue;
    }
    const auto files = inputs_in(dir);
    if (a == 1 && files.empty()) {
      std::fprintf(stderr, "replay: corpus folder %s is empty\n", dir.c_str());
      return 1;
    }
    for (const auto& f : files) {
      std::printf("replay: %s\n", f.c_str());
      std::fflush(stdout);
      std::ifstream in(f, std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      if (!in.good() && !in.eof()) {
        std::fprintf(stderr, "replay: cannot read %s\n", f.c_str());
        return 1;
      }
      // A copy of exactly the input's size: ASan then catches a read one past its end, as under libFuzzer.
      // An empty input gets a valid pointer, as libFuzzer gives it.
      std::vector<std::uint8_t> buf(bytes.begin(), bytes.end());
      static std::uint8_t none = 0;
      const auto t0 = std::chrono::steady_clock::now();
      LLVMFuzzerTestOneInput(buf.empty() ? &none : buf.data(), buf.size());
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (peak_rss_mb() > kMaxRssMb) {
        std::fprintf(stderr, "replay: %s took the peak memory to %ld MB (limit %ld MB)\n", f.c_str(), peak_rss_mb(),
                     kMaxRssMb);
        return 1;
      }
      if (seconds > kMaxSeconds) {
        std::fprintf(stderr, "replay: %s ran %.1f s (limit %.0f s)\n", f.c_str(), seconds, kMaxSeconds);
        return 1;
      }
      ++total;
    }
  }
  std::printf("replay: %zu inputs, no crash\n", total);
  return 0;
}
