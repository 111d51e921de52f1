#pragma once
// Whole-file writes that never leave a half file: write to a temporary beside the target, flush,
// then rename over it (rename is atomic on POSIX within one file system).
#include <filesystem>
#include <string_view>

namespace tagbench {

// Throws std::runtime_error naming the path and the system's reason on any failure; on failure the
// target is untouched and the temporary removed.
void write_file_atomic(const std::filesystem::path& target, std::string_view content);

// Reads a whole file; throws std::runtime_error naming the path if it cannot.
std::string read_file(const std::filesystem::path& path);

}  // namespace tagbench
