// Laser interferometer and campaign: procedure, files, determinism, CLI.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sim_test_util.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/measure/measurement_csv.hpp"
#include "trueaxis/sim/campaign.hpp"

namespace trueaxis::sim {
namespace {

namespace fs = std::filesystem;

fs::path TempDir(const std::string& name) {
  fs::path p = fs::temp_directory_path() / ("trueaxis_sim_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(p);
  return p;
}

TEST(Laser, MeasuresLikeIso2302) {
  VirtualMachine vm(testing::TestMachine(), 1);
  LaserOptions o;
  o.runs = 3;
  o.spacing_mm = 100;
  LaserInterferometer laser(o, 1);
  laser.Setup(vm, 0, 0);
  const double t0 = vm.TimeS();
  const auto m = laser.Measure(vm, {{"state", "cold"}});
  const auto targets = laser.Targets(vm, 0);
  EXPECT_DOUBLE_EQ(targets.front(), 5);    // overrun room at the ends
  EXPECT_DOUBLE_EQ(targets.back(), 595);
  EXPECT_EQ(targets.size(), 7u);           // 590 mm / ~100 mm
  ASSERT_EQ(m.points.size(), 3u * 2 * targets.size());
  EXPECT_NO_THROW(measure::ValidateForEvaluation(m));
  EXPECT_EQ(m.sensor_names.size(), vm.ChannelCount());
  EXPECT_EQ(m.Meta("axis").value_or(""), "X");
  EXPECT_EQ(m.Meta("state").value_or(""), "cold");
  EXPECT_EQ(m.Meta("lead_mm").value_or(""), "10");
  // Time passes: each point costs the move plus the dwell.
  EXPECT_GT(vm.TimeS() - t0, 3 * 2 * 7 * o.dwell_s);
  EXPECT_GT(*m.points.back().time_s, *m.points.front().time_s);
  // Resolution 1 nm: deviations are on a 0.001 µm grid.
  for (const auto& p : m.points) EXPECT_NEAR(p.deviation_um * 1000, std::round(p.deviation_um * 1000), 1e-6);
  // Reversal at each target ≈ backlash (6 µm) ± flank part.
  double fwd = 0, rev = 0;
  for (const auto& p : m.points) (p.direction == Direction::kForward ? fwd : rev) += p.deviation_um;
  EXPECT_NEAR((rev - fwd) / (3 * 7), 6, 1.5);
}

TEST(Laser, RepeatedReadingsScatterByTheInstrumentNoise) {
  VirtualMachine vm(testing::TestMachine(), 2);
  LaserOptions o;
  o.noise_nm = 200;
  LaserInterferometer laser(o, 9);
  laser.Setup(vm, 0, 0);
  vm.MoveTo(0, 300, 2000);
  double sum = 0, sum2 = 0;
  const int n = 400;
  for (int i = 0; i < n; ++i) {
    const double v = laser.ReadMm(vm) * 1e6;  // nm
    sum += v;
    sum2 += v * v;
  }
  const double sd = std::sqrt(sum2 / n - (sum / n) * (sum / n));
  EXPECT_NEAR(sd, 200, 30);
}

CampaignOptions ShortCampaign(const fs::path& dir, std::uint64_t seed) {
  CampaignOptions c;
  c.out_dir = dir.string();
  c.seed = seed;
  c.axes = {"X"};
  c.laser.runs = 2;
  c.warm_runs = 2;
  c.laser.spacing_mm = 150;
  c.laser.dwell_s = 2;
  c.max_warm_measurements = 3;
  c.max_warmup_hours = 2;
  c.ambient_day_offsets = {30};
  c.max_coolant_measurements = 2;
  return c;
}

TEST(Campaign, WritesFilesTemperatureLogAndManifest) {
  const auto dir = TempDir("campaign");
  const auto summary = RunCampaign(testing::TestMachine(), ShortCampaign(dir, 1));
  ASSERT_GE(summary.files.size(), 1u + 2 + 1 + 1);
  std::set<std::string> states;
  for (const auto& f : summary.files) states.insert(f.state);
  EXPECT_EQ(states, (std::set<std::string>{"cold", "warm", "cooldown", "ambient", "coolant", "coolant_rest"}));
  const auto manifest = nlohmann::json::parse(ReadTextFile((dir / "manifest.json").string()));
  ASSERT_EQ(manifest["measurements"].size(), summary.files.size());
  double last_warm_rise = 0;
  for (const auto& e : manifest["measurements"]) {
    const auto path = dir / e["file"].get<std::string>();
    ASSERT_TRUE(fs::exists(path)) << path;
    const auto m = measure::ReadMeasurementCsv(path.string());
    EXPECT_NO_THROW(measure::ValidateForEvaluation(m));
    EXPECT_EQ(m.Meta("state").value_or(""), e["state"].get<std::string>());
    EXPECT_EQ(m.Meta("coolant").value_or(""), e["coolant"].get<std::string>());
    EXPECT_TRUE(e["mean_temperatures_c"].contains("x_nut"));
    if (e["state"] == "warm") last_warm_rise = e["nut_rise_c"].get<double>();
    if (e["state"] == "cooldown") {
      EXPECT_LT(e["nut_rise_c"].get<double>(), last_warm_rise);  // cooler than the saturated state
    }
    if (e["state"] == "coolant") {
      EXPECT_EQ(e["coolant"], "flood");
    }
  }
  // The warm-up really warmed the nut by at least one 0.5 °C step.
  EXPECT_GT(last_warm_rise, 0.5);
  const std::string log = ReadTextFile((dir / "temperature_log.csv").string());
  EXPECT_EQ(log.rfind("time_s,date,coolant,x_mm,y_mm,x_travel_mm,y_travel_mm,t_x_nut_c", 0), 0u);
  // The travelled path (the motion-heat input's history) grows over the campaign: the warm-up moved X.
  {
    const auto last_line_start = log.rfind('\n', log.size() - 2) + 1;
    const std::string last = log.substr(last_line_start);
    std::vector<std::string> cells;
    for (std::size_t a = 0, b; a <= last.size(); a = b + 1) {
      b = last.find(',', a);
      if (b == std::string::npos) b = last.size();
      cells.push_back(last.substr(a, b - a));
    }
    ASSERT_GT(cells.size(), 6u);
    EXPECT_GT(std::stod(cells[5]), 10000.0);  // x_travel_mm: metres of warm-up and laser moves
  }
  EXPECT_GT(std::count(log.begin(), log.end(), '\n'), 100);
  fs::remove_all(dir);
}

// min_warmup_per_test: each dry warm-up test waits for machining of at least r × the last test's
// duration (the gap between two warm tests is machining only); the coolant warm-up is not held.
TEST(Campaign, WarmUpTestsWaitForMachiningOfRTimesTheLastTest) {
  const auto dir = TempDir("campaign_warmup_per_test");
  auto c = ShortCampaign(dir, 3);
  c.max_warm_measurements = 4;
  c.min_warmup_per_test = 1.5;
  const auto summary = RunCampaign(testing::TestMachine(), c);
  const CampaignFile* prev = nullptr;
  int pairs = 0;
  for (const auto& f : summary.files) {
    if (f.state != "warm") continue;
    if (prev) {
      EXPECT_GE(f.start_time_s - prev->end_time_s, 1.5 * (prev->end_time_s - prev->start_time_s) - 1) << f.file;
      ++pairs;
    }
    prev = &f;
  }
  EXPECT_GE(pairs, 1);
  c.min_warmup_per_test = -1;
  std::string why;
  EXPECT_FALSE(c.IsValid(&why));
  EXPECT_NE(why.find("min_warmup_per_test"), std::string::npos) << why;
  fs::remove_all(dir);
}

// coolant_prewarm_h: one coolant session per entry, each on its own day; the second starts after
// an hour of dry machining, so its first test finds the nut warm, and the flood then draws it down.
TEST(Campaign, CoolantSessionsAfterDryMachiningStartOverAWarmMachine) {
  const auto dir = TempDir("campaign_coolant_prewarm");
  auto c = ShortCampaign(dir, 4);
  c.max_coolant_measurements = 3;
  c.coolant_prewarm_h = {0, 1};
  c.coolant_visit = CampaignOptions::CoolantVisit::kAfterSeasons;  // one visit: two sessions
  const auto summary = RunCampaign(testing::TestMachine(), c);
  std::map<int, std::vector<const CampaignFile*>> by_session;
  for (const auto& f : summary.files) {
    if (f.state == "coolant" || f.state == "coolant_rest") {
      EXPECT_EQ(f.coolant, "flood") << f.file;
      by_session[f.coolant_session].push_back(&f);
    } else {
      EXPECT_EQ(f.coolant_session, 0) << f.file;
    }
  }
  ASSERT_EQ(by_session.size(), 2u);
  ASSERT_TRUE(by_session.count(1) && by_session.count(2));
  const CampaignFile& first1 = *by_session[1].front();
  const CampaignFile& first2 = *by_session[2].front();
  EXPECT_EQ(first1.state, "coolant");
  EXPECT_EQ(first2.state, "coolant");
  EXPECT_NE(first1.start_date.substr(0, 10), first2.start_date.substr(0, 10));  // another day
  EXPECT_GT(first2.nut_rise_c, first1.nut_rise_c + 1.0) << "the second session starts over a warm machine";
  // The session's first test comes after the hour of dry machining (the day starts at 07:00).
  EXPECT_GE(first2.start_date.substr(11, 5), "08:00") << first2.start_date;
  // The manifest says which session each coolant file belongs to.
  const auto manifest = nlohmann::json::parse(ReadTextFile((dir / "manifest.json").string()));
  int with_session = 0;
  for (const auto& e : manifest["measurements"])
    if (e.contains("coolant_session")) {
      ++with_session;
      EXPECT_EQ(e["state"].get<std::string>().rfind("coolant", 0), 0u) << e.dump();
    }
  EXPECT_EQ(with_session, static_cast<int>(by_session[1].size() + by_session[2].size()));
  c.coolant_prewarm_h = {0, -1};
  std::string why;
  EXPECT_FALSE(c.IsValid(&why));
  EXPECT_NE(why.find("coolant_prewarm_h"), std::string::npos) << why;
  c.coolant_prewarm_h = {};  // no session at all would be a silent skip
  why.clear();
  EXPECT_FALSE(c.IsValid(&why));
  EXPECT_NE(why.find("at least one"), std::string::npos) << why;
  fs::remove_all(dir);
}

// coolant_visit: the coolant sessions after the other-season days (the default), on the days
// right after the dry warm-ups, or both (then numbered on through the campaign).
TEST(Campaign, CoolantSessionsInTheFirstVisitAfterTheSeasonsOrBoth) {
  using V = CampaignOptions::CoolantVisit;
  for (const V visit : {V::kAfterSeasons, V::kFirstVisit, V::kBoth}) {
    const auto dir = TempDir("campaign_coolant_visit_" + std::to_string(static_cast<int>(visit)));
    auto c = ShortCampaign(dir, 5);
    c.coolant_visit = visit;
    const auto summary = RunCampaign(testing::TestMachine(), c);
    std::string last_warm, first_ambient, last_ambient;
    std::map<int, std::pair<std::string, std::string>> sessions;  // session → first, last start date
    for (const auto& f : summary.files) {
      if (f.state == "warm" || f.state == "cooldown") last_warm = std::max(last_warm, f.start_date);
      if (f.state == "ambient") {
        if (first_ambient.empty()) first_ambient = f.start_date;
        last_ambient = f.start_date;
      }
      if (f.state == "coolant" || f.state == "coolant_rest") {
        auto& [first, last] = sessions[f.coolant_session];
        if (first.empty()) first = f.start_date;
        last = f.start_date;
      } else {
        EXPECT_EQ(f.coolant_session, 0) << f.file;
      }
    }
    ASSERT_FALSE(first_ambient.empty() || last_warm.empty());
    ASSERT_EQ(sessions.size(), visit == V::kBoth ? 2u : 1u);
    const auto& [first1, last1] = sessions.begin()->second;
    EXPECT_GT(first1, last_warm);
    if (visit == V::kAfterSeasons) {
      EXPECT_GT(first1, last_ambient);
    } else {
      EXPECT_LT(last1, first_ambient) << "the first session belongs to the first visit";
      EXPECT_LE(first1.substr(0, 10), "2026-03-09");  // within days of the cold state (TestMachine starts 2026-03-02)
    }
    if (visit == V::kBoth) EXPECT_GT(sessions.rbegin()->second.first, last_ambient);
    // The log stays in time order either way.
    const std::string log = ReadTextFile((dir / "temperature_log.csv").string());
    std::istringstream lines(log);
    std::string line;
    std::getline(lines, line);
    double prev = -1;
    while (std::getline(lines, line)) {
      const double t = std::stod(line.substr(0, line.find(',')));
      ASSERT_GE(t, prev) << line;
      prev = t;
    }
    fs::remove_all(dir);
  }
}

// The hour of the day of a measurement's "date" metadata (YYYY-MM-DDTHH:MM:SS).
double HourOfDay(const measure::Measurement& m) {
  const std::string d = m.Meta("date").value_or("");
  if (d.size() < 19) return -1;
  return std::stod(d.substr(11, 2)) + std::stod(d.substr(14, 2)) / 60 + std::stod(d.substr(17, 2)) / 3600;
}

TEST(Campaign, AmbientDaysMeasureAtEachHourAskedFor) {
  const auto dir = TempDir("ambient_hours");
  auto o = ShortCampaign(dir, 5);
  o.max_warm_measurements = 1;
  o.cooldown_measurements = 0;
  o.coolant_session = false;
  o.ambient_day_offsets = {30, 40};
  o.ambient_hours = {10, 19};
  std::vector<std::string> progress;
  o.progress = [&](const std::string& line) { progress.push_back(line); };
  const auto summary = RunCampaign(testing::TestMachine(), o);
  std::vector<std::pair<std::string, double>> ambient;  // (date, hour of day), in campaign order
  for (const auto& f : summary.files) {
    if (f.state != "ambient") continue;
    const auto m = measure::ReadMeasurementCsv((dir / f.file).string());
    ambient.emplace_back(m.Meta("date").value_or("").substr(0, 10), HourOfDay(m));
  }
  ASSERT_EQ(ambient.size(), 4u);  // 2 days × 2 hours × 1 axis
  for (std::size_t i = 0; i < ambient.size(); ++i) {
    const double asked = i % 2 == 0 ? 10 : 19;
    EXPECT_GE(ambient[i].second, asked) << i;  // the set-up before the first point takes minutes
    EXPECT_LT(ambient[i].second, asked + 0.5) << i;
  }
  EXPECT_EQ(ambient[0].first, ambient[1].first);  // both hours on the same day
  EXPECT_NE(ambient[1].first, ambient[2].first);
  for (const auto& l : progress) EXPECT_EQ(l.find("a day later"), std::string::npos) << l;
  fs::remove_all(dir);

  // An hour the earlier measurements of its day ran past is measured a day later, and said.
  const auto dir2 = TempDir("ambient_overrun");
  o.out_dir = dir2.string();
  o.ambient_day_offsets = {30};
  o.ambient_hours = {10, 10.01};
  progress.clear();
  const auto late = RunCampaign(testing::TestMachine(), o);
  std::vector<std::string> dates;
  for (const auto& f : late.files)
    if (f.state == "ambient")
      dates.push_back(measure::ReadMeasurementCsv((dir2 / f.file).string()).Meta("date").value_or("").substr(0, 10));
  ASSERT_EQ(dates.size(), 2u);
  EXPECT_NE(dates[0], dates[1]);
  bool said = false;
  for (const auto& l : progress) said = said || l.find("ran past it, measuring a day later") != std::string::npos;
  EXPECT_TRUE(said);
  fs::remove_all(dir2);
}

TEST(Campaign, RefusesAmbientHoursOutsideTheDayOrOutOfOrder) {
  CampaignOptions o;
  o.out_dir = "x";
  std::string why;
  o.ambient_hours = {24};
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("24 is not an hour of the day"), std::string::npos) << why;
  o.ambient_hours = {-1};
  EXPECT_FALSE(o.IsValid(&why));
  o.ambient_hours = {19, 10};
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("increasing order"), std::string::npos) << why;
  o.ambient_hours = {10, 10};
  EXPECT_FALSE(o.IsValid(&why));
  o.ambient_hours = {};
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("at least one hour"), std::string::npos) << why;
  o.ambient_day_offsets = {};  // no ambient day: no hour needed
  EXPECT_TRUE(o.IsValid(&why)) << why;
  o.ambient_day_offsets = {60};
  o.ambient_hours = {0, 10, 23.5};
  EXPECT_TRUE(o.IsValid(&why)) << why;
}

