// tagbench: the AprilTag (2011) detector, coding system and benchmark harness, one program with
// git-style subcommands.
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <string>

#include <opencv2/core/utils/logger.hpp>

#include "cli/args.hpp"
#include "cli/commands.hpp"

namespace {

constexpr const char* kHelp = R"(usage: tagbench <command> [options]

Commands:
  family    list, show, check, generate tag families (family --help)
  render    write a tag as PNG (for POV-Ray) or printable SVG
  detect    detect tags in images, directories and videos (JSON or CSV; --draw, --debug-dir)
  codes     the paper's code experiments: code table, Fig. 5 distances, false-positive theory
  generator-speed
            time the lexicode generator (results/generator_speed.csv)
  scene     a synthetic image with tags at known corners (PNG + JSON ground truth)
  raytrace  the localization experiments on POV-Ray frames: angle (Fig. 9), distance (Fig. 10),
            conditions (noise, blur, lighting, occlusion, bending, lens distortion), five detectors
  corpus    the natural-image corpus: build it from Debian packages, list a folder of images,
            extract candidate quads and their payloads (shardable), score families on them
  falsepos  the false-positive experiments on the corpus: complexity (Fig. 6), codes (Fig. 7),
            whole detectors (ours, libapriltag, OpenCV aruco)
  realistic the detectors on frames made like JPEG photographs of small tags (12-40 px), per size
  speed     detector speed on whole image sets (corpus, ray-traced, realistic frames, scenes)
  dataset   export a ray-traced sweep's frames and ground truth (truth.json) for any detector
  score     score any detector's output (JSON lines) on an exported dataset, like the sweeps

Run 'tagbench <command> --help' for a command's options.
Conventions: codes in AprilTag 1 order (MSB = top-left payload cell, row-major, 1 = white).
)";

struct Command {
  const char* name;
  int (*run)(const tagbench::cli::Words&);
};

constexpr Command kCommands[] = {
    {"family", tagbench::cli::cmd_family},
    {"render", tagbench::cli::cmd_render},
    {"detect", tagbench::cli::cmd_detect},
    {"codes", tagbench::cli::cmd_codes},
    {"generator-speed", tagbench::cli::cmd_generator_speed},
    {"scene", tagbench::cli::cmd_scene},
    {"raytrace", tagbench::cli::cmd_raytrace},
    {"corpus", tagbench::cli::cmd_corpus},
    {"falsepos", tagbench::cli::cmd_falsepos},
    {"realistic", tagbench::cli::cmd_realistic},
    {"speed", tagbench::cli::cmd_speed},
    {"dataset", tagbench::cli::cmd_dataset},
    {"score", tagbench::cli::cmd_score},
};

}  // namespace

namespace tagbench::cli {
bool wants_help(const Words& args, const char* help_text) {
  for (const auto& a : args)
    if (a == "--help" || a == "-h") {
      std::fputs(help_text, stdout);
      return true;
    }
  return false;
}

int dispatch_subcommand(const char* command, const Words& w, std::span<const Subcommand> subs) {
  const Words rest(w.begin() + 1, w.end());
  std::string names;
  for (const Subcommand& sub : subs) {
    names += (names.empty() ? "" : ", ") + std::string(sub.name);
    if (w[0] != sub.name) continue;
    // main() would prefix only "tagbench COMMAND: "; errors name the subcommand too, with main's exit codes.
    try {
      return sub.run(rest);
    } catch (const UsageError& e) {
      std::fprintf(stderr, "tagbench %s %s: %s\n", command, sub.name, e.what());
      return 2;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "tagbench %s %s: %s\n", command, sub.name, e.what());
      return 1;
    }
  }
  throw UsageError("unknown subcommand '" + w[0] + "' (" + names + ")");
}
}  // namespace tagbench::cli

int main(int argc, char** argv) {
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "help")) {
    std::fputs(kHelp, argc < 2 ? stderr : stdout);
    return argc < 2 ? 2 : 0;
  }
  // OpenCV's own warnings ("[ WARN:0@0.08] ... imread_(...): can't open/read file") would break the
  // one-line-per-error rule: every command reports what it could not read itself.
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
  const std::string name = argv[1];
  tagbench::cli::Words rest(argv + 2, argv + argc);
  for (const auto& c : kCommands) {
    if (name != c.name) continue;
    try {
      return c.run(rest);
    } catch (const tagbench::cli::UsageError& e) {  // one line: a newline in a name is shown escaped
      std::fprintf(stderr, "tagbench %s: %s\n", c.name, tagbench::cli::one_line(e.what(), true).c_str());
      return 2;
    } catch (const std::filesystem::filesystem_error& e) {
      // "filesystem error: OPERATION: REASON [PATH]" as "PATH: OPERATION: REASON", like our own messages.
      std::string what = e.what();
      if (what.starts_with("filesystem error: ")) what = what.substr(18);
      if (const auto bracket = what.find(" ["); bracket != std::string::npos && !e.path1().empty()) what.resize(bracket);
      if (!e.path1().empty()) what = e.path1().string() + ": " + what;
      std::fprintf(stderr, "tagbench %s: %s\n", c.name, tagbench::cli::one_line(what, true).c_str());
      return 1;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "tagbench %s: %s\n", c.name, tagbench::cli::one_line(e.what(), true).c_str());
      return 1;
    }
  }
  std::fprintf(stderr, "tagbench: unknown command '%s' (run 'tagbench --help')\n", name.c_str());
  return 2;
}
