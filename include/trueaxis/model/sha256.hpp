#pragma once
// SHA-256 of bytes and files (libsodium's crypto_hash_sha256), lower-case hex.
// Used for the model's lineage: every source file and the parent model are
// recorded by hash, so a model can be traced to exactly the data it came from.
#include <string>
#include <string_view>

namespace trueaxis::model {

std::string Sha256Hex(std::string_view bytes);
// Reads the whole file; InputError naming the path when it cannot be read.
std::string Sha256OfFile(const std::string& path);

}  // namespace trueaxis::model
