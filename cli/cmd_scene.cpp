// tagbench scene: a synthetic cluttered image with tags at known corners (bench/scenes.hpp), for
// trying the detector and for the README's example pictures. Writes the PNG and a JSON sidecar with
// the ground truth (corners in printed order TL, TR, BR, BL, pixel centres at integer coordinates).
#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <filesystem>
#include <sstream>

#include "cli/args.hpp"
#include "cli/commands.hpp"
#include "codes/families.hpp"
#include "scenes.hpp"
#include "tools/atomic_file.hpp"

namespace tagbench::cli {

using namespace tagbench::bench;  // the experiments these commands run

namespace {
constexpr const char* kSceneHelp = R"(usage: tagbench scene [--width W] [--height H] [--family F] [--count N] [--seed S] -o FILE.png

A synthetic scene: N tags of family F (default 36h11, 6 tags) in perspective on a cluttered,
unevenly lit background, W x H pixels (default 640 x 480), determined by the seed (default 1).
Also writes FILE.json with the tags' ids and true corners.
)";
}

int cmd_scene(const Words& w) {
  if (wants_help(w, kSceneHelp)) return 0;
  const Args a(w, {{"width"}, {"height"}, {"family"}, {"count"}, {"seed"}, {"out", true, false, "o"}});
  if (!a.positionals().empty()) throw UsageError("unexpected argument '" + a.positionals()[0] + "'");
  if (!a.has("out")) throw UsageError("-o/--out is required");
  const int width = static_cast<int>(a.get_int("width", 640, 64, 16384));
  const int height = static_cast<int>(a.get_int("height", 480, 64, 16384));
  const int count = static_cast<int>(a.get_int("count", 6, 0, 100));
  const auto seed = static_cast<std::uint32_t>(a.get_int("seed", 1, 0, 4294967295LL));
  const std::string family = a.get_or("family", "36h11");
  const std::filesystem::path out = *a.get("out");
  if (out.extension() != ".png") throw UsageError("-o " + out.string() + ": the scene is written as .png");
  // unknown names fail here with the list of known ones
  usage_on_invalid("--family: ", [&] { builtin_family(family); });
  const Scene s = make_scene(width, height, family, count, seed);
  std::vector<std::uint8_t> png;
  if (!cv::imencode(".png", s.image, png)) throw std::runtime_error(out.string() + ": PNG encoding failed");
  std::ostringstream js;
  js.precision(10);
  js << "{\"width\": " << width << ", \"height\": " << height << ", \"family\": \"" << family << "\", \"seed\": " << seed
     << ", \"tags\": [";
  for (std::size_t i = 0; i < s.tags.size(); ++i) {
    js << (i ? ", " : "") << "{\"id\": " << s.tags[i].id << ", \"corners\": [";
    for (std::size_t k = 0; k < 4; ++k)
      js << (k ? ", " : "") << "[" << s.tags[i].corners[k].x() << ", " << s.tags[i].corners[k].y() << "]";
    js << "]}";
  }
  js << "]}\n";
  std::filesystem::path side = out;
  side.replace_extension(".json");
  // The picture and its ground truth together or neither (a full disk must not leave the JSON alone).
  write_files_atomic({{side, js.str()}, {out, std::string(png.begin(), png.end())}});
  return 0;
}

}  // namespace tagbench::cli
