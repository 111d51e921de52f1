// The same results with one thread and with several (issue 6, item 5), end to end: `tagbench
// detect` on a batch of scenes (JSON with poses, CSV at half resolution, the --draw pictures) and
// `tagbench family generate`, byte for byte but for the timing fields. Four threads, so that the
// work interleaves even on two cores.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>

#include "codes/families.hpp"
#include "codes/family_io.hpp"

#include "kill_run.hpp"
#include "run_tagbench.hpp"
#include "scratch_dir.hpp"

namespace test_determinism {

namespace fs = std::filesystem;
using namespace tagbench::testing;

namespace {

const fs::path& root() { return program_scratch("tagbench_determinism"); }

CommandResult run(const std::string& args) { return run_tagbench(args, root()); }

// Scenes of three families and four sizes; two files share a name (in different folders), so --draw
// must make one of the picture names unique, and it must do so the same way every time.
const fs::path& scenes() {
  static const fs::path d = [] {
    const fs::path p = root() / "scenes";
    struct Scene {
      const char* file;
      const char* family;
      int w, h, count, seed;
    };
    const Scene list[] = {{"a/x.png", "36h11", 640, 480, 6, 1},  {"b/x.png", "36h11", 800, 600, 8, 2},
                          {"small.png", "36h11", 320, 240, 3, 3}, {"big.png", "36h11", 1024, 768, 10, 4},
                          {"c/t25.png", "25h9", 640, 480, 6, 5},  {"c/t16.png", "16h5", 640, 480, 6, 6}};
    for (const auto& s : list) {
      fs::create_directories((p / s.file).parent_path());
      const CommandResult r = run(std::string("scene --family ") + s.family + " --width " + std::to_string(s.w) +
                                  " --height " + std::to_string(s.h) + " --count " + std::to_string(s.count) +
                                  " --seed " + std::to_string(s.seed) + " -o " + (p / s.file).string());
      EXPECT_EQ(r.code, 0) << r.err;
      fs::remove(fs::path(p / s.file).replace_extension(".json"));  // ground truth: not an input
    }
    return p;
  }();
  return d;
}

// Every value that follows `key` becomes T: a number up to the next ',', newline or '}', or an
// object (`object`) through its closing '}'.
std::string mask_values(const std::string& json, const std::string& key, bool object) {
  std::string out;
  std::size_t pos = 0;
  for (std::size_t at = json.find(key); at != std::string::npos; at = json.find(key, pos)) {
    const std::size_t v = at + key.size();
    std::size_t end = object ? json.find('}', v) : json.find_first_of(",\n}", v);
    if (end == std::string::npos) break;
    if (object) ++end;
    out.append(json, pos, v - pos);
    out += 'T';
    pos = end;
  }
  out.append(json, pos, std::string::npos);
  return out;
}

// The JSON output without its wall times.
std::string without_times(const std::string& json) {
  return mask_values(mask_values(json, "\"detect_ms\": ", false), "\"timings_ms\": ", true);
}

// A family file without its records of time and threads ("# total: ..." and "# run: ..." lines).
std::string without_run_records(const std::string& fam) {
  std::istringstream in(fam);
  std::string out;
  for (std::string l; std::getline(in, l);)
    if (l.rfind("# total:", 0) != 0 && l.rfind("# run:", 0) != 0) out += l + "\n";
  return out;
}

}  // namespace

TEST(Determinism, DetectGivesTheSameOutputWithOneThreadAndWithFour) {
  const std::string families = " --family 36h11 --family 25h9 --family 16h5 ";
  std::map<int, CommandResult> json, csv;
  for (const int t : {1, 4}) {
    const fs::path draw = root() / ("draw" + std::to_string(t));
    json[t] = run("detect " + scenes().string() + families + "--camera 500,500,319.5,239.5 --tag-size 0.1 --draw " +
                  draw.string() + " --threads " + std::to_string(t));
    ASSERT_EQ(json[t].code, 0) << json[t].err;
    csv[t] = run("detect " + scenes().string() + families + "--half-res --format csv --threads " + std::to_string(t));
    ASSERT_EQ(csv[t].code, 0) << csv[t].err;
  }
  // Not vacuous: the six images, most of their 39 tags found, poses.
  EXPECT_GE(std::count(csv[1].out.begin(), csv[1].out.end(), '\n'), 30) << csv[1].out;
  EXPECT_NE(json[1].out.find("\"pose\": {\"R\""), std::string::npos);
  EXPECT_NE(json[1].out.find("\"detect_ms\""), std::string::npos) << "the timing fields are where they are expected";
  EXPECT_EQ(without_times(json[4].out), without_times(json[1].out));
  EXPECT_EQ(csv[4].out, csv[1].out);
  const auto d1 = file_tree(root() / "draw1"), d4 = file_tree(root() / "draw4");
  EXPECT_EQ(d1.size(), 6u);
  EXPECT_EQ(d1.count("x.png") + d1.count("x_2.png"), 2u) << "the two x.png, one made unique";
  EXPECT_TRUE(d1 == d4) << "the --draw pictures differ:\n" << tree_difference(d1, d4);
}

TEST(Determinism, GenerateGivesTheSameFamilyFileWithOneThreadAndWithFour) {
  for (const std::string params : {"--bits 25 --hamming 7", "--bits 16 --hamming 5 --order lex"}) {
    std::map<int, std::string> fam;
    for (const int t : {1, 4}) {
      const fs::path out = root() / ("gen" + std::to_string(t) + ".fam");
      const CommandResult r = run("family generate " + params + " --threads " + std::to_string(t) + " --out " +
                                  out.string());
      ASSERT_EQ(r.code, 0) << r.err;
      fam[t] = slurp(out);
      EXPECT_NE(fam[t].find("threads=" + std::to_string(t)), std::string::npos) << "the run record names the threads";
    }
    EXPECT_EQ(without_run_records(fam[4]), without_run_records(fam[1])) << params;
    if (params == "--bits 25 --hamming 7") {
      EXPECT_EQ(tagbench::parse_family(fam[4], "gen4.fam").codes(), tagbench::builtin_family("25h7").codes());
    }
  }
}

}  // namespace test_determinism
