#pragma once
// Roles of the web front end, in increasing rights: a viewer watches, an operator also operates
// the machines (axis enable, alarm acknowledge, coolant override, export), an admin also changes
// models and reads the audit log (docs/web.md, *Roles*).
#include <optional>
#include <string_view>

namespace trueaxis::web {

enum class Role : int { kViewer = 0, kOperator = 1, kAdmin = 2 };

inline constexpr std::string_view RoleName(Role r) {
  switch (r) {
    case Role::kViewer: return "viewer";
    case Role::kOperator: return "operator";
    case Role::kAdmin: return "admin";
  }
  return "viewer";
}
inline std::optional<Role> ParseRole(std::string_view s) {
  if (s == "viewer") return Role::kViewer;
  if (s == "operator") return Role::kOperator;
  if (s == "admin") return Role::kAdmin;
  return std::nullopt;
}
inline constexpr bool HasRole(Role have, Role need) { return static_cast<int>(have) >= static_cast<int>(need); }

}  // namespace trueaxis::web
