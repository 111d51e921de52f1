#pragma once
// A reader for Qt resource bundles (the binary .rcc files that `rcc -binary` writes), written from
// the format description in shared/corpus/README.md: magic "qres", four big-endian u32 (version,
// tree offset, data offset, names offset), tree nodes of 14 bytes (version 1) or 22 bytes (later),
// UTF-16BE names, file data as u32 size + bytes, flag 1 = zlib (qCompress: u32 uncompressed size
// first), flag 4 = zstd. Every offset is checked: corrupt input is a one-line std::runtime_error
// naming the bundle and the problem.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace tagbench::corpus {

struct RccEntry {
  std::string path;  // "/dir/sub/file.webp" (UTF-8, leading slash, as Qt's ":/dir/sub/file.webp")
  std::string data;  // the file's bytes, decompressed
};

class RccArchive {
 public:
  // Parses the header and walks the whole tree (names and data extents checked); file data is
  // decompressed only on read(). `name` is used in error messages (usually the file's path).
  RccArchive(std::string bytes, std::string name);
  static RccArchive open(const std::filesystem::path& file);

  std::uint32_t version() const { return version_; }
  // Every file's path, in tree order.
  std::vector<std::string> paths() const;
  // The bytes of one file, decompressed; nullopt if no such path.
  std::optional<std::string> read(const std::string& path) const;
  // Every file with its bytes.
  std::vector<RccEntry> entries() const;

 private:
  struct File {
    std::string path;
    std::uint16_t flags;
    std::uint32_t data_offset;  // absolute offset of the u32 size field
  };
  std::string decode(const File& f) const;
  [[noreturn]] void fail(const std::string& what) const;

  std::string bytes_, name_;
  std::uint32_t version_ = 0;
  std::vector<File> files_;
};

// Convenience: all entries of a bundle in memory or on disk.
std::vector<RccEntry> read_rcc(std::string bytes, const std::string& name);
std::vector<RccEntry> read_rcc_file(const std::filesystem::path& file);

}  // namespace tagbench::corpus
