#pragma once
// Whole-file writes that never leave a half file: write to a temporary beside the target, flush,
// then rename over it (rename is atomic on POSIX within one file system).
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace tagbench {

// Throws std::runtime_error naming the path and the system's reason on any failure; on failure the
// target is untouched and the temporary removed.
void write_file_atomic(const std::filesystem::path& target, std::string_view content);

// Several files as one result: every temporary is written before any is renamed, so a failure (a
// full disk, say) leaves none of them, rather than the first few of a set.
void write_files_atomic(const std::vector<std::pair<std::filesystem::path, std::string>>& files);

// Reads a whole file; throws std::runtime_error naming the path if it cannot.
std::string read_file(const std::filesystem::path& path);

}  // namespace tagbench