std::map<std::string, std::string> ReadAll(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out[e.path().filename().string()] = ReadTextFile(e.path().string());
  return out;
}

TEST(Campaign, SameSeedSameBytesOtherSeedOtherData) {
  const auto a = TempDir("seed_a"), b = TempDir("seed_b"), c = TempDir("seed_c");
  auto oa = ShortCampaign(a, 42), ob = ShortCampaign(b, 42), oc = ShortCampaign(c, 43);
  for (auto* o : {&oa, &ob, &oc}) {
    o->coolant_session = false;
    o->ambient_day_offsets = {};
  }
  RunCampaign(testing::TestMachine(), oa);
  RunCampaign(testing::TestMachine(), ob);
  RunCampaign(testing::TestMachine(), oc);
  const auto fa = ReadAll(a), fb = ReadAll(b), fc = ReadAll(c);
  EXPECT_EQ(fa, fb);
  ASSERT_TRUE(fa.count("X_01_cold.csv"));
  ASSERT_TRUE(fc.count("X_01_cold.csv"));
  EXPECT_NE(fa.at("X_01_cold.csv"), fc.at("X_01_cold.csv"));
  for (const auto& d : {a, b, c}) fs::remove_all(d);
}

int RunCli(const std::string& args, std::string* err) {
  const auto errfile = TempDir("cli_err");
  const std::string cmd = std::string(TRUEAXIS_CLI_PATH) + " " + args + " >/dev/null 2>" + errfile.string();
  const int rc = std::system(cmd.c_str());
  *err = fs::exists(errfile) ? ReadTextFile(errfile.string()) : "";
  fs::remove_all(errfile);
  return WEXITSTATUS(rc);
}

