#pragma once
// Private helper: typed JSON field access whose errors name the JSON path
// (InputError(source, 0, "channels[1].k_um_per_c", why)).
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::thermal::detail {

class JsonFields {
 public:
  explicit JsonFields(std::string source) : source_(std::move(source)) {}
  const std::string& source() const { return source_; }

  [[noreturn]] void Fail(const std::string& path, const std::string& why) const { throw InputError(source_, 0, path, why); }
  static std::string Join(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }
  static std::string Index(const std::string& path, std::size_t i) { return fmt::format("{}[{}]", path, i); }

  const nlohmann::json& Get(const nlohmann::json& obj, const std::string& path, const std::string& key) const {
    if (!obj.is_object()) Fail(path.empty() ? "(top level)" : path, "expected an object");
    auto it = obj.find(key);
    if (it == obj.end()) Fail(Join(path, key), "required field is missing");
    return *it;
  }
  double Number(const nlohmann::json& obj, const std::string& path, const std::string& key) const {
    const auto& v = Get(obj, path, key);
    if (!v.is_number() || !std::isfinite(v.get<double>())) Fail(Join(path, key), "expected a finite number");
    return v.get<double>();
  }
  int Int(const nlohmann::json& obj, const std::string& path, const std::string& key, int lo, int hi) const {
    const auto& v = Get(obj, path, key);
    if (!v.is_number_integer() || v.get<long long>() < lo || v.get<long long>() > hi)
      Fail(Join(path, key), fmt::format("expected an integer in [{}, {}]", lo, hi));
    return v.get<int>();
  }
  std::string String(const nlohmann::json& obj, const std::string& path, const std::string& key) const {
    const auto& v = Get(obj, path, key);
    if (!v.is_string()) Fail(Join(path, key), "expected a string");
    return v.get<std::string>();
  }
  std::vector<double> Numbers(const nlohmann::json& obj, const std::string& path, const std::string& key) const {
    const auto& v = Get(obj, path, key);
    const std::string p = Join(path, key);
    if (!v.is_array()) Fail(p, "expected an array of numbers");
    std::vector<double> out;
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (!v[i].is_number() || !std::isfinite(v[i].get<double>())) Fail(Index(p, i), "expected a finite number");
      out.push_back(v[i].get<double>());
    }
    return out;
  }
  std::vector<std::string> Strings(const nlohmann::json& obj, const std::string& path, const std::string& key) const {
    const auto& v = Get(obj, path, key);
    const std::string p = Join(path, key);
    if (!v.is_array()) Fail(p, "expected an array of strings");
    std::vector<std::string> out;
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (!v[i].is_string() || v[i].get<std::string>().empty()) Fail(Index(p, i), "expected a non-empty string");
      out.push_back(v[i].get<std::string>());
    }
    return out;
  }
  const nlohmann::json& Array(const nlohmann::json& obj, const std::string& path, const std::string& key) const {
    const auto& v = Get(obj, path, key);
    if (!v.is_array() || v.empty()) Fail(Join(path, key), "expected a non-empty array");
    return v;
  }

 private:
  std::string source_;
};

}  // namespace trueaxis::thermal::detail
