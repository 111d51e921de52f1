#pragma once
// The options that choose a ray-traced sweep's frames (--trials, --tag-size, --seed, --family,
// --scene, --distance, --angles, --distances, --conditions), shared by the commands that plan one:
// tagbench dataset export (and the raytrace experiments).
#include <string>
#include <vector>

#include "cli/args.hpp"
#include "raytrace/sweeps.hpp"

namespace tagbench::cli {

// The option specs above (to add to a command's own).
std::vector<OptionSpec> sweep_option_specs();

// The settings of experiment `name` ("angle", ...) from those options, resolved and checked, and the
// frames planned (a tag that does not fit is refused here): UsageError with one line for anything
// wrong, before anything is rendered or written. `detectors`: the comparators (empty: all five).
bench::SweepSettings parse_sweep_settings(const std::string& name, const Args& a,
                                          const std::vector<std::string>& detectors = {});
// The same over `base`, whose detectors and external detectors are kept (tagbench raytrace's
// --detectors, parse_detector_list).
bench::SweepSettings parse_sweep_settings(const std::string& name, const Args& a, bench::SweepSettings base);

// --detectors LIST: built-in names and external:NAME=COMMAND items (a COMMAND runs to the next item
// that is a built-in name or another external:, so it may hold commas), into settings.detectors and
// settings.external (with the timeout of --external-timeout). UsageError for a malformed item.
void parse_detector_list(const std::string& option, const std::string& list, double external_timeout,
                         bench::SweepSettings& settings);
// The same into plain lists (tagbench falsepos detectors).
void parse_detector_list(const std::string& option, const std::string& list, double external_timeout,
                         std::vector<std::string>& detectors, std::vector<bench::ExternalDetector>& external);

// Refuses (UsageError) an --out that is, or would lie under, something other than a folder.
void check_out_folder(const std::string& option, const std::string& out);

}  // namespace tagbench::cli
