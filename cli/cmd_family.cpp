// tagbench family: list, show, stats, check and generate tag families.
#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "cli/args.hpp"
#include "cli/commands.hpp"
#include "codes/families.hpp"
#include "codes/family_io.hpp"
#include "codes/hamming_scan.hpp"
#include "codes/lexicode.hpp"
#include "tools/atomic_file.hpp"
#include "tools/progress.hpp"
#include "tools/sysinfo.hpp"

namespace tagbench::cli {

namespace {

constexpr const char* kFamilyHelp = R"(usage: tagbench family <list|show|stats|check|generate> ...

  family list                     built-in families: name, bits, h, complexity, count
  family show NAME [--format fam|cpp|hex]
                                  the codes, one hex code a line (AprilTag 1 order); fam: a family file
  family stats NAME...            count, minimum distance with and without rotations, distance histogram
  family check FILE...            validate family files (count, duplicates, minimum distance)
  family generate --bits N --hamming H [options]
                                  the paper's lexicode generator (family generate --help)
NAME is a built-in family (16h5, 36h11, artoolkitplus-bch, ...) or a family file.
)";

constexpr const char* kGenerateHelp = R"(usage: tagbench family generate --bits N --hamming H [options]

The paper's modified lexicode (section V-A): candidates in the order V0 + k*982451653 mod 2^N
(V0 from java.util.Random(seed)), accepted when all four rotations keep distance >= H from each other
and from every rotation of every accepted code, and the rectangle complexity is >= C. The defaults
reproduce the published AprilTag families bit for bit (16h5, 25h7, 25h9, 36h9, 36h10, 36h11).

  --bits N               payload bits, a square 9..64 (3x3 to 8x8)
  --hamming H            minimum Hamming distance, 1..N
  --complexity C         minimum rectangle complexity (default min(10, N/3))
  --seed S               generator seed (default N*10000 + H*100 + C, as the original)
  --order prime|lex      candidate order (default prime; lex = 0, 1, 2, ...)
  --threads T            worker threads (default: all cores); the result never depends on T
  --checkpoint FILE      save progress to FILE (atomically) every --checkpoint-seconds
  --checkpoint-seconds S seconds between checkpoints (default 10)
  --resume               continue from --checkpoint FILE (its parameters win; given ones must agree)
  --max-codes M          stop after M codes: the output is the exact first M codes of the family,
                         marked as a prefix (for 7x7 and 8x8 payloads, whose full runs never end)
  --name NAME            family name (default NhH, with _cC, _sS, _lex for non-default settings)
  --format fam|cpp       output format (default fam: the family file)
  --out FILE             output file (default: stdout); written only when the run ends
Progress goes to stderr. SIGINT/SIGTERM save the checkpoint and exit with status 130.
)";

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop = true; }

int do_list(const Words& w) {
  const Args a(w, {});
  if (!a.positionals().empty()) throw UsageError("list takes no arguments");
  std::printf("%-22s %5s %3s %10s %6s  %s\n", "name", "bits", "h", "complexity", "codes", "source");
  for (const auto& n : builtin_family_names()) {
    const TagFamily& f = builtin_family(n);
    const auto& i = f.info();
    std::printf("%-22s %5d %3d %10d %6zu  %s\n", n.c_str(), i.bits, i.min_hamming, i.min_complexity, f.size(),
                i.generator.c_str());
  }
  for (const auto& n : pending_family_names())
    std::printf("%-22s  (lexicode run in progress: not yet a family; resume its checkpoint)\n", n.c_str());
  return 0;
}

int do_show(const Words& w) {
  const Args a(w, {{"format"}});
  if (a.positionals().size() != 1) throw UsageError("show takes one family name or file");
  const TagFamily f = load_family(a.positionals()[0]);
  const std::string fmt = a.get_or("format", "hex");
  if (fmt == "hex") {
    for (const Code c : f.codes()) std::printf("%s\n", hex_code(c).c_str());
  } else if (fmt == "fam") {
    std::fputs(format_family(f).c_str(), stdout);
  } else if (fmt == "cpp") {
    std::fputs(format_family_cpp(f).c_str(), stdout);
  } else {
    throw UsageError("--format: unknown format '" + fmt + "' (hex, fam or cpp)");
  }
  return 0;
}

int do_stats(const Words& w) {
  const Args a(w, {{"threads"}});
  if (a.positionals().empty()) throw UsageError("stats needs at least one family name or file");
  const int threads = static_cast<int>(a.get_int("threads", 0, 0, 1024));
  for (const auto& name : a.positionals()) {
    const TagFamily f = load_family(name);
    const DistanceStats s = distance_stats(f.codes(), f.payload_width(), threads);
    std::printf("family %s: %zu codes, %d bits, h=%d, complexity threshold %d (measured minimum %d)\n",
                f.name().c_str(), f.size(), f.bits(), f.min_hamming(), f.info().min_complexity,
                min_complexity_of(f.codes(), f.payload_width()));
    std::printf("  minimum distance without rotations: %d\n", s.min_plain);
    std::printf("  minimum distance with rotations:    %d (pairs and each code's own rotations; own: %d)\n",
                s.min_with_rotations, s.min_self_rotation);
    std::printf("  distance histogram over all %zu pairs (minimum over rotations):\n",
                f.size() * (f.size() - 1) / 2);
    for (std::size_t k = 0; k < s.histogram.size(); ++k)
      if (s.histogram[k]) std::printf("    %2zu %llu\n", k, static_cast<unsigned long long>(s.histogram[k]));
  }
  return 0;
}

