// trueaxis tool day|tv|render|offset — tool thermal error with heating /
// steady / cooling sub-models (seed 001, second half; docs/tool-thermal.md).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <random>
#include <stdexcept>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>

#include "command.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/json_text.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/core/text_lines.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/tooltherm/tool_evaluation.hpp"
#include "trueaxis/tooltherm/tool_report.hpp"
#include "trueaxis/tooltherm/zone_temperature.hpp"

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
  std::string program = "mixed";
  std::string out, report;
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
  if (a.program == "mixed") o.program = ToolDayProgramKind::kMixed;
  else if (a.program == "blocks") o.program = ToolDayProgramKind::kBlocks;
  else throw InputError("command line", 0, "--program", "must be mixed or blocks");
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
      "| tool | cutting samples | hysteresis µm | none RMS / max µm | one model | heating/steady/cooling sub-models | first-order lag | "
      "two-body | zones | best (by CV) | RMS reduction: sub-models / best |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& sc : ev.tools) {
    const ToolDescription* t = table.Find(sc.tool);
    auto cell = [&](ToolModelKind k) {
      const auto i = static_cast<std::size_t>(k);
      return fmt::format("{:.2f} / {:.2f}", sc.rms_um[i], sc.max_um[i]);
    };
    const double none = sc.rms_um[0];
    auto red = [&](ToolModelKind k) { return none > 0 ? 100.0 * (1 - sc.rms_um[static_cast<std::size_t>(k)] / none) : 0.0; };
    const auto m = ev.models.find(sc.tool);
    s += fmt::format("| T{} {} | {} | {:.2f} | {} | {} | {} | {} | {} | {} | {} ({}) | {:.0f} % / {:.0f} % |\n", sc.tool,
                     t ? t->name : "", sc.samples, sc.curve_spread_um, cell(ToolModelKind::kNone),
                     cell(ToolModelKind::kOne), cell(ToolModelKind::kIntervals), cell(ToolModelKind::kLag),
                     cell(ToolModelKind::kTwoBody), cell(ToolModelKind::kZones), cell(ToolModelKind::kBest),
                     m == ev.models.end()                      ? "-"
                     : !m->second.fallback_from_tools.empty() ? "fallback"
                                                              : ToolModelKindName(m->second.best),
                     red(ToolModelKind::kIntervals),
                     red(ToolModelKind::kBest));
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
      "Tool thermal day ({} program): trained on day seed {}, tested on day seed {} ({} h, Tv every {} s from the {}), "
      "residual tip error after the tool length offset (through the limiter):\n\n{}",
      a.program, a.seed, a.seed + 1, a.hours, a.sample_s, a.sensor, ScoreTable(ev, table));
  std::fputs(md.c_str(), stdout);
  if (!a.report.empty()) {
    if (fs::path(a.report).has_parent_path()) fs::create_directories(fs::path(a.report).parent_path());
    std::ofstream(a.report) << ToolDayReportHtml(table, test, ev, md.substr(0, md.find("\n")));
    std::printf("wrote %s\n", a.report.c_str());
  }
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

// ---- tool render: one frame of a warmed-up virtual tool, as a user's camera would give it ----
struct RenderArgs {
  std::string tools, out;
  int tool = 1;
  double minutes = 10;
  std::uint64_t seed = 1;
};

void RunRender(const RenderArgs& a) {
  const ToolTable table = ReadToolFile(a.tools);
  const ToolDescription* t = table.Find(a.tool);
  if (!t) throw InputError(a.tools, 0, "--tool", fmt::format("tool {} is not in the file", a.tool));
  if (!(a.minutes >= 0 && a.minutes <= 600)) throw InputError("command line", 0, "--minutes", "must be in [0, 600]");
  VirtualTool vt(*t, table.standard_temp_c, 20);
  const ToolConditions cut{true, 24, 6000, 120 * t->diameter_mm, false, 20, 20};
  for (int i = 0; i < static_cast<int>(a.minutes * 60); ++i) vt.Advance(1, cut);
  ThermalCameraOptions o;
  std::mt19937_64 rng(a.seed);
  const cv::Mat img = RenderThermalImage(vt, {false, 20, 20}, o, rng);
  fs::create_directories(a.out);
  cv::Mat counts;  // 16-bit raw counts in centi-kelvin: T = counts · 0.01 − 273.15
  img.convertTo(counts, CV_16U, 100.0, 27315.0);
  const std::string png = (fs::path(a.out) / "frame.png").string();
  if (!cv::imwrite(png, counts)) throw std::runtime_error("cannot write " + png);
  std::ofstream csv(fs::path(a.out) / "frame.csv");
  for (int r = 0; r < img.rows; ++r)
    for (int c = 0; c < img.cols; ++c) csv << fmt::format("{:.2f}{}", img.at<float>(r, c), c + 1 < img.cols ? "," : "\n");
  const auto zones = ImageZonesFor(*t, o);
  std::ofstream(fs::path(a.out) / "zones.toml") << ZoneToml(zones);
  std::vector<double> tr, sr;
  for (const auto& z : t->zones) {
    tr.push_back(vt.SurfaceC(0.5 * (z.from_mm + z.to_mm)));
    sr.push_back(z.area_mm2);
  }
  std::printf("tool %d after %.0f min of cutting: true tip error %+.2f um, Tv of the true surface %.2f C\n"
              "wrote %s (16-bit, T = counts * 0.01 - 273.15), frame.csv (C), zones.toml\n",
              a.tool, a.minutes, vt.TipErrorUm(), WeightedMeanTemperatureC(tr, sr), png.c_str());
}

