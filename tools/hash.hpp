#pragma once
// FNV-1a (Fowler-Noll-Vo) over bytes: the cache keys of rendered frames, the candidate store's
// checksums and corpus-list digests, the host part of owner tags. Not cryptographic: it tells
// apart inputs nobody crafts to collide. The values are written into files, so they never change.
#include <cstdint>
#include <string_view>

namespace tagbench {

std::uint64_t fnv1a64(std::string_view bytes);
std::uint32_t fnv1a32(std::string_view bytes);

}  // namespace tagbench
