#include "tools/hash.hpp"

namespace tagbench {

std::uint64_t fnv1a64(std::string_view bytes) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  return h;
}

std::uint32_t fnv1a32(std::string_view bytes) {
  std::uint32_t h = 0x811c9dc5u;
  for (const unsigned char c : bytes) {
    h ^= c;
    h *= 0x01000193u;
  }
  return h;
}

}  // namespace tagbench
