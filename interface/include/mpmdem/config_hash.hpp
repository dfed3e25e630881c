// Hash of the shared `coupling:` section, exchanged in the handshake so that both sides
// prove they read the same coupling settings. The caller canonicalises the section
// (see config/canonical.hpp); this is FNV-1a 64 over those bytes.
#pragma once

#include <cstdint>
#include <string_view>

namespace mpmdem {

inline std::uint64_t fnv1a64(std::string_view bytes) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return h;
}

}  // namespace mpmdem
