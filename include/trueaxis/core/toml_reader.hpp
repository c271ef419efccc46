#pragma once
// Checked reading of one TOML table (toml++), shared by every TOML file
// trueaxis reads (machine description, run configuration).
//
// Every accessor records the key as known; RejectUnknown() then fails on any
// other key, because a typo silently falling back to a default makes a wrong
// machine that looks right. Failures throw InputError(source, line, key, why)
// with the key's dotted path (e.g. "axis[0].pitch.progressive_um").
#include <cstdint>
#include <initializer_list>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

namespace trueaxis {

// Parses TOML text; a syntax error becomes InputError(source, line, "", why).
toml::table ParseTomlOrThrow(std::string_view text, const std::string& source);

class TomlTableReader {
 public:
  TomlTableReader(const toml::table& table, std::string source, std::string prefix);

  int Line(const toml::node* node) const;                 // the node's line, or the table's
  std::string Key(std::string_view key) const;           // dotted path of `key`
  [[noreturn]] void Fail(std::string_view key, const toml::node* node, const std::string& why) const;

  const toml::node* Node(std::string_view key);          // nullptr when absent
  // Each setter leaves `out` unchanged when the key is absent (unless required).
  void Double(std::string_view key, double& out, double lo, double hi, bool required = false);
  void Int(std::string_view key, int& out, int lo, int hi);
  void U64(std::string_view key, std::uint64_t& out);
  void Bool(std::string_view key, bool& out);
  bool String(std::string_view key, std::string& out, bool required = false);  // true when present
  // A string that must be one of `choices`: its index, or -1 when absent.
  int Choice(std::string_view key, std::initializer_list<std::string_view> choices);
  void Strings(std::string_view key, std::vector<std::string>& out);
  // Strings() of names that must differ (axes, channels): a repeated name fails at its element's
  // line, saying "<what> 'X' is listed twice" (two axes "X" made one axis get two corrections).
  void UniqueStrings(std::string_view key, std::vector<std::string>& out, std::string_view what);
  void Doubles(std::string_view key, std::vector<double>& out, double lo, double hi);
  const toml::table* Table(std::string_view key);       // nullptr when absent
  void RejectUnknown() const;
  const std::string& source() const { return source_; }

 private:
  const toml::table& table_;
  std::string source_;
  std::string prefix_;
  std::set<std::string> seen_;
};

}  // namespace trueaxis
