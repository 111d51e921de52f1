#pragma once
// tagbench falsepos: what its two files share. cmd_falsepos.cpp has the help, the dispatch and the
// candidate-store subcommands (complexity, codes); falsepos_detectors.cpp the whole detectors' ones.
#include <filesystem>

#include "cli/args.hpp"
#include "cli/commands.hpp"

namespace tagbench::cli::falsepos_cmd {

// --out DIR (default results): an existing folder, else a UsageError.
std::filesystem::path out_dir(const Args& a);

// tagbench falsepos detectors, tagbench falsepos margin (falsepos_detectors.cpp).
int falsepos_detectors(const Words& w);
int falsepos_margin(const Words& w);

}  // namespace tagbench::cli::falsepos_cmd
