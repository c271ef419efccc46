// A thermal-model campaign as a user runs it on a real machine, played against the virtual machine
// served over MODBUS TCP on 127.0.0.1 (`trueaxis sim serve`, an independent process) through only
// the channels a real machine has: `campaign log` records the terminal's temperatures, positions,
// travelled paths and coolant while the machine warms up (stopped and started again half-way: the
// log goes on); the laser files come from the served machine's laser (its own clock's date, a time
// per point, no machine sensors); `campaign add` stamps each on the campaign clock with the logged
// temperatures; `fit` fits the manifest; `predict` replays a held-out warm-up test.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace {
namespace fs = std::filesystem;

const std::string kCli = TRUEAXIS_CLI_PATH;
const std::string kMachine = std::string(TRUEAXIS_SOURCE_DIR) + "/examples/machines/vmc850.toml";
constexpr double kScale = 600;  // machine seconds per wall second

std::string Slurp(const fs::path& p) {
  std::stringstream s;
  s << std::ifstream(p).rdbuf();
  return s.str();
}

std::pair<int, std::string> RunTrueaxis(const std::string& args, const fs::path& out) {
  const int rc = std::system((kCli + " " + args + " > " + out.string() + " 2>&1").c_str());
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, Slurp(out)};
}

double NumberAfter(const std::string& text, const std::string& label) {
  const std::regex re(label + R"(\s+ISO 230-2 A\s+([0-9.]+))");
  std::smatch m;
  if (!std::regex_search(text, m, re)) return -1;
  return std::stod(m[1]);
}