CampaignFile SessionTest(const std::string& axis, const std::string& state, double nut_rise_c) {
  CampaignFile f;
  f.axis = axis;
  f.state = state;
  f.nut_rise_c = nut_rise_c;
  return f;
}

TEST(Campaign, WarmUpCoverageGapsNameTheSessionsThatLeaveMostOfTheRiseUntested) {
  std::vector<CampaignFile> files = {SessionTest("X", "cold", 0)};
  for (double r : {0.7, 1.2, 1.7, 2.2, 2.7, 3.5, 4.4, 5.4, 6.8, 8.4, 10.5, 13.1}) files.push_back(SessionTest("X", "warm", r));
  for (double r : {5.0, 5.7, 6.1, 12.9}) files.push_back(SessionTest("Y", "coolant", r));  // the nut's first jump, then saturation
  for (double r : {0.5, 1.0, 6.0}) files.push_back(SessionTest("Z", "warm", r));           // counted from the cold state
  for (double r : {3.0, 2.0}) files.push_back(SessionTest("Z", "cooldown", r));            // not a warm-up
  const auto gaps = WarmUpCoverageGaps(files);
  ASSERT_EQ(gaps.size(), 2u);
  EXPECT_EQ(gaps[0], "Y coolant warm-up: tests at nut +5.0, +5.7, +6.1, +12.9 °C vs cold; 6.8 of its 7.9 °C rise (86 %) "
                     "lie between two of them, untested");
  EXPECT_NE(gaps[1].find("Z dry warm-up: tests at nut +0.5, +1.0, +6.0 °C"), std::string::npos) << gaps[1];
  EXPECT_NE(gaps[1].find("5.0 of its 6.0 °C rise (83 %)"), std::string::npos) << gaps[1];
  EXPECT_EQ(WarmUpCoverageGaps(files, 0.9).size(), 0u);  // the threshold is the caller's
  CampaignSummary summary;
  summary.files = files;
  EXPECT_NE(summary.BriefReport().find("\n  Y coolant warm-up"), std::string::npos) << summary.BriefReport();
  // Two coolant sessions are judged apart; one over a warm machine falls first, then rises.
  std::vector<CampaignFile> two;
  for (double r : {5.0, 5.7, 6.1, 6.6}) two.push_back(SessionTest("Y", "coolant", r)), two.back().coolant_session = 1;
  for (double r : {12.0, 8.0, 12.5}) two.push_back(SessionTest("Y", "coolant", r)), two.back().coolant_session = 2;
  const auto gaps2 = WarmUpCoverageGaps(two);
  ASSERT_EQ(gaps2.size(), 1u);
  EXPECT_NE(gaps2[0].find("Y coolant (session 2) warm-up: tests at nut +12.0, +8.0, +12.5 °C"), std::string::npos)
      << gaps2[0];
}

