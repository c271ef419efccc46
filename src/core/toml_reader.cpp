#include "trueaxis/core/toml_reader.hpp"

#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis {
namespace {
bool AsNumber(const toml::node& n, double& v) {
  if (auto f = n.as_floating_point()) v = f->get();
  else if (auto i = n.as_integer()) v = static_cast<double>(i->get());
  else return false;
  return true;
}
}  // namespace

toml::table ParseTomlOrThrow(std::string_view text, const std::string& source) {
  try {
    return toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    throw InputError(source, static_cast<int>(e.source().begin.line), "", std::string(e.description()));
  }
}

TomlTableReader::TomlTableReader(const toml::table& table, std::string source, std::string prefix)
    : table_(table), source_(std::move(source)), prefix_(std::move(prefix)) {}

int TomlTableReader::Line(const toml::node* node) const {
  return static_cast<int>((node ? node : &table_)->source().begin.line);
}

std::string TomlTableReader::Key(std::string_view key) const {
  return prefix_.empty() ? std::string(key) : prefix_ + "." + std::string(key);
}

void TomlTableReader::Fail(std::string_view key, const toml::node* node, const std::string& why) const {
  throw InputError(source_, Line(node), Key(key), why);
}

const toml::node* TomlTableReader::Node(std::string_view key) {
  seen_.insert(std::string(key));
  return table_.get(key);
}

void TomlTableReader::Double(std::string_view key, double& out, double lo, double hi, bool required) {
  const toml::node* n = Node(key);
  if (!n) {
    if (required) Fail(key, nullptr, "missing (required)");
    return;
  }
  double v = 0;
  if (!AsNumber(*n, v)) Fail(key, n, "must be a number");
  if (!std::isfinite(v) || v < lo || v > hi) Fail(key, n, fmt::format("{} is out of range [{}, {}]", v, lo, hi));
  out = v;
}

void TomlTableReader::Int(std::string_view key, int& out, int lo, int hi) {
  const toml::node* n = Node(key);
  if (!n) return;
  auto i = n->as_integer();
  if (!i) Fail(key, n, "must be an integer");
  if (i->get() < lo || i->get() > hi) Fail(key, n, fmt::format("{} is out of range [{}, {}]", i->get(), lo, hi));
  out = static_cast<int>(i->get());
}

void TomlTableReader::U64(std::string_view key, std::uint64_t& out) {
  const toml::node* n = Node(key);
  if (!n) return;
  auto i = n->as_integer();
  if (!i || i->get() < 0) Fail(key, n, "must be a non-negative integer");
  out = static_cast<std::uint64_t>(i->get());
}

void TomlTableReader::Bool(std::string_view key, bool& out) {
  const toml::node* n = Node(key);
  if (!n) return;
  auto b = n->as_boolean();
  if (!b) Fail(key, n, "must be true or false");
  out = b->get();
}

bool TomlTableReader::String(std::string_view key, std::string& out, bool required) {
  const toml::node* n = Node(key);
  if (!n) {
    if (required) Fail(key, nullptr, "missing (required)");
    return false;
  }
  auto s = n->as_string();
  if (!s) Fail(key, n, "must be a string");
  out = s->get();
  return true;
}

int TomlTableReader::Choice(std::string_view key, std::initializer_list<std::string_view> choices) {
  std::string v;
  if (!String(key, v)) return -1;
  int i = 0;
  for (auto c : choices) {
    if (c == v) return i;
    ++i;
  }
  Fail(key, table_.get(key), fmt::format("'{}' is not one of: {}", v, fmt::join(choices, ", ")));
}

void TomlTableReader::Strings(std::string_view key, std::vector<std::string>& out) {
  const toml::node* n = Node(key);
  if (!n) return;
  auto a = n->as_array();
  if (!a) Fail(key, n, "must be an array of strings");
  out.clear();
  for (const auto& e : *a) {
    auto s = e.as_string();
    if (!s) Fail(key, &e, "must be an array of strings");
    out.push_back(s->get());
  }
}

void TomlTableReader::UniqueStrings(std::string_view key, std::vector<std::string>& out, std::string_view what) {
  Strings(key, out);
  const toml::array* a = table_.get(key) ? table_.get(key)->as_array() : nullptr;
  for (std::size_t i = 0; a && i < out.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (out[j] == out[i]) Fail(key, a->get(i), fmt::format("{} '{}' is listed twice", what, out[i]));
}

void TomlTableReader::Doubles(std::string_view key, std::vector<double>& out, double lo, double hi) {
  const toml::node* n = Node(key);
  if (!n) return;
  auto a = n->as_array();
  if (!a) Fail(key, n, "must be an array of numbers");
  out.clear();
  for (const auto& e : *a) {
    double v = 0;
    if (!AsNumber(e, v)) Fail(key, &e, "must be an array of numbers");
    if (!std::isfinite(v) || v < lo || v > hi) Fail(key, &e, fmt::format("{} is out of range [{}, {}]", v, lo, hi));
    out.push_back(v);
  }
}

const toml::table* TomlTableReader::Table(std::string_view key) {
  const toml::node* n = Node(key);
  if (!n) return nullptr;
  auto t = n->as_table();
  if (!t) Fail(key, n, "must be a table");
  return t;
}

void TomlTableReader::RejectUnknown() const {
  for (const auto& [k, v] : table_)
    if (!seen_.count(std::string(k.str()))) Fail(k.str(), &v, "unknown key");
}

}  // namespace trueaxis
