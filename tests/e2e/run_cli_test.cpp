// `trueaxis run` end to end: the compensator loop against the virtual
// machine in process and against `trueaxis sim serve` over MODBUS TCP on
// 127.0.0.1 (an independent process), logging into the history database.
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>
#include <tuple>
#include <utility>

#include <gtest/gtest.h>

#include "trueaxis/model/composite_model.hpp"
#include "trueaxis/model/model_json.hpp"
#include "trueaxis/store/history_db.hpp"

namespace trueaxis {
namespace {
namespace fs = std::filesystem;

const std::string kCli = TRUEAXIS_CLI_PATH;
const std::string kMachine = std::string(TRUEAXIS_SOURCE_DIR) + "/examples/machines/vmc850.toml";

// A model for the example machine's X axis with its real sensor names.
void WriteXModel(const fs::path& path, const std::string& nut_sensor = "x_nut") {
  model::CompositeModel m;
  m.machine = "VMC-850";
  model::AxisModel a;
  a.axis = "X";
  a.reference_position_mm = 0;
  a.key_sensors = {nut_sensor, "x_bearing"};
  a.baseline_temp_c = {18, 18};
  a.ambient_sensor = "ambient";
  a.ambient_baseline_c = 18;
  a.rho_um_per_mm_per_c = -0.0115;
  for (auto& d : a.directions) {
    d.geometric.center_mm = 425;
    d.geometric.half_span_mm = 425;
    d.geometric.coefficients_um = {-20, -15};
    d.thermal = {{CoolantState::kOff, {-0.01, -0.002}, 0}};
  }
  m.axes.push_back(a);
  model::WriteModelFile(m, path.string());
}

struct TempDir {
  explicit TempDir(const std::string& name) : path(fs::temp_directory_path() / (name + std::to_string(getpid()))) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  fs::path path;
};

int RunShell(const std::string& cmd) {
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

std::string Slurp(const fs::path& p) {
  std::stringstream s;
  s << std::ifstream(p).rdbuf();
  return s.str();
}

TEST(RunCli, VirtualMachineInProcessLogsCorrectionsToHistoryAndCsv) {
  TempDir dir("trueaxis_run_virtual");
  WriteXModel(dir.path / "model.json");
  std::ofstream(dir.path / "run.toml") << "[machine]\nkind = \"virtual\"\nfile = \"" << kMachine
                                       << "\"\ntime_scale = 60\n[model]\nfile = \"model.json\"\n"
                                          "[[axis]]\nname = \"Y\"\nenabled = false\n[[axis]]\nname = \"Z\"\nenabled = false\n"
                                          "[history]\ndb = \"h.sqlite\"\ncsv = \"cycles.csv\"\nrecord_interval_s = 0.1\n";
  const std::string cmd = kCli + " run --config " + (dir.path / "run.toml").string() + " --duration-s 1.5 > " +
                          (dir.path / "out.txt").string() + " 2> " + (dir.path / "err.txt").string();
  ASSERT_EQ(RunShell(cmd), 0) << Slurp(dir.path / "err.txt");
  EXPECT_NE(Slurp(dir.path / "out.txt").find("cycles"), std::string::npos);
  store::HistoryDb db((dir.path / "h.sqlite").string(), store::HistoryDb::Mode::kReadOnly);
  const auto rows = db.QueryCompensation({}, {"X"});
  ASSERT_GT(rows.size(), 5u);
  double max_abs = 0;
  for (const auto& r : rows) max_abs = std::max(max_abs, std::fabs(r.correction_um));
  EXPECT_GT(max_abs, 5);  // the model asks for tens of µm along X
  const auto changes = db.QueryModelChanges({});
  ASSERT_EQ(changes.size(), 1u);
  EXPECT_EQ(changes[0].revision, "1");  // the model's revision number, not a word
  EXPECT_FALSE(db.QueryTemperatures({}, {"x_nut"}).empty());
  const std::string csv = Slurp(dir.path / "cycles.csv");
  EXPECT_EQ(csv.rfind("time_s,alarms,X_position_mm,X_correction_um", 0), 0u);
  const auto rows_first = std::count(csv.begin(), csv.end(), '\n');
  EXPECT_GT(rows_first, 5);

  // A row cut short (kill -9 in the middle of a write): the next run removes it and APPENDS.
  std::ofstream(dir.path / "cycles.csv", std::ios::app) << "12.345,sensor_he";
  ASSERT_EQ(RunShell(cmd), 0) << Slurp(dir.path / "err.txt");
  EXPECT_NE(Slurp(dir.path / "err.txt").find("cut short"), std::string::npos);
  const std::string both = Slurp(dir.path / "cycles.csv");
  EXPECT_EQ(both.rfind(csv, 0), 0u) << "the first run's rows must be kept";
  EXPECT_GT(std::count(both.begin(), both.end(), '\n'), rows_first + 5);
  EXPECT_EQ(both.find("sensor_he\n"), std::string::npos);
  EXPECT_EQ(both.find("time_s,alarms", 1), std::string::npos) << "one header only";
}

// SIGINT stops the loop without waiting for the rest of a long period (it waited up to period_s).
TEST(RunCli, SigintStopsWithinALongPeriod) {
  TempDir dir("trueaxis_run_sigint");
  WriteXModel(dir.path / "model.json");
  std::ofstream(dir.path / "run.toml") << "[machine]\nkind = \"virtual\"\nfile = \"" << kMachine
                                       << "\"\n[model]\nfile = \"model.json\"\n[loop]\nperiod_s = 10\n";
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const std::string config = (dir.path / "run.toml").string();
    execl(kCli.c_str(), kCli.c_str(), "run", "--config", config.c_str(), "--quiet", static_cast<char*>(nullptr));
    _exit(127);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // inside the first 10 s period
  kill(pid, SIGINT);
  // It must exit well before the period's end; waitpid with WNOHANG polled for up to 6 s.
  int status = 0;
  pid_t done = 0;
  for (int i = 0; i < 60 && done == 0; ++i) {
    done = waitpid(pid, &status, WNOHANG);
    if (done == 0) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  if (done == 0) {
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
    FAIL() << "run did not stop within 6 s of SIGINT (period 10 s)";
  }
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
}

TEST(RunCli, WithSignalProcessingInFront) {
  TempDir dir("trueaxis_run_signal");
  WriteXModel(dir.path / "model.json");
  std::ofstream(dir.path / "run.toml") << "[machine]\nkind = \"virtual\"\nfile = \"" << kMachine
                                       << "\"\ntime_scale = 60\n[model]\nfile = \"model.json\"\n"
                                          "[[axis]]\nname = \"Y\"\nenabled = false\n[[axis]]\nname = \"Z\"\nenabled = false\n"
                                          "[signal]\nenabled = true\n[history]\ndb = \"h.sqlite\"\nrecord_interval_s = 0.1\n";
  const std::string cmd = kCli + " run --config " + (dir.path / "run.toml").string() + " --duration-s 1.5 > " +
                          (dir.path / "out.txt").string() + " 2> " + (dir.path / "err.txt").string();
  ASSERT_EQ(RunShell(cmd), 0) << Slurp(dir.path / "err.txt");
  store::HistoryDb db((dir.path / "h.sqlite").string(), store::HistoryDb::Mode::kReadOnly);
  const auto rows = db.QueryCompensation({}, {"X"});
  ASSERT_GT(rows.size(), 5u);
  double max_abs = 0;
  for (const auto& r : rows) max_abs = std::max(max_abs, std::fabs(r.correction_um));
  EXPECT_GT(max_abs, 5) << Slurp(dir.path / "err.txt");
  EXPECT_EQ(Slurp(dir.path / "err.txt").find("sensor_"), std::string::npos) << Slurp(dir.path / "err.txt");
}

TEST(RunCli, BadConfigAndUnfittingModelAreInputErrors) {
  TempDir dir("trueaxis_run_bad");
  WriteXModel(dir.path / "model.json", "x_screw_middle");  // no such channel on the machine
  std::ofstream(dir.path / "typo.toml") << "[machine]\nkind = \"virtual\"\nfile = \"" << kMachine
                                        << "\"\n[model]\nfile = \"model.json\"\n[limits]\nmax_stp_um = 1\n";
  const std::string typo = kCli + " run --config " + (dir.path / "typo.toml").string() + " 2> " + (dir.path / "e1.txt").string();
  EXPECT_EQ(RunShell(typo), 2);
  EXPECT_NE(Slurp(dir.path / "e1.txt").find("typo.toml:7: field 'limits.max_stp_um': unknown key"), std::string::npos)
      << Slurp(dir.path / "e1.txt");

  std::ofstream(dir.path / "run.toml") << "[machine]\nkind = \"virtual\"\nfile = \"" << kMachine
                                       << "\"\n[model]\nfile = \"model.json\"\n";
  const std::string unfit = kCli + " run --config " + (dir.path / "run.toml").string() + " --duration-s 1 2> " +
                            (dir.path / "e2.txt").string();
  EXPECT_EQ(RunShell(unfit), 2);
  EXPECT_NE(Slurp(dir.path / "e2.txt").find("x_screw_middle"), std::string::npos) << Slurp(dir.path / "e2.txt");

  // A redundant-probe group naming a channel the machine does not have: refused, naming the line.
  WriteXModel(dir.path / "model.json");
  std::ofstream(dir.path / "groups.toml") << "[machine]\nkind = \"virtual\"\nfile = \"" << kMachine
                                          << "\"\n[model]\nfile = \"model.json\"\n[signal]\ngroups = [[\"x_nut\", \"x_nut_b\"]]\n";
  const std::string groups = kCli + " run --config " + (dir.path / "groups.toml").string() + " --duration-s 1 2> " +
                             (dir.path / "e3.txt").string();
  EXPECT_EQ(RunShell(groups), 2);
  EXPECT_NE(Slurp(dir.path / "e3.txt").find("groups.toml:7: field 'signal.groups': 'x_nut_b' is not a temperature channel"),
            std::string::npos)
      << Slurp(dir.path / "e3.txt");
}

// Refused at start with the config's file, line and field (exit 2), before any loop runs: a model
// fitted on another machine (ran silently before), an [[axis]] the machine lacks (no line before),
// a missing machine file (only "cannot open" before), a PMC unit id that is an RTD module's.
TEST(RunCli, ConfigErrorsFoundAfterReadingNameTheConfigLine) {
  TempDir dir("trueaxis_run_lines");
  const auto run = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir.path / name) << text;
    const std::string cmd = kCli + " run --config " + (dir.path / name).string() + " --duration-s 1 2> " +
                            (dir.path / "err.txt").string();
    const int rc = RunShell(cmd);
    return std::make_pair(rc, Slurp(dir.path / "err.txt"));
  };
  const std::string machine = "[machine]\nkind = \"virtual\"\nfile = \"" + kMachine + "\"\n";  // lines 1-3
  WriteXModel(dir.path / "lathe.json");
  {
    model::CompositeModel m = model::ReadModelFile((dir.path / "lathe.json").string());
    m.machine = "TC-620";
    model::WriteModelFile(m, (dir.path / "lathe.json").string());
  }
  auto [rc, err] = run("lathe.toml", machine + "[model]\nfile = \"lathe.json\"\n");
  EXPECT_EQ(rc, 2) << err;
  EXPECT_NE(err.find("lathe.toml:5: field 'model.file': "), std::string::npos) << err;
  EXPECT_NE(err.find("'TC-620'"), std::string::npos) << err;
  EXPECT_NE(err.find("'VMC-850'"), std::string::npos) << err;

  WriteXModel(dir.path / "model.json");
  std::tie(rc, err) = run("axis.toml", machine + "[model]\nfile = \"model.json\"\n[[axis]]\nname = \"Q\"\n");
  EXPECT_EQ(rc, 2) << err;
  EXPECT_NE(err.find("axis.toml:7: field 'axis[0].name': the machine has no axis 'Q'"), std::string::npos) << err;

  std::tie(rc, err) = run("nomachine.toml", "[machine]\nkind = \"virtual\"\nfile = \"nope.toml\"\n[model]\nfile = \"model.json\"\n");
  EXPECT_EQ(rc, 2) << err;
  EXPECT_NE(err.find("nomachine.toml:3: field 'machine.file': "), std::string::npos) << err;

  std::tie(rc, err) = run("units.toml",
                          "[machine]\nkind = \"modbus\"\nport = 1\ncnc_unit_id = 2\naxes = [\"X\"]\n"
                          "channels = [\"x_nut\", \"x_bearing\", \"ambient\"]\n[model]\nfile = \"model.json\"\n");
  EXPECT_EQ(rc, 2) << err;
  EXPECT_NE(err.find("units.toml:4: field 'machine.cnc_unit_id': 2 is also an RTD module's unit id"), std::string::npos)
      << err;
}

// A port unlikely to be taken (derived from the pid, so parallel test runs differ).
int FreePort() {
  return 20000 + static_cast<int>(getpid() % 20000);
}

TEST(RunCli, OverModbusTcpAgainstSimServe) {
  TempDir dir("trueaxis_run_modbus");
  WriteXModel(dir.path / "model.json");
  const int port = FreePort();
  // The terminal: an independent process that stops by itself.
  const std::string serve = kCli + " sim serve --machine " + kMachine + " --port " + std::to_string(port) +
                            " --time-scale 60 --duration-s 6 --status-interval-s 0 > " +
                            (dir.path / "serve.txt").string() + " 2>&1 &";
  ASSERT_EQ(RunShell(serve), 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  std::ofstream(dir.path / "run.toml")
      << "[machine]\nkind = \"modbus\"\nport = " << port
      << "\naxes = [\"X\", \"Y\", \"Z\"]\nchannels = [\"x_nut\", \"x_bearing\", \"x_motor\", \"y_nut\", \"y_bearing\", "
         "\"y_motor\", \"z_nut\", \"z_bearing\", \"z_motor\", \"ambient\", \"bed\"]\n"
         "[model]\nfile = \"model.json\"\n[[axis]]\nname = \"Y\"\nenabled = false\n[[axis]]\nname = \"Z\"\nenabled = false\n"
         "[history]\ndb = \"h.sqlite\"\nrecord_interval_s = 0.1\n";
  const std::string cmd = kCli + " run --config " + (dir.path / "run.toml").string() + " --duration-s 2.5 > " +
                          (dir.path / "out.txt").string() + " 2> " + (dir.path / "err.txt").string();
  ASSERT_EQ(RunShell(cmd), 0) << Slurp(dir.path / "err.txt");
  store::HistoryDb db((dir.path / "h.sqlite").string(), store::HistoryDb::Mode::kReadOnly);
  const auto rows = db.QueryCompensation({}, {"X"});
  ASSERT_GT(rows.size(), 5u);
  double max_abs = 0;
  for (const auto& r : rows) max_abs = std::max(max_abs, std::fabs(r.correction_um));
  EXPECT_GT(max_abs, 5) << Slurp(dir.path / "err.txt");
  EXPECT_FALSE(db.QueryTemperatures({}, {"x_nut"}).empty());
  std::this_thread::sleep_for(std::chrono::seconds(4));  // let the server's own duration end it
}

// A user's own laser file, fitted and run against a MODBUS terminal that has no RTD modules in the
// config: a geometric-only model runs with no temperature channels and no ambient option; a model
// with a room term (ρ from the file's cte) is refused saying which sensor, which axis and how to
// map it, and runs once mapped; the axes without a model are named in the alarm.
TEST(RunCli, FittedColdModelOverModbusWithoutAndWithTemperatureChannels) {
  TempDir dir("trueaxis_run_cold_fit");
  const std::string cold = std::string(TRUEAXIS_SOURCE_DIR) + "/examples/measurements/x_axis_cold.csv";
  {  // the same runs without the cte metadata: the fit records the air sensor but has no room term
    std::ifstream in(cold);
    std::ofstream out(dir.path / "x_cold_no_cte.csv");
    for (std::string line; std::getline(in, line);)
      if (line.rfind("# cte_um_per_m_c", 0) != 0) out << line << "\n";
  }
  const auto fit = [&](const std::string& csv, const std::string& model) {
    return RunShell(kCli + " fit --out " + (dir.path / model).string() + " " + csv + " > " +
                    (dir.path / "fit.txt").string() + " 2>&1");
  };
  ASSERT_EQ(fit((dir.path / "x_cold_no_cte.csv").string(), "geometric.json"), 0) << Slurp(dir.path / "fit.txt");
  ASSERT_EQ(fit(cold, "room.json"), 0) << Slurp(dir.path / "fit.txt");
  {
    const auto geometric = model::ReadModelFile((dir.path / "geometric.json").string());
    ASSERT_EQ(geometric.axes.size(), 1u);
    EXPECT_TRUE(geometric.axes[0].key_sensors.empty());
    EXPECT_FALSE(geometric.axes[0].AmbientInUse());
    const auto room = model::ReadModelFile((dir.path / "room.json").string());
    EXPECT_EQ(room.axes[0].ambient_sensor, "air");
    EXPECT_NE(room.axes[0].rho_um_per_mm_per_c, 0);
  }

  const int port = FreePort() + 2;
  const std::string serve = kCli + " sim serve --machine " + kMachine + " --port " + std::to_string(port) +
                            " --time-scale 60 --duration-s 9 --status-interval-s 0 > " +
                            (dir.path / "serve.txt").string() + " 2>&1 &";
  ASSERT_EQ(RunShell(serve), 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  const auto run = [&](const std::string& name, const std::string& model, const std::string& channels) {
    std::ofstream(dir.path / name) << "[machine]\nkind = \"modbus\"\nport = " << port
                                   << "\naxes = [\"X\", \"Y\", \"Z\"]\n" << channels << "[model]\nfile = \"" << model
                                   << "\"\n[history]\ndb = \"" << name << ".sqlite\"\nrecord_interval_s = 0.1\n";
    const int rc = RunShell(kCli + " run --config " + (dir.path / name).string() + " --duration-s 2 > " +
                            (dir.path / "out.txt").string() + " 2> " + (dir.path / "err.txt").string());
    return std::make_pair(rc, Slurp(dir.path / "err.txt"));
  };

  // Geometric-only, no channels: runs, corrects X, and the alarm names Y and Z (no model for them).
  auto [rc, err] = run("geometric.toml", "geometric.json", "");
  ASSERT_EQ(rc, 0) << err;
  EXPECT_NE(err.find("no temperature channels"), std::string::npos) << err;
  EXPECT_NE(err.find("no_model_for_axis(Y Z)"), std::string::npos) << err;
  {
    store::HistoryDb db((dir.path / "geometric.toml.sqlite").string(), store::HistoryDb::Mode::kReadOnly);
    const auto rows = db.QueryCompensation({}, {"X"});
    ASSERT_GT(rows.size(), 5u);
    double max_abs = 0;
    for (const auto& r : rows) max_abs = std::max(max_abs, std::fabs(r.correction_um));
    EXPECT_GT(max_abs, 1) << err;  // the cold runs' error along X, some µm
    bool named = false;
    for (const auto& a : db.QueryAlarms({})) named = named || a.message.find("no_model_for_axis(Y Z)") != std::string::npos;
    EXPECT_TRUE(named) << "the history's alarm log names the axes";
  }

  // The room term without a channel: refused (exit 2) before any loop runs, saying what to do.
  std::tie(rc, err) = run("room.toml", "room.json", "");
  EXPECT_EQ(rc, 2) << err;
  for (const char* words : {"room.json", "axes[X].ambient_sensor", "axis X's model", "'air'", "[channels] air = ",
                            "--ambient-sensor none"})
    EXPECT_NE(err.find(words), std::string::npos) << words << " in: " << err;

  // Mapped as the message says: runs.
  std::tie(rc, err) = run("mapped.toml", "room.json",
                          "channels = [\"x_nut\", \"x_bearing\", \"x_motor\", \"y_nut\", \"y_bearing\", \"y_motor\", "
                          "\"z_nut\", \"z_bearing\", \"z_motor\", \"ambient\", \"bed\"]\n[channels]\nair = \"ambient\"\n");
  EXPECT_EQ(rc, 0) << err;
  std::this_thread::sleep_for(std::chrono::seconds(3));  // let the server's own duration end it
}

TEST(RunCli, StaysUpWhenTheTerminalIsUnreachable) {
  TempDir dir("trueaxis_run_nolink");
  WriteXModel(dir.path / "model.json");
  std::ofstream(dir.path / "run.toml")
      << "[machine]\nkind = \"modbus\"\nport = " << FreePort() + 1
      << "\naxes = [\"X\"]\nchannels = [\"x_nut\", \"x_bearing\", \"ambient\"]\n[model]\nfile = \"model.json\"\n";
  const std::string cmd = kCli + " run --config " + (dir.path / "run.toml").string() + " --duration-s 1.2 > " +
                          (dir.path / "out.txt").string() + " 2> " + (dir.path / "err.txt").string();
  ASSERT_EQ(RunShell(cmd), 0) << Slurp(dir.path / "err.txt");
  const std::string err = Slurp(dir.path / "err.txt");
  EXPECT_NE(err.find("not reachable"), std::string::npos) << err;
  EXPECT_NE(err.find("link_read"), std::string::npos) << err;
}

}  // namespace
}  // namespace trueaxis