int do_check(const Words& w) {
  const Args a(w, {});
  if (a.positionals().empty()) throw UsageError("check needs at least one family file");
  int bad = 0;
  for (const auto& p : a.positionals()) {
    try {
      const TagFamily f = read_family_file(p);
      std::printf("%s: ok (%s, %zu codes, h=%d)\n", p.c_str(), f.name().c_str(), f.size(), f.min_hamming());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "tagbench family check: %s\n", e.what());
      ++bad;
    }
  }
  return bad ? 1 : 0;
}

int do_generate(const Words& w) {
  if (wants_help(w, kGenerateHelp)) return 0;
  const Args a(w, {{"bits"}, {"hamming"}, {"complexity"}, {"seed"}, {"order"}, {"threads"}, {"checkpoint"},
                   {"checkpoint-seconds"}, {"resume", false}, {"max-codes"}, {"name"}, {"format"}, {"out"}});
  if (!a.positionals().empty()) throw UsageError("unexpected argument '" + a.positionals()[0] + "'");
  LexicodeParams p;
  LexicodeState start;
  const auto bits = a.get_int("bits", 1, 64);
  const auto h = a.get_int("hamming", 1, 64);
  const auto cplx = a.get_int("complexity", 0, 64);
  const auto seed = a.get_int("seed", INT64_MIN, INT64_MAX);
  const std::optional<std::string> order = a.get("order");
  const std::optional<std::string> ckpt = a.get("checkpoint");
  if (a.has("checkpoint-seconds") && !ckpt) throw UsageError("--checkpoint-seconds needs --checkpoint FILE");
  if (a.flag("resume")) {
    if (!ckpt) throw UsageError("--resume needs --checkpoint FILE");
    Checkpoint c = read_checkpoint(*ckpt);
    const auto clash = [](const char* opt, long long given, long long have) {
      if (given != have)
        throw UsageError(std::string(opt) + " " + std::to_string(given) + " disagrees with the checkpoint's " +
                         std::to_string(have));
    };
    if (bits) clash("--bits", *bits, c.params.bits);
    if (h) clash("--hamming", *h, c.params.min_hamming);
    if (cplx) clash("--complexity", *cplx, c.params.resolved_complexity());
    if (seed) clash("--seed", *seed, c.params.resolved_seed());
    if (order && parse_candidate_order(*order) != c.params.order)
      throw UsageError("--order " + *order + " disagrees with the checkpoint's " + to_string(c.params.order));
    p = c.params;
    start = std::move(c.state);
  } else {
    if (!bits) throw UsageError("--bits is required");
    if (!h) throw UsageError("--hamming is required");
    p.bits = static_cast<int>(*bits);
    p.min_hamming = static_cast<int>(*h);
    if (cplx) p.min_complexity = static_cast<int>(*cplx);
    p.seed = seed;
    try {
      if (order) p.order = parse_candidate_order(*order);
      p.validate();
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
  }
  const int threads = static_cast<int>(a.get_int("threads", hardware_threads(), 1, 1024));
  const double ckpt_every = a.get_double("checkpoint-seconds", 10, 0.01, 1e6);
  const auto max_codes = static_cast<std::size_t>(a.get_int("max-codes", 0, 1, 1LL << 40));
  const std::string fmt = a.get_or("format", "fam");
  if (fmt != "fam" && fmt != "cpp") throw UsageError("--format: unknown format '" + fmt + "' (fam or cpp)");
  const std::optional<std::string> out = a.get("out");
  // Fail before hours of work, not after.
  for (const auto& [opt, path] : {std::pair{"--out", out}, std::pair{"--checkpoint", ckpt}}) {
    if (!path) continue;
    const auto dir = std::filesystem::absolute(*path).parent_path();
    if (!std::filesystem::is_directory(dir))
      throw UsageError(std::string(opt) + " " + *path + ": " + why_not_directory(dir.string()) + " " + dir.string());
  }

  std::string name = a.get_or("name", "");
  // The name is a header line of the file: a line break would start another header key.
  for (const char ch : name)
    if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f)
      throw UsageError("--name '" + name + "': control characters (a line break) cannot be part of a family name");
  if (name.empty()) {
    name = std::to_string(p.bits) + "h" + std::to_string(p.min_hamming);
    if (p.min_complexity >= 0 && p.min_complexity != std::min(10, p.bits / 3)) name += "_c" + std::to_string(p.min_complexity);
    if (p.seed && *p.seed != LexicodeParams{p.bits, p.min_hamming, p.min_complexity, {}, p.order}.resolved_seed())
      name += "_s" + std::to_string(*p.seed);
    if (p.order == CandidateOrder::kLex) name += "_lex";
  }

  // A run killed with kill -9 while it wrote its checkpoint (or family file) left the temporary.
  for (const auto& path : {ckpt, out})
    if (path) remove_stale_temporaries(std::filesystem::absolute(*path).parent_path());
  LexicodeGenerator gen(p, std::move(start));
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  ProgressBar bar("generate " + name);
  using Clock = std::chrono::steady_clock;
  auto last_ckpt = Clock::now();
  const auto save = [&](const LexicodeState& s) {
    if (ckpt) write_file_atomic(*ckpt, format_checkpoint(p, s));
    last_ckpt = Clock::now();
  };
  const unsigned __int128 first = gen.state().next_index;
  const double elapsed_before = gen.state().elapsed_seconds;
  gen.run(threads, max_codes, [&](const LexicodeProgress& pr, const LexicodeState& s) {
    const double frac = static_cast<double>(pr.done) / static_cast<double>(pr.total);
    const double left = pr.candidates_per_second > 0 ? static_cast<double>(pr.total - pr.done) / pr.candidates_per_second : -1;
    char detail[128];
    std::snprintf(detail, sizeof detail, "%zu codes, %.3g cand/s", pr.codes, pr.candidates_per_second);
    bar.update(frac, to_decimal(pr.done) + "/" + to_decimal(pr.total), detail, left);
    if (ckpt && std::chrono::duration<double>(Clock::now() - last_ckpt).count() >= ckpt_every) save(s);
    return !g_stop.load();
  });
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  const LexicodeState& s = gen.state();
  const bool prefix = !gen.complete();
  if (prefix && (max_codes == 0 || s.codes.size() < max_codes)) {  // interrupted
    save(s);
    std::fprintf(stderr, "tagbench family generate: interrupted at candidate %s with %zu codes%s\n",
                 to_decimal(s.next_index).c_str(), s.codes.size(),
                 ckpt ? (", checkpoint " + *ckpt).c_str() : " (no --checkpoint: progress lost)");
    return 130;
  }
  FamilyInfo info;
  info.name = name;
  info.bits = p.bits;
  info.min_hamming = p.min_hamming;
  info.min_complexity = p.resolved_complexity();
  info.seed = p.resolved_seed();
  info.order = to_string(p.order);
  info.generator = "tagbench-lexicode " + std::to_string(kGeneratorVersion) + (prefix ? " (prefix)" : "");
  if (s.codes.empty()) throw std::runtime_error("no code satisfies these parameters: the family would be empty");
  const TagFamily fam(info, s.codes, /*check_distance=*/true);
  const double run_seconds = s.elapsed_seconds - elapsed_before;
  char rec[512];
  std::snprintf(rec, sizeof rec,
                "run: candidates=%s wall_seconds=%.1f threads=%d candidates_per_second=%.4g scan=%s cpu=\"%s\"",
                to_decimal(s.next_index - first).c_str(), run_seconds, threads,
                run_seconds > 0 ? static_cast<double>(s.next_index - first) / run_seconds : 0.0, hamming_scan_impl(),
                cpu_model_name().c_str());
  std::vector<std::string> comments = {std::string("generated by: tagbench family generate --bits ") +
                                           std::to_string(p.bits) + " --hamming " + std::to_string(p.min_hamming) +
                                           " --complexity " + std::to_string(info.min_complexity) + " --seed " +
                                           std::to_string(*info.seed) + " --order " + info.order,
                                       std::string("total: candidates=") + to_decimal(s.next_index) +
                                           " wall_seconds=" + std::to_string(s.elapsed_seconds),
                                       rec};
  if (prefix) comments.push_back("prefix: the first " + std::to_string(s.codes.size()) +
                                 " codes of the lexicode; later candidates were not examined");
  const std::string text = fmt == "cpp" ? format_family_cpp(fam) : format_family(fam, comments);
  if (out) write_file_atomic(*out, text);
  else std::fputs(text.c_str(), stdout);
  if (ckpt && !prefix) std::filesystem::remove(*ckpt);  // the family file is the result now
  return 0;
}

}  // namespace

int cmd_family(const Words& w) {
  if (w.empty() || ((w[0] == "--help" || w[0] == "-h"))) {
    std::fputs(kFamilyHelp, w.empty() ? stderr : stdout);
    return w.empty() ? 2 : 0;
  }
  const Words rest(w.begin() + 1, w.end());
  if (w[0] == "generate") return do_generate(rest);
  if (wants_help(rest, kFamilyHelp)) return 0;
  if (w[0] == "list") return do_list(rest);
  if (w[0] == "show") return do_show(rest);
  if (w[0] == "stats") return do_stats(rest);
  if (w[0] == "check") return do_check(rest);
  throw UsageError("unknown subcommand '" + w[0] + "' (list, show, stats, check, generate)");
}

}  // namespace tagbench::cli
