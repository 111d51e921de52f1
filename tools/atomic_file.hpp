#pragma once
// Whole-file writes that never leave a half file: write to a temporary beside the target, flush,
// then rename over it (rename is atomic on POSIX within one file system).
//
// A process killed (kill -9, power cut) while writing leaves its temporary behind. Temporaries are
// named TARGET.tmp.OWNER, OWNER being this process's owner_tag() ("PID-HOST", HOST 8 hex digits of
// the host name), so a later run can tell its dead predecessors' leftovers from the temporaries of
// runs still going, on this host or on another one writing into the same (network) folder, and
// remove only the former (remove_stale_temporaries).
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <sys/types.h>

namespace tagbench {

// Throws std::runtime_error naming the path and the system's reason on any failure; on failure the
// target is untouched and the temporary removed. A symbolic link is written through (the file it
// names is replaced, the link kept); a target that exists and is not a regular file (a directory,
// device, FIFO or socket) is refused, as renaming over it would replace the node.
void write_file_atomic(const std::filesystem::path& target, std::string_view content);

// The file a write to `target` replaces (write_file_atomic's rule above); throws std::runtime_error
// when it would not be a regular file.
std::filesystem::path write_destination(const std::filesystem::path& target);

// Several files as one result: every temporary is written before any is renamed, so a failure (a
// full disk, say) leaves none of them, rather than the first few of a set.
void write_files_atomic(const std::vector<std::pair<std::filesystem::path, std::string>>& files);

// Reads a whole file; throws std::runtime_error naming the path if it cannot.
std::string read_file(const std::filesystem::path& path);

// "PID-HOST" of this process (HOST: 8 hex digits of a hash of the host name), or of process `pid`
// on this host.
std::string owner_tag();
std::string owner_tag(pid_t pid);
// True when `tag` names a process of this host that no longer exists. A tag of another host, of a
// live process or of this process, or text that is not a tag, is never stale.
bool owner_is_gone(std::string_view tag);
// The same for a name that starts with an owner tag and a dash ("PID-HOST-rest", how work folders and
// batch files are named); false when it does not.
bool owner_prefix_is_gone(std::string_view name);

// The temporary write_file_atomic uses for `target` in process `pid` (this process by default).
std::filesystem::path atomic_temporary(const std::filesystem::path& target, pid_t pid = 0);

// Removes the temporaries (TARGET.tmp.OWNER) left in `dir` (and below it when `recursive`) by
// processes of this host that are gone. Best effort: what cannot be listed or removed is skipped.
// Returns how many files were removed.
std::size_t remove_stale_temporaries(const std::filesystem::path& dir, bool recursive = false);

}  // namespace tagbench
