#pragma once
// The frame cache's batch files (render.hpp): what one render_frames call leaves while POV-Ray runs,
// and what a later call does with them when that call's process is gone (killed, Ctrl-C).
//
// A batch is named ID = OWNER-HASH (OWNER = owner_tag(), "PID-HOST"; HASH from the batch's frame keys):
//   batch-ID.pov        the scene, a #switch (frame_number) over the batch's frames 1..M
//   batch-ID.keys       the cache key of frame k on line k (written before POV-Ray starts)
//   batch-ID-wW-R.log   POV-Ray's output of worker W's run R
//   tmp-ID-NNN.png      POV-Ray's image of frame NNN, renamed to frame-KEY.png once it decodes
// A dead batch's finished images are not lost: each tmp-ID-NNN.png that decodes as a whole frame is
// moved into the cache under its key (the pixels a new render would give), and the rest removed.
#include <cstddef>
#include <filesystem>
#include <span>
#include <string>

namespace tagbench::bench {

// True when `png` is a readable image of the render size (a half-written one is not).
bool decodes_as_frame(const std::filesystem::path& png);

// Writes batch-BATCH.keys in `dir`: keys[k - 1] on line k.
void write_batch_keys(const std::filesystem::path& dir, const std::string& batch, std::span<const std::string> keys);

struct DeadBatchCleanup {
  std::size_t frames_kept = 0;    // finished images moved into the cache
  std::size_t files_removed = 0;  // scenes, key lists, logs, unfinished images, temporaries
};

// For every batch in `dir` whose process is gone: keeps its finished frames, removes its other files
// and the atomic writes' temporaries of gone processes. Batches of runs still going (on this host or
// another sharing the cache) are left alone. Best effort: what cannot be read, moved or removed is
// skipped.
DeadBatchCleanup clear_dead_batches(const std::filesystem::path& dir);

}  // namespace tagbench::bench