// ---- tool tv: a user's image and zone file → Tr per zone and Tv ----
struct TvArgs {
  std::string image, zones;
  double scale = 1, offset_c = 0;
};

void RunTv(const TvArgs& a) {
  const ZoneFile zones = ReadZoneFile(a.zones);
  const cv::Mat img = ReadThermalImage(a.image, a.scale, a.offset_c);
  const auto tr = ZoneMeansC(img, zones, a.image);
  for (std::size_t i = 0; i < tr.size(); ++i)
    std::printf("zone %-10s Tr %8.3f C  Sr %10.1f mm2\n", zones.zones[i].name.c_str(), tr[i], zones.zones[i].area_mm2);
  std::printf("Tv %.3f C\n", WeightedMeanTemperatureC(tr, ZoneAreas(zones.zones)));
}

// ---- tool offset: a model file + a Tv course → predicted error and the offset to apply ----
struct OffsetArgs {
  std::string models, tools, series, model = "intervals";
  int tool = 1;
};

std::vector<ToolRecord> ReadTvSeries(const std::string& path, std::vector<int>* lines) {
  const std::string text = ReadTextFile(path);
  LineCursor cur(text);
  std::vector<ToolRecord> rows;
  bool header = false;
  while (cur.Next()) {
    if (cur.line().empty() || cur.line()[0] == '#') continue;
    const auto f = SplitCsvFields(cur.line());
    if (!header) {
      if (f.size() < 2 || f[0] != "time_s" || f[1] != "tv_c")
        throw InputError(path, cur.number(), "header", "expected the columns time_s,tv_c");
      header = true;
      continue;
    }
    if (f.size() < 2) throw InputError(path, cur.number(), "tv_c", "missing");
    const auto t = ParseDouble(f[0]), v = ParseDouble(f[1]);
    if (!t) throw InputError(path, cur.number(), "time_s", fmt::format("'{}' is not a number", f[0]));
    if (!v || !PlausibleToolTemperatureC(*v))
      throw InputError(path, cur.number(), "tv_c",
                       fmt::format("'{}' is not a temperature in [{:g}, {:g}] C", f[1], kToolTemperatureMinC, kToolTemperatureMaxC));
    if (!rows.empty() && !(*t > rows.back().time_s)) throw InputError(path, cur.number(), "time_s", "must increase");
    rows.push_back({*t, *v, 0, rows.empty(), {}});
    lines->push_back(cur.number());
  }
  if (rows.empty()) throw InputError(path, "no samples");
  return rows;
}

// The series against the Tv the tool's models were trained on. Beyond the range the one curve
// extrapolates (the interval sub-models hold their edge): a warning. Far beyond it — by more than
// the range's own width and 10 °C — the series is not this tool's Tv (a series in kelvin, raw
// counts, another tool's): refused, since the offset printed below would go to the machine.
void CheckTvAgainstTraining(const ToolErrorModel& model, const std::vector<ToolRecord>& rows,
                            const std::vector<int>& lines, const std::string& path) {
  const auto range = model.TrainingTvRangeC();
  if (!range) return;
  const auto [lo, hi] = *range;
  const double slack = std::max(10.0, hi - lo);
  std::size_t outside = 0, first_outside = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const double tv = rows[i].tv_c;
    if (tv < lo - slack || tv > hi + slack)
      throw InputError(path, lines[i], "tv_c",
                       fmt::format("Tv {:g} °C is far outside the {:.1f}…{:.1f} °C tool {}'s models were trained on "
                                   "(a series in kelvin? subtract 273.15); no offset computed",
                                   tv, lo, hi, model.tool));
    if ((tv < lo || tv > hi) && outside++ == 0) first_outside = i;
  }
  if (outside > 0)
    std::fprintf(stderr,
                 "warning: %s: %zu of %zu Tv samples (the first on line %d, %.2f °C) are outside the %.1f…%.1f °C the "
                 "models were trained on; the prediction extrapolates there\n",
                 path.c_str(), outside, rows.size(), lines[first_outside], rows[first_outside].tv_c, lo, hi);
}

