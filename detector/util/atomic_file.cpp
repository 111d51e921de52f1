#include "util/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace tagbench {

namespace {

std::filesystem::path temporary_for(const std::filesystem::path& target) {
  return target.string() + ".tmp." + std::to_string(::getpid());
}

// Writes `content` to target's temporary and syncs it; on failure removes it and throws.
void write_temporary(const std::filesystem::path& target, std::string_view content) {
  const std::filesystem::path tmp = temporary_for(target);
  const auto fail = [&](const char* what) {
    const std::string reason = std::strerror(errno);
    ::unlink(tmp.c_str());
    throw std::runtime_error("cannot write " + target.string() + ": " + what + ": " + reason);
  };
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    const std::string reason = std::strerror(errno);
    throw std::runtime_error("cannot write " + target.string() + ": " + reason);
  }
  std::size_t off = 0;
  while (off < content.size()) {
    const ssize_t w = ::write(fd, content.data() + off, content.size() - off);
    if (w < 0) {
      if (errno == EINTR) continue;
      ::close(fd);
      fail("write");
    }
    off += static_cast<std::size_t>(w);
  }
  if (::fsync(fd) != 0) { ::close(fd); fail("fsync"); }
  if (::close(fd) != 0) fail("close");
}

void rename_temporary(const std::filesystem::path& target) {
  const std::filesystem::path tmp = temporary_for(target);
  if (::rename(tmp.c_str(), target.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    ::unlink(tmp.c_str());
    throw std::runtime_error("cannot write " + target.string() + ": rename: " + reason);
  }
}

}  // namespace

void write_file_atomic(const std::filesystem::path& target, std::string_view content) {
  write_temporary(target, content);
  rename_temporary(target);
}

void write_files_atomic(const std::vector<std::pair<std::filesystem::path, std::string>>& files) {
  std::size_t staged = 0;
  try {
    for (; staged < files.size(); ++staged) write_temporary(files[staged].first, files[staged].second);
  } catch (...) {
    for (std::size_t i = 0; i < staged; ++i) ::unlink(temporary_for(files[i].first).c_str());
    throw;
  }
  // Renames within a folder do not fail for want of space; should one fail anyway, the temporaries
  // not yet renamed go too.
  for (std::size_t i = 0; i < files.size(); ++i) {
    try {
      rename_temporary(files[i].first);
    } catch (...) {
      for (std::size_t k = i + 1; k < files.size(); ++k) ::unlink(temporary_for(files[k].first).c_str());
      throw;
    }
  }
}

std::string read_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw std::runtime_error(path.string() + ": is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot open: " + std::strerror(errno));
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw std::runtime_error(path.string() + ": read error");
  return ss.str();
}

}  // namespace tagbench
