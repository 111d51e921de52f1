#include "tools/hash.hpp"

namespace tagbench {
namespace {

// FNV-1a with the width's offset basis and prime.
template <class Hash>
Hash fnv1a(std::string_view bytes, Hash basis, Hash prime) {
  Hash h = basis;
  for (const unsigned char c : bytes) {
    h ^= c;
    h *= prime;
  }
  return h;
}

}  // namespace

std::uint64_t fnv1a64(std::string_view bytes) {
  return fnv1a<std::uint64_t>(bytes, 0xcbf29ce484222325ULL, 0x100000001b3ULL);
}
std::uint32_t fnv1a32(std::string_view bytes) { return fnv1a<std::uint32_t>(bytes, 0x811c9dc5u, 0x01000193u); }

}  // namespace tagbench