void RunOffset(const OffsetArgs& a) {
  const ToolTable table = ReadToolFile(a.tools);
  const ToolDescription* t = table.Find(a.tool);
  if (!t) throw InputError(a.tools, 0, "--tool", fmt::format("tool {} is not in the file", a.tool));
  const nlohmann::json doc = ParseJsonOrThrow(ReadTextFile(a.models), a.models);
  if (!doc.contains("tools") || !doc.at("tools").is_array()) throw InputError(a.models, 0, "tools", "missing array");
  const nlohmann::json* entry = nullptr;
  for (const auto& j : doc.at("tools"))
    if (j.is_object() && j.value("tool", -1) == a.tool) entry = &j;
  if (!entry) throw InputError(a.models, 0, "tools", fmt::format("no model for tool {}", a.tool));
  const ToolErrorModel model = ToolErrorModel::FromJson(*entry, a.models);
  ToolModelKind kind;
  try {
    kind = ParseToolModelKind(a.model);
  } catch (const std::invalid_argument& e) {
    throw InputError("command line", 0, "--model", e.what());
  }
  std::vector<int> lines;
  const auto rows = ReadTvSeries(a.series, &lines);
  CheckTvAgainstTraining(model, rows, lines, a.series);
  if (!model.fallback_from_tools.empty()) {
    std::string from;
    for (int f : model.fallback_from_tools) from += fmt::format("{}T{}", from.empty() ? "" : ", ", f);
    std::fprintf(stderr,
                 "warning: %s: tool %d's model is a stand-in built from %s (it cut too little on its training day); "
                 "record it cutting and fit again\n",
                 a.models.c_str(), a.tool, from.c_str());
  }
  ToolErrorPredictor p(model, kind);
  double e = 0;
  for (const auto& r : rows) e = p.Push(r.time_s, r.tv_c, r.restart);
  const double correction = -e;
  std::printf("tool %d at t = %.0f s, Tv %.2f C, interval %s: predicted tip error %+.2f um (%s model), correction %+.2f um\n",
              a.tool, rows.back().time_s, rows.back().tv_c, thermal::ThermalIntervalName(p.interval()), e,
              ToolModelKindName(kind), correction);
  std::printf("LinuxCNC tool table: %s\n", LinuxCncToolTableLine(*t, t->GaugeLengthMm(), correction).c_str());
  std::printf("%s\n", G10ToolOffsetCommand(t->number, t->GaugeLengthMm(), correction).c_str());
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
  d->add_option("--program", day->program, "mixed (job shop) or blocks (long heating and cooling)")->capture_default_str();
  d->add_option("--report", day->report, "HTML report: scores, error against Tv by interval, error over the day");
  d->add_option("--out", day->out, "folder for tool_models.json, tool_day.md, tool_day_test.csv");
  d->callback([day] { RunDay(*day); });

  auto ra = std::make_shared<RenderArgs>();
  auto* r = tool->add_subcommand("render", "One thermal-camera frame of a virtual tool after some minutes of cutting");
  r->add_option("--tools", ra->tools, "tool file")->required();
  r->add_option("--tool", ra->tool, "tool number")->capture_default_str();
  r->add_option("--minutes", ra->minutes, "minutes of cutting before the frame")->capture_default_str();
  r->add_option("--seed", ra->seed, "noise seed")->capture_default_str();
  r->add_option("--out", ra->out, "folder for frame.png, frame.csv, zones.toml")->required();
  r->callback([ra] { RunRender(*ra); });

  auto ta = std::make_shared<TvArgs>();
  auto* v = tool->add_subcommand("tv", "Tr per zone and Tv = sum(Tr*Sr)/sum(Sr) from a thermal image and a zone file");
  v->add_option("--image", ta->image, "16-bit PNG/TIFF of raw counts, or a CSV matrix")->required();
  v->add_option("--zones", ta->zones, "zone file (TOML)")->required();
  v->add_option("--scale", ta->scale, "temperature = value * scale + offset")->capture_default_str();
  v->add_option("--offset", ta->offset_c, "offset in C (e.g. -273.15 for kelvin)")->capture_default_str();
  v->callback([ta] { RunTv(*ta); });

  auto oa = std::make_shared<OffsetArgs>();
  auto* o = tool->add_subcommand("offset", "Predicted tip error of a Tv course and the tool length offset to apply");
  o->add_option("--models", oa->models, "tool_models.json (from tool day)")->required();
  o->add_option("--tools", oa->tools, "tool file (nominal lengths)")->required();
  o->add_option("--tool", oa->tool, "tool number")->capture_default_str();
  o->add_option("--series", oa->series, "CSV time_s,tv_c of the mounted tool since it was mounted")->required();
  o->add_option("--model", oa->model, "none, one, intervals, lag, two_body, zones (needs the zone means: falls back to one), best")->capture_default_str();
  o->callback([oa] { RunOffset(*oa); });
}

CommandRegistrar reg("tool", Setup);

}  // namespace
}  // namespace trueaxis::cli
