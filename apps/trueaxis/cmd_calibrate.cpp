// trueaxis calibrate: fit every sensor of a calibration session against a
// reference sensor (zero offset + scale factor, seed 000 "自動標定") and write
// the result as cal.json for the temperature monitor (docs/signal.md).
#include <ctime>
#include <memory>

#include <fmt/format.h>

#include "command.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/output_path.hpp"
#include "trueaxis/signal/calibration.hpp"
#include "trueaxis/store/history_db.hpp"

namespace {

struct CalibrateOptions {
  std::string session;
  std::string reference;
  std::string out;
  std::string db;
  double min_span_c = trueaxis::signal::CalibrationOptions{}.min_span_c;
};

void RunCalibrate(const CalibrateOptions& o) {
  using namespace trueaxis::signal;
  CalibrationOptions options;
  options.min_span_c = o.min_span_c;
  std::string why;
  if (!options.IsValid(&why)) throw trueaxis::InputError("command line", 0, "--min-span-c", why);
  trueaxis::RefuseOutputOverInput(o.out, {o.session, o.db}, "--out");
  const CalibrationSession session = ReadCalibrationSessionCsv(o.session);
  const CalibrationSet set = CalibrateSession(session, o.reference, options);
  // Open the database before writing anything, so a bad --db leaves no half result.
  std::unique_ptr<trueaxis::store::HistoryDb> db;
  if (!o.db.empty()) db = std::make_unique<trueaxis::store::HistoryDb>(o.db, trueaxis::store::HistoryDb::Mode::kReadWrite);
  WriteCalibrationFile(o.out, set);
  if (db) db->InsertCalibration(static_cast<double>(std::time(nullptr)), set);
  fmt::print("{}", set.FullReport());
  fmt::print("{} rows, {} sensors calibrated; written to {}{}\n", session.rows(), set.sensors.size(), o.out,
             o.db.empty() ? "" : " and stored in " + o.db);
}

void Setup(CLI::App& app) {
  auto opts = std::make_shared<CalibrateOptions>();
  auto* cmd = app.add_subcommand("calibrate", "Calibrate temperature sensors against a reference sensor (offset + scale)");
  cmd->add_option("--session", opts->session, "CSV of simultaneous readings: header of sensor names, one row per instant")
      ->required();
  cmd->add_option("--reference", opts->reference, "name of the reference sensor column")->required();
  cmd->add_option("--out", opts->out, "calibration JSON to write")->required();
  cmd->add_option("--db", opts->db, "also store the calibration in this history database");
  cmd->add_option("--min-span-c", opts->min_span_c, "reference span needed to fit the scale factor (°C)");
  cmd->callback([opts] { RunCalibrate(*opts); });
}

trueaxis::cli::CommandRegistrar reg("calibrate", Setup);

}  // namespace
