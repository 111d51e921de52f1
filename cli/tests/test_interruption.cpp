// Family generation killed with kill -9 (issue 6, item 4), beyond test_cli's single kill and resume:
// killed while several threads work on a block, resumed on one thread and killed again, then resumed
// to the end: the family is the published one, the checkpoint is gone, and so are the temporaries of
// checkpoints a kill cut short.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "codes/families.hpp"
#include "codes/family_io.hpp"
#include "tools/atomic_file.hpp"

#include "kill_run.hpp"
#include "run_tagbench.hpp"
#include "scratch_dir.hpp"

namespace test_interruption {

namespace fs = std::filesystem;
using namespace tagbench::testing;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path d = program_scratch("tagbench_interruption") / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// The checkpoint's next candidate, or 0 while there is none (it is replaced atomically, so a read
// sees a whole one).
std::uint64_t progress(const fs::path& ckpt) {
  if (!fs::exists(ckpt)) return 0;
  try {
    return static_cast<std::uint64_t>(tagbench::read_checkpoint(ckpt).state.next_index);
  } catch (const std::exception&) {
    return 0;  // renamed away between the check and the read: no news
  }
}

}  // namespace

TEST(GenerationInterruption, KilledTwiceOnDifferentThreadCountsResumesToThePublishedFamily) {
  const fs::path dir = scratch("gen"), logs = scratch("gen-logs");
  const fs::path ckpt = dir / "25h7.ckpt", out = dir / "25h7.fam";
  const std::string ck = " --checkpoint-seconds 0.02 --checkpoint " + ckpt.string() + " --out " + out.string();

  const pid_t first = start_tagbench("family generate --bits 25 --hamming 7 --threads 3" + ck, logs);
  const KillOutcome k1 = kill_when(first, [&] { return progress(ckpt) > 0; });
  ASSERT_TRUE(k1.killed_mid_run) << k1.why << "\n" << slurp(logs / "stderr");
  const std::uint64_t at1 = progress(ckpt);
  ASSERT_GT(at1, 0u);
  ASSERT_LT(at1, std::uint64_t{1} << 25);
  EXPECT_FALSE(fs::exists(out));
  // A kill while the checkpoint was being written leaves its temporary.
  const fs::path stale1 = tagbench::atomic_temporary(ckpt, first);
  std::ofstream(stale1) << "half a checkpoint";

  // Resumed on one thread, killed again once it has got further.
  const pid_t second = start_tagbench("family generate --resume --threads 1" + ck, logs);
  const KillOutcome k2 = kill_when(second, [&] { return progress(ckpt) > at1; });
  ASSERT_TRUE(k2.killed_mid_run) << k2.why << "\n" << slurp(logs / "stderr");
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(stale1)) << "the resumed run clears the killed run's temporary";
  const fs::path stale2 = tagbench::atomic_temporary(out, second);
  std::ofstream(stale2) << "half a family file";

  const CommandResult r = run_tagbench("family generate --resume --threads 2" + ck, logs);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(tagbench::read_family_file(out).codes(), tagbench::builtin_family("25h7").codes());
  EXPECT_FALSE(fs::exists(ckpt)) << "a completed run removes its checkpoint";
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path(), out) << "left beside the family: " << e.path();
}

}  // namespace test_interruption
