// bench/zoo_refit.py (issue 10's model studies): a zoo run re-fitted with other fit options, its
// day's on and off tests scored again without running the day. Run on one small zoo machine: with
// no options the re-fit is the run's own model (every row as the run's); with another option the
// rows change; bad input is refused with a message and exit 1 (as is a zoo_table.py run whose demo
// fails).
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <utility>

namespace fs = std::filesystem;

namespace {

class ZooRefit : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::temp_directory_path() / ("zoo_refit_test_" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_);
    const auto [rc, text] = Run("bench/zoo_table.py --seed 3 --out " + (*dir_ / "zoo").string() +
                                " examples/machines/vmc400_small.toml");
    ASSERT_EQ(rc, 0) << text;
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
  }
  // One bench script from the source tree with the test's trueaxis: exit status and output.
  static std::pair<int, std::string> Run(const std::string& script_and_args) {
    const fs::path out = *dir_ / "out.txt";
    const std::string cmd = "cd " + std::string(TRUEAXIS_SOURCE_DIR) + " && /usr/bin/python3 " + script_and_args +
                            " --trueaxis " + TRUEAXIS_CLI_PATH + " > " + out.string() + " 2>&1";
    const int rc = std::system(cmd.c_str());
    std::stringstream text;
    text << std::ifstream(out).rdbuf();
    return {WEXITSTATUS(rc), text.str()};
  }
  static std::string Refit(const std::string& args, int* rc) {
    auto [code, text] = Run("bench/zoo_refit.py --run " + (*dir_ / "zoo").string() + " " + args);
    *rc = code;
    return text;
  }
  static fs::path* dir_;
};
fs::path* ZooRefit::dir_ = nullptr;

int RowsChanged(const std::string& text) {
  std::smatch m;
  if (!std::regex_search(text, m, std::regex(R"((\d+) rows changed by more than)"))) return -1;
  return std::stoi(m[1]);
}

TEST_F(ZooRefit, NoOptionsGiveTheRunsOwnModelAndAnotherOptionChangesTheRows) {
  int rc = -1;
  const std::string same = Refit("", &rc);
  ASSERT_EQ(rc, 0) << same;
  EXPECT_NE(same.find("15 rows re-fitted"), std::string::npos) << same;
  EXPECT_EQ(RowsChanged(same), 0) << same;
  EXPECT_EQ(same.find("without a prediction"), std::string::npos) << same;
  // No lag on the keys: another model, so the day's rows come out differently.
  const std::string other = Refit("--fit-options \"--lag-grid-s 0\"", &rc);
  ASSERT_EQ(rc, 0) << other;
  EXPECT_GT(RowsChanged(other), 0) << other;
  // An option that starts with "--" and has no value is passed on, not taken for the script's.
  const std::string flag = Refit("--fit-options --coolant-soak", &rc);
  EXPECT_EQ(rc, 0) << flag;
}

TEST_F(ZooRefit, BadInputIsRefusedWithAMessage) {
  int rc = -1;
  std::string text = Refit("nosuch", &rc);
  EXPECT_EQ(rc, 1);
  EXPECT_NE(text.find("nosuch: no campaign/manifest.json"), std::string::npos) << text;
  text = Refit("--fit-options --bogus", &rc);
  EXPECT_EQ(rc, 1);
  EXPECT_NE(text.find("trueaxis fit failed"), std::string::npos) << text;
  EXPECT_NE(text.find("--bogus"), std::string::npos) << text;
  const auto [run_rc, run_text] = Run("bench/zoo_refit.py --run " + (*dir_ / "empty").string());
  EXPECT_EQ(run_rc, 1);
  EXPECT_NE(run_text.find("no machine directories"), std::string::npos) << run_text;
  // zoo_table.py: a machine whose demo fails fails the run (it was exit 0 with a note in the table).
  const auto [table_rc, table_text] = Run("bench/zoo_table.py --out " + (*dir_ / "bad").string() + " nosuch.toml");
  EXPECT_EQ(table_rc, 1);
  EXPECT_NE(table_text.find("demo failed"), std::string::npos) << table_text;
}

}  // namespace