TEST(CampaignRealMachine, LogAddFitAgainstTheServedMachine) {
  const fs::path dir = fs::temp_directory_path() / ("trueaxis_campaign_e2e" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path campaign = dir / "campaign", laser = dir / "laser";
  const int port = 20000 + getpid() % 20000;

  // The machine: soaked until the cold test at 1 h, then machining, a laser test every 40 min.
  const std::string serve = kCli + " sim serve --machine " + kMachine + " --port " + std::to_string(port) +
                            " --time-scale " + std::to_string(kScale) +
                            " --laser-axis X --laser-out " + laser.string() +
                            " --laser-first-s 3600 --laser-every-s 2400 --laser-runs 3 --laser-spacing-mm 50"
                            " --laser-count 11 --duration-s 58 --status-interval-s 0 > " + (dir / "serve.txt").string() +
                            " 2>&1 &";
  ASSERT_EQ(std::system(serve.c_str()), 0);
  for (int i = 0; i < 200 && Slurp(dir / "serve.txt").find("registers:") == std::string::npos; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_NE(Slurp(dir / "serve.txt").find("registers:"), std::string::npos) << Slurp(dir / "serve.txt");

  // The user's run config for the terminal, without a model yet.
  std::ofstream(dir / "terminal.toml")
      << "[machine]\nkind = \"modbus\"\nhost = \"127.0.0.1\"\nport = " << port
      << "\naxes = [\"X\", \"Y\", \"Z\"]\n"
         "channels = [\"x_nut\", \"x_bearing\", \"x_motor\", \"y_nut\", \"y_bearing\", \"y_motor\", \"z_nut\",\n"
         "            \"z_bearing\", \"z_motor\", \"ambient\", \"bed\"]\n";
  const std::string log_cmd = kCli + " campaign log " + campaign.string() + " --config " +
                              (dir / "terminal.toml").string() + " --period-s 60 --clock-scale " +
                              std::to_string(kScale) + " --status";
  // Two sessions, the second started as the first stops: the log goes on in the same file.
  const std::string sessions = "(" + log_cmd + " --duration-s 24 > " + (dir / "log1.txt").string() + " 2>&1; echo $? > " +
                               (dir / "rc1").string() + "; " + log_cmd + " --duration-s 28 > " + (dir / "log2.txt").string() +
                               " 2>&1; echo $? > " + (dir / "rc2").string() + ") &";
  ASSERT_EQ(std::system(sessions.c_str()), 0);

  // The user meanwhile: each laser file, once written, added as a cold test (the first) or a warm-up
  // test; one the log has not yet passed is tried again later.
  std::vector<std::string> added;    // laser files in the order added
  std::vector<std::string> skipped;  // measured across the log's restart
  auto add_new_files = [&](bool last_try) {
    std::vector<fs::path> files;
    if (fs::exists(laser))
      for (const auto& e : fs::directory_iterator(laser))
        if (e.path().extension() == ".csv") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      if (std::find(added.begin(), added.end(), f.string()) != added.end() ||
          std::find(skipped.begin(), skipped.end(), f.string()) != skipped.end())
        continue;
      const auto [rc, text] = RunTrueaxis("campaign add " + campaign.string() + " " + f.string() + " --axis X --state " +
                                              (added.empty() ? "cold" : "warm"),
                                          dir / "add.txt");
      if (rc == 0) {
        EXPECT_NE(text.find("the file's date"), std::string::npos) << text;
        added.push_back(f.string());
        continue;
      }
      // Refused, naming the file: not covered yet (tried again later; after the log stopped, left
      // out), or measured while the log was restarting (left out: its temperatures are not known).
      EXPECT_EQ(rc, 2) << text;
      EXPECT_NE(text.find(f.string()), std::string::npos) << text;
      if (text.find("the log has a gap") != std::string::npos) {
        skipped.push_back(f.string());
        continue;
      }
      EXPECT_NE(text.find("once the log has passed its end"), std::string::npos) << text;
      if (!last_try) break;  // keep the order: the next one after this one
    }
  };
  for (int i = 0; i < 400 && !fs::exists(dir / "rc2"); ++i) {
    add_new_files(false);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  ASSERT_TRUE(fs::exists(dir / "rc2")) << "the log sessions did not end";
  add_new_files(true);
  const std::string out1 = Slurp(dir / "log1.txt"), out2 = Slurp(dir / "log2.txt");
  EXPECT_EQ(Slurp(dir / "rc1"), "0\n") << out1;
  EXPECT_EQ(Slurp(dir / "rc2"), "0\n") << out2;
  EXPECT_NE(out2.find("continuing"), std::string::npos) << out2;
  // The warm-up rule spoke: a test due as the nut rose.
  EXPECT_NE((out1 + out2).find("next warm-up test due now"), std::string::npos) << out1.substr(0, 3000);
  std::this_thread::sleep_for(std::chrono::seconds(3));  // the server stops by itself

  // The log: the fit's layout, in time order across the restart, travel growing.
  const std::string log_text = Slurp(campaign / "temperature_log.csv");
  ASSERT_EQ(log_text.rfind("time_s,date,coolant,x_mm,y_mm,z_mm,x_travel_mm,y_travel_mm,z_travel_mm,t_x_nut_c", 0), 0u)
      << log_text.substr(0, 200);
  std::istringstream rows(log_text);
  std::string line;
  std::getline(rows, line);
  double last_t = -1e18, first_travel = -1, last_travel = -1;
  int n = 0;
  while (std::getline(rows, line)) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    for (std::string c; std::getline(ls, c, ',');) cells.push_back(c);
    ASSERT_GE(cells.size(), 20u) << line;
    const double t = std::stod(cells[0]), travel = std::stod(cells[6]);
    EXPECT_GT(t, last_t) << line;
    if (first_travel < 0) first_travel = travel;
    EXPECT_GE(travel, last_travel) << line;
    last_t = t;
    last_travel = travel;
    ++n;
  }
  EXPECT_GT(n, 300) << "rows every 60 s of campaign time over ~9 h";
  EXPECT_GT(last_travel - first_travel, 100000) << "the machine's program moved X over 100 m";

  ASSERT_GE(added.size(), 8u) << Slurp(dir / "serve.txt");
  EXPECT_LE(skipped.size(), 1u) << "only a test across the restart may fall into a gap";
  const std::size_t held_out = 5;  // a warm-up test half-way, left out of the fit
  auto manifest = nlohmann::json::parse(Slurp(campaign / "manifest.json"));
  ASSERT_EQ(manifest["measurements"].size(), added.size());
  const std::string held_file = manifest["measurements"][held_out]["file"].get<std::string>();
  EXPECT_GT(manifest["measurements"][held_out]["nut_rise_c"].get<double>(), 0.5) << "a warm state";
  // Fit without the held-out test.
  manifest["measurements"].erase(manifest["measurements"].begin() + static_cast<long>(held_out));
  std::ofstream(campaign / "fit_manifest.json") << manifest.dump(2);
  const auto [fit_rc, fit_text] =
      RunTrueaxis("fit --out " + (dir / "model.json").string() + " " + (campaign / "fit_manifest.json").string(), dir / "fit.txt");
  ASSERT_EQ(fit_rc, 0) << fit_text;

  const auto [pred_rc, pred_text] =
      RunTrueaxis("predict --model " + (dir / "model.json").string() + " --measurement " + (campaign / held_file).string() +
              " --temperature-log " + (campaign / "temperature_log.csv").string(),
          dir / "predict.txt");
  ASSERT_EQ(pred_rc, 0) << pred_text;
  const double a_off = NumberAfter(pred_text, "measured error"), a_on = NumberAfter(pred_text, "measured − predicted");
  ASSERT_GT(a_off, 0) << pred_text;
  ASSERT_GT(a_on, 0) << pred_text;
  EXPECT_LT(a_on, 0.5 * a_off) << pred_text;
  std::cout << "held-out warm-up test: ISO 230-2 A " << a_off << " µm measured, " << a_on
            << " µm with the compensation; " << added.size() << " tests added, " << skipped.size() << " left out\n";
  fs::remove_all(dir);
}

}  // namespace
