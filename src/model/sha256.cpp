#include "trueaxis/model/sha256.hpp"

#include <sodium.h>

#include <stdexcept>

#include "trueaxis/core/text_file.hpp"

namespace trueaxis::model {

std::string Sha256Hex(std::string_view bytes) {
  // sodium_init is idempotent and thread-safe; hashing itself needs no init,
  // but calling it keeps libsodium's CPU-feature selection deterministic.
  if (sodium_init() < 0) throw std::runtime_error("libsodium could not be initialised");
  unsigned char digest[crypto_hash_sha256_BYTES];
  crypto_hash_sha256(digest, reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size());
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(2 * sizeof digest);
  for (unsigned char b : digest) {
    out.push_back(kHex[b >> 4]);
    out.push_back(kHex[b & 0xF]);
  }
  return out;
}

std::string Sha256OfFile(const std::string& path) { return Sha256Hex(ReadFileBytes(path)); }

}  // namespace trueaxis::model
