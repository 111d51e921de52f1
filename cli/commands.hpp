#pragma once
// The `tagbench` subcommands. Each takes the words after its name and returns the exit code;
// errors are thrown (UsageError -> exit 2, anything else -> exit 1) and printed on one line by main.
#include <span>
#include <string>
#include <vector>

namespace tagbench::cli {

using Words = std::vector<std::string>;

int cmd_family(const Words& args);
int cmd_render(const Words& args);
int cmd_codes(const Words& args);
int cmd_generator_speed(const Words& args);
int cmd_scene(const Words& args);
int cmd_detect(const Words& args);
int cmd_raytrace(const Words& args);
int cmd_corpus(const Words& args);
int cmd_falsepos(const Words& args);
int cmd_realistic(const Words& args);
int cmd_speed(const Words& args);
int cmd_dataset(const Words& args);
int cmd_score(const Words& args);

// True (and the help printed to stdout) when args ask for help.
bool wants_help(const Words& args, const char* help_text);

// For commands with subcommands (corpus, falsepos): runs the one named by args[0] (args not empty)
// with the words after it. Its errors are printed here as "tagbench COMMAND SUB: message" with
// main's exit codes (2 for usage errors, 1 otherwise); an unknown name throws UsageError.
struct Subcommand {
  const char* name;
  int (*run)(const Words&);
};
int dispatch_subcommand(const char* command, const Words& args, std::span<const Subcommand> subcommands);

}  // namespace tagbench::cli
