#pragma once
// A tiny Qt resource bundle writer for the tests (laid out as the corpus README describes:
// breadth-first tree, children of a directory contiguous).
#include <zlib.h>
#include <zstd.h>

#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace rcctest {

enum class Pack { none, zlib, zstd };

struct Node {
  std::string name;
  bool dir = false;
  std::string data;
  Pack pack = Pack::none;
  std::vector<std::unique_ptr<Node>> kids;
  Node* child_dir(const std::string& n) {
    for (auto& k : kids)
      if (k->dir && k->name == n) return k.get();
    kids.push_back(std::make_unique<Node>());
    kids.back()->name = n;
    kids.back()->dir = true;
    return kids.back().get();
  }
};

inline void put16(std::string& s, std::uint32_t v) {
  s += static_cast<char>((v >> 8) & 0xFF);
  s += static_cast<char>(v & 0xFF);
}
inline void put32(std::string& s, std::uint32_t v) {
  put16(s, v >> 16);
  put16(s, v & 0xFFFF);
}
inline void set32(std::string& s, std::size_t off, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s[off + i] = static_cast<char>((v >> (24 - 8 * i)) & 0xFF);
}

class Writer {
 public:
  // path like "a/b/c.png" (no leading slash); name may hold non-ASCII UTF-8 (BMP only).
  void add(const std::string& path, const std::string& data, Pack pack = Pack::none) {
    Node* n = &root_;
    std::size_t start = 0;
    while (true) {
      const auto slash = path.find('/', start);
      if (slash == std::string::npos) break;
      n = n->child_dir(path.substr(start, slash - start));
      start = slash + 1;
    }
    auto f = std::make_unique<Node>();
    f->name = path.substr(start);
    f->data = data;
    f->pack = pack;
    n->kids.push_back(std::move(f));
  }

  std::string bytes(std::uint32_t version) const {
    root_.dir = true;
    // Breadth-first numbering.
    std::vector<const Node*> order{&root_};
    std::map<const Node*, std::uint32_t> first_child;
    for (std::size_t i = 0; i < order.size(); ++i) {
      first_child[order[i]] = static_cast<std::uint32_t>(order.size());
      for (const auto& k : order[i]->kids) order.push_back(k.get());
    }
    std::string names, data;
    std::map<const Node*, std::uint32_t> name_off, data_off;
    for (const Node* n : order) {
      name_off[n] = static_cast<std::uint32_t>(names.size());
      const std::u16string u = utf16(n->name);
      put16(names, static_cast<std::uint32_t>(u.size()));
      put32(names, 0x12345678);  // the hash is not checked by readers of this kind
      for (const char16_t c : u) put16(names, c);
      if (n->dir) continue;
      data_off[n] = static_cast<std::uint32_t>(data.size());
      std::string payload = n->data;
      if (n->pack == Pack::zlib) {
        uLongf len = compressBound(static_cast<uLong>(payload.size()));
        std::string z(len, '\0');
        compress(reinterpret_cast<Bytef*>(z.data()), &len, reinterpret_cast<const Bytef*>(payload.data()),
                 static_cast<uLong>(payload.size()));
        std::string q;
        put32(q, static_cast<std::uint32_t>(payload.size()));
        payload = q + z.substr(0, len);
      } else if (n->pack == Pack::zstd) {
        std::string z(ZSTD_compressBound(payload.size()), '\0');
        z.resize(ZSTD_compress(z.data(), z.size(), payload.data(), payload.size(), 3));
        payload = z;
      }
      put32(data, static_cast<std::uint32_t>(payload.size()));
      data += payload;
    }
    std::string tree;
    for (const Node* n : order) {
      put32(tree, n == &root_ ? 0 : name_off[n]);
      const std::uint16_t flags = n->dir ? 2 : n->pack == Pack::zlib ? 1 : n->pack == Pack::zstd ? 4 : 0;
      put16(tree, flags);
      if (n->dir) {
        put32(tree, static_cast<std::uint32_t>(n->kids.size()));
        put32(tree, first_child.at(n));
      } else {
        put16(tree, 0);  // country
        put16(tree, 1);  // language
        put32(tree, data_off.at(n));
      }
      if (version >= 2) {
        put32(tree, 0);  // last modified, u64
        put32(tree, 0);
      }
    }
    std::string out = "qres";
    put32(out, version);
    put32(out, 0);  // tree offset, set below
    put32(out, 0);  // data
    put32(out, 0);  // names
    if (version >= 3) put32(out, 0);  // overall flags
    set32(out, 12, static_cast<std::uint32_t>(out.size()));
    out += data;
    set32(out, 16, static_cast<std::uint32_t>(out.size()));
    out += names;
    set32(out, 8, static_cast<std::uint32_t>(out.size()));
    out += tree;
    return out;
  }

 private:
  static std::u16string utf16(const std::string& s) {
    std::u16string out;
    for (std::size_t i = 0; i < s.size();) {
      const unsigned char c = static_cast<unsigned char>(s[i]);
      if (c < 0x80) {
        out += c;
        i += 1;
      } else if ((c >> 5) == 6) {
        out += static_cast<char16_t>(((c & 0x1F) << 6) | (s[i + 1] & 0x3F));
        i += 2;
      } else {
        out += static_cast<char16_t>(((c & 0x0F) << 12) | ((s[i + 1] & 0x3F) << 6) | (s[i + 2] & 0x3F));
        i += 3;
      }
    }
    return out;
  }
  mutable Node root_;
};

}  // namespace rcctest
