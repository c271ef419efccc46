// trueaxis user add|passwd|remove|list --users FILE …
// The web front end's users (docs/web.md): argon2id hashes in a SQLite file. There is no default
// password: the first admin is made here. The password is read from --password-file (first line)
// or from standard input (prompted twice, not echoed, on a terminal) — never from the command line.
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "command.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/web/access_db.hpp"

namespace {

using namespace trueaxis;

struct Options {
  std::string users, name, role = "viewer", password_file;
};

std::string StripEol(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
  return s;
}

std::string ReadHidden(const char* prompt) {
  fmt::print(stderr, "{}", prompt);
  termios old{};
  const bool tty = tcgetattr(STDIN_FILENO, &old) == 0;
  if (tty) {
    termios quiet = old;
    quiet.c_lflag &= ~static_cast<tcflag_t>(ECHO);
    tcsetattr(STDIN_FILENO, TCSANOW, &quiet);
  }
  std::string line;
  std::getline(std::cin, line);
  if (tty) tcsetattr(STDIN_FILENO, TCSANOW, &old);
  fmt::print(stderr, "\n");
  return StripEol(line);
}

std::string ReadPassword(const Options& o) {
  if (!o.password_file.empty()) {
    std::ifstream in(o.password_file);
    if (!in) throw InputError(o.password_file, "cannot read the password file");
    std::string line;
    std::getline(in, line);
    return StripEol(line);
  }
  if (isatty(STDIN_FILENO)) {
    const std::string a = ReadHidden("Password: ");
    if (ReadHidden("Again: ") != a) throw InputError("stdin", 0, "password", "the two passwords differ");
    return a;
  }
  std::string line;
  if (!std::getline(std::cin, line)) throw InputError("stdin", 0, "password", "no password on standard input");
  return StripEol(line);
}

web::Role RoleOrThrow(const std::string& s) {
  const auto r = web::ParseRole(s);
  if (!r) throw InputError("--role", 0, "role", "'" + s + "' is not viewer, operator or admin");
  return *r;
}

// passwd, remove and list work on a users database that exists: opening a missing one created an
// empty file, and `user list` of a mistyped path printed nothing and exited 0 — "no users".
// Only `user add` creates the database (docs/web.md).
void RequireUsersFile(const std::string& path) {
  std::error_code ec;
  const auto type = std::filesystem::status(path, ec).type();
  if (type == std::filesystem::file_type::not_found)
    throw InputError("command line", 0, "--users",
                     "'" + path + "' does not exist (`trueaxis user add` creates a users database)");
  if (type == std::filesystem::file_type::directory)
    throw InputError("command line", 0, "--users", "'" + path + "' is a folder, not a users database");
}

void Setup(CLI::App& app) {
  auto o = std::make_shared<Options>();
  CLI::App* user = app.add_subcommand("user", "Users of the web front end (argon2id hashes; docs/web.md)");
  user->require_subcommand(1);
  auto users_option = [o](CLI::App* c) {
    c->add_option("--users", o->users, "User and audit-log database (SQLite; `user add` creates a missing one)")->required();
  };

  CLI::App* add = user->add_subcommand("add", "Add a user (password from --password-file or standard input)");
  users_option(add);
  add->add_option("--name", o->name, "User name")->required();
  add->add_option("--role", o->role, "viewer, operator or admin")->capture_default_str();
  add->add_option("--password-file", o->password_file, "Read the password from the first line of this file");
  add->callback([o] {
    const web::Role role = RoleOrThrow(o->role);
    web::AccessDb db(o->users);
    web::CheckUserName(o->name);
    db.AddUser(o->name, role, ReadPassword(*o));
    db.Record({0, "", 0, "", "", "cli", "user_add", o->name, std::string(web::RoleName(role)), "ok"});
    fmt::print("user {} added ({}) to {}\n", o->name, web::RoleName(role), o->users);
  });

  CLI::App* passwd = user->add_subcommand("passwd", "Set a user's password (standard input or --password-file)");
  users_option(passwd);
  passwd->add_option("--name", o->name, "User name")->required();
  passwd->add_option("--password-file", o->password_file, "Read the password from the first line of this file");
  passwd->callback([o] {
    RequireUsersFile(o->users);
    web::AccessDb db(o->users);
    db.SetPassword(o->name, ReadPassword(*o));
    db.Record({0, "", 0, "", "", "cli", "user_passwd", o->name, "", "ok"});
    fmt::print("password of {} changed (the user's open sessions end at their next request)\n", o->name);
  });

  CLI::App* remove = user->add_subcommand("remove", "Remove a user");
  users_option(remove);
  remove->add_option("--name", o->name, "User name")->required();
  remove->callback([o] {
    RequireUsersFile(o->users);
    web::AccessDb db(o->users);
    if (!db.RemoveUser(o->name)) throw InputError(o->users, 0, "name", "no user '" + o->name + "'");
    db.Record({0, "", 0, "", "", "cli", "user_remove", o->name, "", "ok"});
    fmt::print("user {} removed\n", o->name);
    const auto users = db.Users();
    if (std::none_of(users.begin(), users.end(), [](const web::UserRecord& u) { return u.role == web::Role::kAdmin; }))
      fmt::print(stderr,
                 "warning: {} has no admin left: nobody can manage users or switch compensation from the web front end "
                 "until `trueaxis user add --users {} --role admin …`\n",
                 o->users, o->users);
  });

  CLI::App* list = user->add_subcommand("list", "List the users and their roles");
  users_option(list);
  list->callback([o] {
    RequireUsersFile(o->users);
    web::AccessDb db(o->users);
    for (const auto& u : db.Users()) fmt::print("{}\t{}\t{}\n", u.name, web::RoleName(u.role), u.created_utc);
  });
}

trueaxis::cli::CommandRegistrar reg("user", Setup);

}  // namespace
