// trueaxis tool day|tv|render|offset — tool thermal error with heating /
// steady / cooling sub-models (seed 001, second half; docs/tool-thermal.md).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>

#include "command.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/json_text.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/core/text_lines.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/tooltherm/tool_evaluation.hpp"

namespace trueaxis::cli {
namespace {
using namespace trueaxis::tooltherm;
namespace fs = std::filesystem;

struct DayArgs {
  std::string tools;
  int random_tools = 0;
  std::uint64_t seed = 1;
  double hours = 8;
  double sample_s = 2;
  std::string sensor = "camera";
  std::string out;
};

ToolTable LoadTools(const DayArgs& a) {
  if (a.tools.empty() == (a.random_tools == 0))
    throw InputError("command line", 0, "--tools", "give a tool file (--tools) or --random-tools N, not both");
  if (a.random_tools < 0 || a.random_tools > 50) throw InputError("command line", 0, "--random-tools", "must be 1…50");
  return a.tools.empty() ? RandomToolTable(a.random_tools, a.seed) : ReadToolFile(a.tools);
}

ToolDayOptions DayOptions(const DayArgs& a, std::uint64_t seed) {
  if (!(a.hours > 0 && a.hours <= 72)) throw InputError("command line", 0, "--hours", "must be in (0, 72]");
  if (!(a.sample_s >= 0.5 && a.sample_s <= 600)) throw InputError("command line", 0, "--sample-s", "must be in [0.5, 600]");
  ToolDayOptions o;
  o.hours = a.hours;
  o.sample_s = a.sample_s;
  o.step_s = std::min(0.5, a.sample_s);
  o.seed = seed;
  if (a.sensor == "camera") o.sensor = TvSensor::kCamera;
  else if (a.sensor == "pyrometer") o.sensor = TvSensor::kPyrometer;
  else throw InputError("command line", 0, "--sensor", "must be camera or pyrometer");
  return o;
}

std::string ModelsJson(const std::map<int, ToolErrorModel>& models, const ToolTable& table) {
  nlohmann::json doc = {{"format", "trueaxis tool thermal models"}, {"version", 1}, {"tools", nlohmann::json::array()}};
  for (const auto& [n, m] : models) {
    auto j = m.ToJson();
    if (const ToolDescription* t = table.Find(n)) {
      j["name"] = t->name;
      j["nominal_length_mm"] = t->GaugeLengthMm();
      j["diameter_mm"] = t->diameter_mm;
    }
    doc["tools"].push_back(j);
  }
  return doc.dump(2) + "\n";
}

std::string ScoreTable(const ToolEvaluation& ev, const ToolTable& table) {
  std::string s =
      "| tool | samples | hysteresis (spread about one curve) µm | none RMS / max µm | one model | seed 001 sub-models | "
      "first-order lag | two-body (ours) | reduction, sub-models / two-body |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& sc : ev.tools) {
    const ToolDescription* t = table.Find(sc.tool);
    auto cell = [&](ToolModelKind k) {
      const auto i = static_cast<std::size_t>(k);
      return fmt::format("{:.2f} / {:.2f}", sc.rms_um[i], sc.max_um[i]);
    };
    const double none = sc.rms_um[0];
    auto red = [&](ToolModelKind k) { return none > 0 ? 100.0 * (1 - sc.rms_um[static_cast<std::size_t>(k)] / none) : 0.0; };
    s += fmt::format("| T{} {} | {} | {:.2f} | {} | {} | {} | {} | {} | {:.0f} % / {:.0f} % |\n", sc.tool, t ? t->name : "",
                     sc.samples, sc.curve_spread_um, cell(ToolModelKind::kNone), cell(ToolModelKind::kOne),
                     cell(ToolModelKind::kIntervals), cell(ToolModelKind::kLag), cell(ToolModelKind::kTwoBody),
                     red(ToolModelKind::kIntervals), red(ToolModelKind::kTwoBody));
  }
  return s;
}

void RunDay(const DayArgs& a) {
  const ToolTable table = LoadTools(a);
  const ToolDayRecording training = RunToolDay(table, DayOptions(a, a.seed));
  const ToolDayRecording test = RunToolDay(table, DayOptions(a, a.seed + 1));
  const ToolEvaluation ev = EvaluateToolModels(table, training, test);
  for (const auto& w : ev.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  const std::string md = fmt::format(
      "Tool thermal day: trained on day seed {}, tested on day seed {} ({} h, Tv every {} s from the {}), "
      "residual tip error after the tool length offset (through the limiter):\n\n{}",
      a.seed, a.seed + 1, a.hours, a.sample_s, a.sensor, ScoreTable(ev, table));
  std::fputs(md.c_str(), stdout);
  if (!a.out.empty()) {
    fs::create_directories(a.out);
    std::ofstream(fs::path(a.out) / "tool_models.json") << ModelsJson(ev.models, table);
    std::ofstream(fs::path(a.out) / "tool_day.md") << md;
    std::ofstream csv(fs::path(a.out) / "tool_day_test.csv");
    csv << "time_s,tool,tv_c,true_error_um,restart,rpm,cutting,coolant\n";
    for (const auto& s : test.samples)
      csv << fmt::format("{:.1f},{},{:.3f},{:.3f},{},{:.0f},{},{}\n", s.time_s, s.tool, s.tv_c, s.true_error_um,
                         s.restart ? 1 : 0, s.rpm, s.cutting ? 1 : 0, s.coolant ? 1 : 0);
    std::printf("wrote %s/tool_models.json, tool_day.md, tool_day_test.csv\n", a.out.c_str());
  }
}

void Setup(CLI::App& app) {
  auto* tool = app.add_subcommand("tool", "Tool thermal error: virtual tool, Tv from zones, heating/steady/cooling sub-models");
  tool->require_subcommand(1);
  auto day = std::make_shared<DayArgs>();
  auto* d = tool->add_subcommand("day", "Fit on one virtual day, compensate another; RMS/max per tool and model");
  d->add_option("--tools", day->tools, "tool file (TOML, docs/tool-thermal.md)");
  d->add_option("--random-tools", day->random_tools, "N random tools instead of a file (drawn from --seed)");
  d->add_option("--seed", day->seed, "training day seed; the test day is seed + 1")->capture_default_str();
  d->add_option("--hours", day->hours, "length of each day")->capture_default_str();
  d->add_option("--sample-s", day->sample_s, "seconds between Tv readings")->capture_default_str();
  d->add_option("--sensor", day->sensor, "camera or pyrometer")->capture_default_str();
  d->add_option("--out", day->out, "folder for tool_models.json, tool_day.md, tool_day_test.csv");
  d->callback([day] { RunDay(*day); });
}

CommandRegistrar reg("tool", Setup);

}  // namespace
}  // namespace trueaxis::cli