TEST(Campaign, CliRunsAndRejectsBadMachineFile) {
  const auto dir = TempDir("cli");
  fs::create_directories(dir);
  const auto machine = dir / "m.toml";
  WriteTextFile(machine.string(), testing::TestMachineToml());
  std::string err;
  EXPECT_EQ(RunCli("sim campaign --machine " + machine.string() + " --out " + (dir / "out").string() +
                       " --axes Y --runs 2 --warm-runs 2 --spacing-mm 200 --max-warm 1 --cooldown 0 --ambient-days 5 --no-coolant",
                   &err),
            0)
      << err;
  EXPECT_TRUE(fs::exists(dir / "out" / "manifest.json"));
  EXPECT_TRUE(fs::exists(dir / "out" / "Y_01_cold.csv"));
  EXPECT_NE(err.find("measuring Y"), std::string::npos);  // progress on stderr

  const auto bad = dir / "bad.toml";
  WriteTextFile(bad.string(), testing::TestMachineToml() + "backlsh_um = 3\n");
  EXPECT_EQ(RunCli("sim campaign --machine " + bad.string() + " --out " + (dir / "out2").string(), &err), 2);
  EXPECT_NE(err.find("bad.toml:"), std::string::npos) << err;
  EXPECT_NE(err.find("backlsh_um"), std::string::npos) << err;

  const auto tiny = dir / "tiny.toml";
  WriteTextFile(tiny.string(), "[[axis]]\nname = \"X\"\ntravel_mm = 8\nlead_mm = 5\n");
  EXPECT_EQ(RunCli("sim campaign --machine " + tiny.string() + " --out " + (dir / "out4").string(), &err), 2);
  EXPECT_NE(err.find("do not fit the travel"), std::string::npos) << err;

  // --max-coolant reaches the campaign: that many coolant warm-up tests per session (the nut of this
  // small axis rises in fine steps; --coolant-visit first: one session), and a count of 0 is refused.
  EXPECT_EQ(RunCli("sim campaign --quiet --machine " + machine.string() + " --out " + (dir / "out6").string() +
                       " --axes Y --runs 2 --warm-runs 2 --spacing-mm 200 --max-warm 1 --cooldown 0 --ambient-days 5 --max-coolant 3"
                       " --coolant-visit first",
                   &err),
            0)
      << err;
  const auto manifest6 = nlohmann::json::parse(ReadTextFile((dir / "out6" / "manifest.json").string()));
  int coolant_tests = 0;
  for (const auto& e : manifest6["measurements"]) coolant_tests += e["state"] == "coolant";
  EXPECT_EQ(coolant_tests, 3);
  EXPECT_EQ(RunCli("sim campaign --machine " + machine.string() + " --out " + (dir / "out8").string() +
                       " --coolant-visit never",
                   &err),
            2);
  EXPECT_NE(err.find("--coolant-visit"), std::string::npos) << err;
  EXPECT_EQ(RunCli("sim campaign --machine " + machine.string() + " --out " + (dir / "out7").string() + " --max-coolant 0", &err), 2);
  EXPECT_NE(err.find("--max-coolant"), std::string::npos) << err;
  EXPECT_EQ(RunCli("sim campaign --machine " + machine.string() + " --out " + (dir / "out3").string() + " --axes Q", &err), 2);
  EXPECT_NE(err.find("'Q'"), std::string::npos) << err;
  EXPECT_EQ(RunCli("sim campaign --machine " + machine.string() + " --out " + (dir / "out5").string() + " --ambient-hours 10,24", &err), 2);
  EXPECT_NE(err.find("ambient_hours: 24 is not an hour of the day"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir / "out5" / "manifest.json"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace trueaxis::sim
