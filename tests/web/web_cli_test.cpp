// The CLI of the web front end: `trueaxis user add|list|passwd|remove` (password from stdin or a
// file, never the command line) and `trueaxis web` (the demo shop), which refuses to start with
// no user (no default password).
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include <gtest/gtest.h>

#include "store/test_dir.hpp"
#include "support/cli_runner.hpp"
#include "trueaxis/web/access_db.hpp"

namespace trueaxis::web {
namespace {

namespace fs = std::filesystem;
using trueaxis::testing::RunCli;

class WebCliTest : public trueaxis::testing::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    db_ = (dir_ / "users.db").string();
  }
  std::string File(const std::string& name, const std::string& text) const {
    const std::string p = (dir_ / name).string();
    std::ofstream(p) << text;
    return p;
  }
  std::string db_;
};

TEST_F(WebCliTest, UserAddReadsThePasswordFromStdinOrAFileAndStoresOnlyAHash) {
  auto r = RunCli("user add --users " + db_ + " --name chief --role admin < " + File("pw", "chief-password-1\n"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = RunCli("user add --users " + db_ + " --name anna --role operator --password-file " + File("pw2", "anna-password-1\n"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  AccessDb db(db_);
  const auto chief = db.FindUser("chief");
  ASSERT_TRUE(chief);
  EXPECT_EQ(chief->role, Role::kAdmin);
  EXPECT_TRUE(VerifyPassword(chief->password_hash, "chief-password-1"));
  EXPECT_TRUE(VerifyPassword(db.FindUser("anna")->password_hash, "anna-password-1"));
  r = RunCli("user list --users " + db_);
  EXPECT_NE(r.output.find("chief\tadmin"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("argon2"), std::string::npos) << "hashes are not listed";
  r = RunCli("user passwd --users " + db_ + " --name anna < " + File("pw3", "anna-password-2\n"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(VerifyPassword(AccessDb(db_).FindUser("anna")->password_hash, "anna-password-2"));
  r = RunCli("user remove --users " + db_ + " --name anna");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("no admin left"), std::string::npos) << r.output;
  EXPECT_FALSE(AccessDb(db_).FindUser("anna"));
  r = RunCli("user remove --users " + db_ + " --name chief");  // the last admin: done, and said
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: " + db_ + " has no admin left"), std::string::npos) << r.output;
}

TEST_F(WebCliTest, UserAddRefusesBadInputWithExitCode2) {
  EXPECT_EQ(RunCli("user add --users " + db_ + " --name x --role admin < " + File("short", "short\n")).exit_code, 2);
  EXPECT_EQ(RunCli("user add --users " + db_ + " --name x --role boss < " + File("ok", "long-enough-1\n")).exit_code, 2);
  EXPECT_EQ(RunCli("user add --users " + db_ + " --name 'a b' --role admin < " + File("ok2", "long-enough-1\n")).exit_code, 2);
  EXPECT_EQ(RunCli("user add --users " + db_ + " --name y --role admin < /dev/null").exit_code, 2);
  EXPECT_EQ(RunCli("user remove --users " + db_ + " --name nobody").exit_code, 2);
  EXPECT_EQ(RunCli("user list --users " + File("notdb", "this is not a database, it is a text file\n")).exit_code, 2);
}

TEST_F(WebCliTest, WebRefusesToStartWithoutAUserThenServesForItsDuration) {
  auto r = RunCli("web --listen 127.0.0.1:0 --users " + db_ + " --duration-s 1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("user add"), std::string::npos) << r.output;
  ASSERT_EQ(RunCli("user add --users " + db_ + " --name chief --role admin < " + File("pw", "chief-password-1\n")).exit_code, 0);
  r = RunCli("web --listen 127.0.0.1:0 --users " + db_ + " --machines 50 --duration-s 1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("http://127.0.0.1:"), std::string::npos) << r.output;
  EXPECT_EQ(RunCli("web --listen 127.0.0.1 --users " + db_ + " --duration-s 1").exit_code, 2);
  EXPECT_EQ(RunCli("web --listen 127.0.0.1:99999 --users " + db_ + " --duration-s 1").exit_code, 2);
}

}  // namespace
}  // namespace trueaxis::web
