#pragma once
// Passwords are stored only as argon2id hashes (libsodium crypto_pwhash_str: a random salt and
// the cost parameters are kept in the string, so a stronger cost later still verifies old ones).
#include <string>
#include <string_view>

namespace trueaxis::web {

enum class HashCost {
  kInteractive,  // libsodium's INTERACTIVE limits (64 MiB, 2 passes): the default for users
  kMinimum,      // the smallest libsodium allows: tests only
};

std::string HashPassword(std::string_view password, HashCost cost = HashCost::kInteractive);
bool VerifyPassword(const std::string& hash, std::string_view password);
// A string of `bytes` random bytes in lower-case hex (session ids, CSRF tokens).
std::string RandomToken(std::size_t bytes = 32);
// Compares two strings in time independent of where they differ.
bool ConstantTimeEquals(std::string_view a, std::string_view b);

}  // namespace trueaxis::web
