#pragma once
// A ray-traced sweep run from the command line (tagbench raytrace, tagbench falsepos margin): a
// progress bar per phase on stderr (rendering, then detecting), and every frame that fails to render
// reported on one line (the first ten; then how many more), while the run goes on.
#include <string>

#include "cli/args.hpp"
#include "raytrace/sweeps.hpp"

namespace tagbench::cli {

// The render options of --processes P (default: one per core), --cache DIR (default
// default_render_cache()) and --povray PATH (default povray, from PATH).
bench::RenderOptions render_options(const Args& a);

// `command` prefixes the failure lines ("tagbench raytrace"); `label` names the bars ("raytrace
// distance"). Throws what run_sweep throws.
bench::SweepResult run_sweep_with_progress(const bench::SweepSettings& settings, const bench::RenderOptions& render,
                                           const std::string& command, const std::string& label);

}  // namespace tagbench::cli
