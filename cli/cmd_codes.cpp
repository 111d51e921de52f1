// tagbench codes: the paper's code experiments written as CSV into a results folder.
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "cli/args.hpp"
#include "cli/commands.hpp"
#include "code_experiments.hpp"
#include "generator_speed.hpp"
#include "tools/sysinfo.hpp"
#include "codes/families.hpp"
#include "tools/atomic_file.hpp"

namespace tagbench::cli {

using namespace tagbench::bench;  // the experiments these commands run

namespace {
constexpr const char* kCodesHelp = R"(usage: tagbench codes [--out DIR] [--threads T]

Writes the paper's code experiments (section V) into DIR (default results):
  code_table.csv    the encoding table: scheme, bits, codes, minimum Hamming distance with rotations,
                    the paper's figures beside ours
  fig5_hamming.csv  Fig. 5: distances between all pairs of codewords (minimum over rotations)
  fp_theory.csv     the theoretical false-positive table for 36h10 and 36h15, 0..7 bits corrected
  codes.json        the settings and family provenance behind the three
)";
}

int cmd_codes(const Words& w) {
  if (wants_help(w, kCodesHelp)) return 0;
  const Args a(w, {{"out"}, {"threads"}});
  if (!a.positionals().empty()) throw UsageError("unexpected argument '" + a.positionals()[0] + "'");
  const std::filesystem::path dir = a.get_or("out", "results");
  const int threads = static_cast<int>(a.get_int("threads", 0, 0, 1024));
  if (!std::filesystem::is_directory(dir)) throw UsageError("--out " + dir.string() + ": " + why_not_directory(dir.string()));
  // Compute everything first, then write: a failure leaves no partial set.
  const auto table = code_table(threads);
  const auto fp = fp_theory();
  std::ostringstream js;
  js << "{\n  \"command\": \"tagbench codes\",\n  \"rotations\": \"distances are minima over the 4 rotations; "
        "fp_percent_4_rotations counts 4 accepted orientations per code\",\n  \"families\": [\n";
  for (std::size_t i = 0; i < table.size(); ++i) {
    const auto& r = table[i];
    js << "    {\"scheme\": \"" << r.scheme.scheme << "\", \"family\": \"" << r.scheme.family << "\", \"available\": "
       << (r.available ? "true" : "false");
    if (r.available) {
      const auto& info = builtin_family(r.scheme.family).info();
      js << ", \"generator\": \"" << info.generator << "\"";
      if (info.seed) js << ", \"seed\": " << *info.seed;
      if (!info.order.empty()) js << ", \"order\": \"" << info.order << "\"";
    }
    js << "}" << (i + 1 < table.size() ? "," : "") << "\n";
  }
  js << "  ]\n}\n";
  write_files_atomic({{dir / "code_table.csv", code_table_csv(table)},
                      {dir / "fig5_hamming.csv", fig5_csv(table)},
                      {dir / "fp_theory.csv", fp_theory_csv(fp)},
                      {dir / "codes.json", js.str()}});
  std::fprintf(stderr, "tagbench codes: wrote code_table.csv, fig5_hamming.csv, fp_theory.csv, codes.json in %s\n",
               dir.string().c_str());
  return 0;
}

}  // namespace tagbench::cli

namespace tagbench::cli {

namespace {
constexpr const char* kSpeedHelp = R"(usage: tagbench generator-speed [--out FILE] [--families LIST] [--threads LIST]

Times the lexicode generator on small shipped families (default 16h5,25h9,25h7) at each thread
count (default 1 and all cores), checks each output equals the shipped family, and adds the
recorded runs of the shipped 36-bit families (from their files). Writes CSV (default
results/generator_speed.csv).
)";

}  // namespace

int cmd_generator_speed(const Words& w) {
  if (wants_help(w, kSpeedHelp)) return 0;
  const Args a(w, {{"out"}, {"families"}, {"threads"}});
  if (!a.positionals().empty()) throw UsageError("unexpected argument '" + a.positionals()[0] + "'");
  const std::filesystem::path out = a.get_or("out", "results/generator_speed.csv");
  if (!std::filesystem::is_directory(std::filesystem::absolute(out).parent_path()))
    throw UsageError("--out " + out.string() + ": " + why_not_directory(std::filesystem::absolute(out).parent_path().string()));
  std::vector<int> threads;
  for (const auto& t : option_list("--threads", a.get_or("threads", "1," + std::to_string(hardware_threads()))))
    threads.push_back(static_cast<int>(parse_int("--threads", t, 1, 1024)));
  const auto families = option_list("--families", a.get_or("families", "16h5,25h9,25h7"));
  for (const auto& f : families)  // unknown names fail before any timing
    usage_on_invalid("--families: ", [&] { builtin_family(f); });
  auto rows = measure_generator_speed(families, threads);
  for (auto& r : recorded_generator_runs()) rows.push_back(std::move(r));
  write_file_atomic(out, generator_speed_csv(rows));
  for (const auto& r : rows)
    if (r.source == "measured" && !r.matches_shipped)
      throw std::runtime_error("generated " + r.family + " differs from the shipped family");
  return 0;
}

}  // namespace tagbench::cli
