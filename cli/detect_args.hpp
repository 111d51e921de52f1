#pragma once
// tagbench detect: its options (the command line into Settings) and its --help text.
#include <filesystem>
#include <optional>
#include <string>

#include <vector>

#include "cli/args.hpp"
#include "cli/detect_explain.hpp"
#include "detect/detector.hpp"

namespace tagbench::cli::detect_cmd {

namespace fs = std::filesystem;

struct Settings {
  std::string profile = "default";  // "default", "thorough" or "paper" (--profile)
  DetectorOptions det;
  bool csv = false;
  bool jsonl = false;  // --format jsonl: one JSON line per image (the format tagbench score reads)
  std::optional<fs::path> draw;
  bool draw_is_file = false;
  std::optional<fs::path> debug_dir;
  int threads = 1;
  std::vector<ExplainPoint> explain;  // --explain X,Y[,FAMILY:ID], repeatable
};

// The --help text (also the documentation of the JSON and CSV output).
extern const char* const kHelp;

// Reads the options; throws UsageError (args.hpp) on a bad one, before anything is read or written.
Settings parse_settings(const Args& a);

}  // namespace tagbench::cli::detect_cmd
