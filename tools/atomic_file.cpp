#include "tools/atomic_file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "tools/hash.hpp"

namespace tagbench {

namespace {

// 8 hex digits of FNV-1a 32 of the host name: short, and the same in every process of the host.
const std::string& host_hash() {
  static const std::string h = [] {
    char name[256] = {};
    if (::gethostname(name, sizeof name - 1) != 0) name[0] = '\0';
    char buf[9];
    std::snprintf(buf, sizeof buf, "%08x", fnv1a32(name));
    return std::string(buf);
  }();
  return h;
}

std::filesystem::path temporary_for(const std::filesystem::path& target) { return atomic_temporary(target); }

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

std::string owner_tag(pid_t pid) { return std::to_string(pid) + "-" + host_hash(); }
std::string owner_tag() { return owner_tag(::getpid()); }

bool owner_is_gone(std::string_view tag) {
  const auto dash = tag.find('-');
  if (dash == std::string_view::npos || dash == 0 || dash > 9 || tag.substr(dash + 1) != host_hash()) return false;
  long pid = 0;
  for (const char c : tag.substr(0, dash)) {
    if (c < '0' || c > '9') return false;
    pid = pid * 10 + (c - '0');
  }
  if (pid <= 0 || pid == ::getpid()) return false;
  // EPERM: it exists under another user. A zombie still counts as alive (its parent has not reaped it).
  return ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
}

bool owner_prefix_is_gone(std::string_view name) {
  const auto dash1 = name.find('-');
  const auto dash2 = dash1 == std::string_view::npos ? std::string_view::npos : name.find('-', dash1 + 1);
  return dash2 != std::string_view::npos && owner_is_gone(name.substr(0, dash2));
}

std::filesystem::path atomic_temporary(const std::filesystem::path& target, pid_t pid) {
  return target.string() + ".tmp." + owner_tag(pid > 0 ? pid : ::getpid());
}

std::size_t remove_stale_temporaries(const std::filesystem::path& dir, bool recursive) {
  namespace fs = std::filesystem;
  std::size_t removed = 0;
  const auto consider = [&](const fs::directory_entry& e) {
    std::error_code ec;
    if (!e.is_regular_file(ec) || e.is_symlink(ec)) return;
    const std::string name = e.path().filename().string();
    const auto at = name.rfind(".tmp.");
    if (at == std::string::npos || at == 0) return;
    if (owner_is_gone(std::string_view(name).substr(at + 5)) && fs::remove(e.path(), ec)) ++removed;
  };
  std::error_code ec;
  if (recursive) {
    fs::recursive_directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec), end;
    for (; !ec && it != end; it.increment(ec)) consider(*it);
  } else {
    fs::directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec), end;
    for (; !ec && it != end; it.increment(ec)) consider(*it);
  }
  return removed;
}

std::filesystem::path write_destination(const std::filesystem::path& target) {
  namespace fs = std::filesystem;
  fs::path p = target;
  std::error_code ec;
  for (int hops = 0; fs::is_symlink(fs::symlink_status(p, ec)); ++hops) {
    if (hops == 40) throw std::runtime_error("cannot write " + target.string() + ": too many levels of symbolic links");
    const fs::path next = fs::read_symlink(p, ec);
    if (ec) throw std::runtime_error("cannot write " + target.string() + ": " + ec.message());
    p = next.is_absolute() ? next : p.parent_path() / next;
  }
  const fs::file_status st = fs::status(p, ec);
  if (fs::exists(st) && !fs::is_regular_file(st))
    throw std::runtime_error("cannot write " + target.string() + ": " +
                             (fs::is_directory(st) ? "is a directory" : "not a regular file (a device, FIFO or socket)"));
  return p;
}

void write_file_atomic(const std::filesystem::path& target, std::string_view content) {
  const std::filesystem::path dest = write_destination(target);
  write_temporary(dest, content);
  rename_temporary(dest);
}

void write_files_atomic(const std::vector<std::pair<std::filesystem::path, std::string>>& files) {
  std::vector<std::filesystem::path> dest;
  for (const auto& f : files) dest.push_back(write_destination(f.first));  // all checked before any is written
  std::size_t staged = 0;
  try {
    for (; staged < files.size(); ++staged) write_temporary(dest[staged], files[staged].second);
  } catch (...) {
    for (std::size_t i = 0; i < staged; ++i) ::unlink(temporary_for(dest[i]).c_str());
    throw;
  }
  // Renames within a folder do not fail for want of space; should one fail anyway, the temporaries
  // not yet renamed go too.
  for (std::size_t i = 0; i < files.size(); ++i) {
    try {
      rename_temporary(dest[i]);
    } catch (...) {
      for (std::size_t k = i + 1; k < files.size(); ++k) ::unlink(temporary_for(dest[k]).c_str());
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
