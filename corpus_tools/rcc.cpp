#include "rcc.hpp"

#include <zlib.h>
#include <zstd.h>

#include <stdexcept>

#include "tools/atomic_file.hpp"

namespace tagbench::corpus {

namespace {
constexpr std::uint16_t kCompressed = 1, kDirectory = 2, kCompressedZstd = 4;
constexpr std::uint64_t kMaxEntryBytes = std::uint64_t{1} << 31;  // refuse absurd sizes from corrupt input
// Deflate turns one byte into at most 1032 (a 258-byte match per 2 bits): a zlib entry whose
// stated size is beyond that of its data is corrupt, refused before the size is allocated.
constexpr std::uint64_t kMaxZlibRatio = 1032;
constexpr int kMaxDepth = 256;

void append_utf8(std::string& out, std::uint32_t cp) {
  if (cp < 0x80) {
    out += static_cast<char>(cp);
  } else if (cp < 0x800) {
    out += static_cast<char>(0xC0 | (cp >> 6));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else if (cp < 0x10000) {
    out += static_cast<char>(0xE0 | (cp >> 12));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (cp >> 18));
    out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  }
}
}  // namespace

void RccArchive::fail(const std::string& what) const {
  throw std::runtime_error(name_ + ": corrupt Qt resource bundle: " + what);
}

RccArchive::RccArchive(std::string bytes, std::string name) : bytes_(std::move(bytes)), name_(std::move(name)) {
  const std::uint64_t size = bytes_.size();
  auto need = [&](std::uint64_t off, std::uint64_t len, const char* what) {
    if (off > size || len > size - off)
      fail(std::string(what) + " at offset " + std::to_string(off) + " runs past the end (" + std::to_string(size) +
           " bytes)");
  };
  auto u16 = [&](std::uint64_t off) {
    return static_cast<std::uint16_t>((static_cast<unsigned char>(bytes_[off]) << 8) |
                                      static_cast<unsigned char>(bytes_[off + 1]));
  };
  auto u32 = [&](std::uint64_t off) {
    return (std::uint32_t{u16(off)} << 16) | u16(off + 2);
  };

  if (size < 4 || bytes_.compare(0, 4, "qres") != 0) fail("no 'qres' magic");
  need(4, 16, "header");
  version_ = u32(4);
  const std::uint32_t tree = u32(8), data = u32(12), names = u32(16);
  if (version_ < 1 || version_ > 3) fail("unknown version " + std::to_string(version_));
  const std::uint64_t node_size = version_ == 1 ? 14 : 22;

  auto name_of = [&](std::uint32_t rel) {
    const std::uint64_t off = std::uint64_t{names} + rel;
    need(off, 6, "name");
    const std::uint16_t len = u16(off);
    need(off + 6, std::uint64_t{len} * 2, "name characters");
    std::string out;
    for (std::uint64_t i = 0; i < len; ++i) {
      std::uint32_t c = u16(off + 6 + 2 * i);
      if (c >= 0xD800 && c < 0xDC00 && i + 1 < len) {
        const std::uint32_t lo = u16(off + 6 + 2 * (i + 1));
        if (lo >= 0xDC00 && lo < 0xE000) {
          c = 0x10000 + ((c - 0xD800) << 10) + (lo - 0xDC00);
          ++i;
        }
      }
      if (c == '/' || c == 0) fail("a name contains '/' or NUL");
      append_utf8(out, c);
    }
    if (out.empty() || out == "." || out == "..") fail("an empty, '.' or '..' name");
    return out;
  };

  std::vector<bool> seen;
  // Iterative walk: (node index, parent path, depth).
  struct Item {
    std::uint32_t node;
    std::string prefix;
    int depth;
  };
  std::vector<Item> stack{{0, "", 0}};
  while (!stack.empty()) {
    Item it = std::move(stack.back());
    stack.pop_back();
    const std::uint64_t off = std::uint64_t{tree} + std::uint64_t{it.node} * node_size;
    need(off, node_size, ("tree node " + std::to_string(it.node)).c_str());
    if (it.node >= seen.size()) seen.resize(std::uint64_t{it.node} + 1, false);
    if (seen[it.node]) fail("tree node " + std::to_string(it.node) + " is reached twice (a cycle)");
    seen[it.node] = true;
    const std::uint16_t flags = u16(off + 4);
    const bool is_root = it.depth == 0;
    const std::string path = is_root ? std::string() : it.prefix + "/" + name_of(u32(off));
    if (flags & kDirectory) {
      if (it.depth >= kMaxDepth) fail("directories nested deeper than " + std::to_string(kMaxDepth));
      const std::uint32_t count = u32(off + 6), first = u32(off + 10);
      if (count == 0) continue;
      const std::uint64_t last = std::uint64_t{first} + count - 1;
      need(std::uint64_t{tree} + first * node_size, count * node_size,
           ("children of tree node " + std::to_string(it.node)).c_str());
      for (std::uint64_t c = last + 1; c-- > first;)
        stack.push_back({static_cast<std::uint32_t>(c), path, it.depth + 1});
    } else {
      if (is_root) fail("the root node is not a directory");
      const std::uint64_t doff = std::uint64_t{data} + u32(off + 10);
      need(doff, 4, ("data size of " + path).c_str());
      need(doff + 4, u32(doff), ("data of " + path).c_str());
      if ((flags & kCompressed) && (flags & kCompressedZstd)) fail(path + " is flagged both zlib and zstd");
      files_.push_back({path, flags, static_cast<std::uint32_t>(doff)});
    }
  }
}

RccArchive RccArchive::open(const std::filesystem::path& file) { return RccArchive(read_file(file), file.string()); }

std::vector<std::string> RccArchive::paths() const {
  std::vector<std::string> out;
  out.reserve(files_.size());
  for (const auto& f : files_) out.push_back(f.path);
  return out;
}

std::optional<std::string> RccArchive::read(const std::string& path) const {
  for (const auto& f : files_)
    if (f.path == path) return decode(f);
  return std::nullopt;
}

std::vector<RccEntry> RccArchive::entries() const {
  std::vector<RccEntry> out;
  out.reserve(files_.size());
  for (const auto& f : files_) out.push_back({f.path, decode(f)});
  return out;
}

std::string RccArchive::decode(const File& f) const {
  const auto* p = reinterpret_cast<const unsigned char*>(bytes_.data()) + f.data_offset;
  const std::uint32_t len = (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
  const unsigned char* payload = p + 4;  // the constructor checked [payload, payload + len) is inside
  if (f.flags & kCompressed) {
    if (len < 4) fail(f.path + ": zlib entry shorter than its size field");
    const std::uint64_t expect = (std::uint64_t{payload[0]} << 24) | (std::uint64_t{payload[1]} << 16) |
                                 (std::uint64_t{payload[2]} << 8) | payload[3];
    if (expect > kMaxEntryBytes || expect > (std::uint64_t{len} - 4) * kMaxZlibRatio)
      fail(f.path + ": zlib entry claims " + std::to_string(expect) + " bytes from " + std::to_string(len - 4));
    std::string out(expect, '\0');
    uLongf out_len = static_cast<uLongf>(expect);
    const int rc = uncompress(reinterpret_cast<Bytef*>(out.data()), &out_len, payload + 4, len - 4);
    if (rc != Z_OK || out_len != expect)
      fail(f.path + ": zlib data does not inflate to its stated " + std::to_string(expect) + " bytes (zlib error " +
           std::to_string(rc) + ")");
    return out;
  }
  if (f.flags & kCompressedZstd) {
    const unsigned long long stated = ZSTD_getFrameContentSize(payload, len);
    if (stated == ZSTD_CONTENTSIZE_ERROR) fail(f.path + ": not a zstd frame");
    const bool known = stated != ZSTD_CONTENTSIZE_UNKNOWN;
    if (known && stated > kMaxEntryBytes) fail(f.path + ": zstd entry claims " + std::to_string(stated) + " bytes");
    // Streamed whether or not the frame states its size: the stated size is only a header field,
    // so memory must follow the data actually decompressed (a few corrupt bytes must not make us
    // allocate up to kMaxEntryBytes).
    std::string out;
    ZSTD_DStream* ds = ZSTD_createDStream();
    ZSTD_initDStream(ds);
    ZSTD_inBuffer in{payload, len, 0};
    std::string chunk(1 << 16, '\0');
    std::size_t rc = 1;
    while (in.pos < in.size || rc != 0) {
      ZSTD_outBuffer ob{chunk.data(), chunk.size(), 0};
      rc = ZSTD_decompressStream(ds, &ob, &in);
      if (ZSTD_isError(rc) || (ob.pos == 0 && in.pos == in.size && rc != 0) || out.size() > kMaxEntryBytes ||
          (known && out.size() + ob.pos > stated)) {
        ZSTD_freeDStream(ds);
        fail(f.path + (known && !ZSTD_isError(rc) && out.size() + ob.pos > stated
                           ? ": zstd data does not decompress to its stated size"
                           : ": zstd data is corrupt or truncated"));
      }
      out.append(chunk.data(), ob.pos);
    }
    ZSTD_freeDStream(ds);
    if (known && out.size() != stated) fail(f.path + ": zstd data does not decompress to its stated size");
    return out;
  }
  return std::string(reinterpret_cast<const char*>(payload), len);
}

std::vector<RccEntry> read_rcc(std::string bytes, const std::string& name) {
  return RccArchive(std::move(bytes), name).entries();
}

std::vector<RccEntry> read_rcc_file(const std::filesystem::path& file) { return RccArchive::open(file).entries(); }

}  // namespace tagbench::corpus
