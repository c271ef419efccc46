// trueaxis fiveaxis identify|simulate|correct|bench — five-axis contour error,
// seed 004 (docs/fiveaxis.md).
#include <iostream>
#include <memory>
#include <sstream>

#include <fmt/format.h>

#include "command.hpp"
#include "trueaxis/core/output_path.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/plausibility.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/fiveaxis/axis_identification.hpp"
#include "trueaxis/fiveaxis/experiment.hpp"
#include "trueaxis/fiveaxis/experiment_report.hpp"
#include "trueaxis/fiveaxis/machine_variation.hpp"
#include "trueaxis/fiveaxis/program.hpp"

namespace trueaxis::cli {
namespace {
using namespace trueaxis::fiveaxis;

struct PathOptions {
  std::string machine, path, program;
  double feed = 0;
};

void AddPathOptions(CLI::App* cmd, PathOptions* o) {
  cmd->add_option("--machine", o->machine, "five-axis machine TOML (examples/fiveaxis/)")->required();
  cmd->add_option("--path", o->path, "built-in test path: cone, s-shape, inclined-circle, helix or inclined-pocket");
  cmd->add_option("--program", o->program, "a program: G-code subset (.nc, .ngc, …) or CSV (.csv)");
  cmd->add_option("--feed", o->feed, "feed (mm/min) of a test path, or of a CSV without a feed column");
}

ToolPath LoadPath(const PathOptions& o, const FiveAxisMachine& m) {
  if (o.path.empty() == o.program.empty()) throw InputError("command line", 0, "--path", "give either --path or --program");
  // 0 = not given (a CSV with a feed column, a G-code program); anything else must be a real feed.
  if (o.feed != 0)
    if (auto why = ImplausibleFeedMmPerMin(o.feed)) throw InputError("command line", 0, "--feed", *why);
  if (!o.program.empty()) return ReadProgramFile(o.program, m, o.feed);
  if (o.feed == 0) throw InputError("command line", 0, "--feed", "a test path needs --feed (mm/min)");
  ToolPath p = MakeTestPath(o.path, Kinematics(m.kinematics), o.feed);
  p.feed_field = "--feed";
  CheckAxisRanges(p, m, o.path);
  return p;
}

// Says on stderr which axes the model describes poorly (the correction's limit).
void WarnAboutModelFit(const TrackingErrorModel& model, const FiveAxisMachine& m) {
  for (const std::string& w : ModelFitWarnings(model, m.axis_names())) fmt::print(stderr, "warning: {}: {}\n", m.name, w);
}

TrackingErrorModel LoadOrIdentify(const std::string& model_path, const FiveAxisMachine& m) {
  TrackingErrorModel model = model_path.empty() ? IdentifyTrackingModel(m, AxisTestOptions{}, VirtualMachineRunner(m))
                                                : ModelFromJson(ReadTextFile(model_path), model_path, m.axis_names());
  WarnAboutModelFit(model, m);
  return model;
}

// --method: how the corrected command is found (docs/fiveaxis.md, "Correction").
void AddMethodOption(CLI::App* cmd, std::string* method) {
  cmd->add_option("--method", *method,
                  "inverse: the model inverted per axis; passes: the contour-error correction through the kinematics, "
                  "repeated --iterations times")
      ->check(CLI::IsMember({"inverse", "passes"}))
      ->capture_default_str();
}

CorrectionMethod MethodFromOption(const std::string& method) {
  return method == "passes" ? CorrectionMethod::kPasses : CorrectionMethod::kModelInverse;
}

void PrintRuns(const Experiment& x, const FiveAxisMachine& m) {
  fmt::print("{:<18} {:>10} {:>10} {:>14} {:>14} {:>10}\n", "run", "rms (µm)", "max (µm)", "orient. rms", "orient. max",
             "end (µm)");
  for (const SimulatedRun* r : {&x.without_ff, &x.with_ff, &x.corrected})
    fmt::print("{:<18} {:>10.3f} {:>10.3f} {:>9.2f} µrad {:>9.2f} µrad {:>10.3f}\n", r->label, r->contour.rms_um,
               r->contour.max_um, r->contour.rms_urad, r->contour.max_urad, r->contour.end_point_um);
  fmt::print("FF kf = {:.4f} (mean of the moving axes); FF + correction vs FF alone: rms −{:.1f} %, max −{:.1f} %\n",
             x.feed_forward.averaged, ReductionPercent(x.with_ff.contour.rms_um, x.corrected.contour.rms_um),
             ReductionPercent(x.with_ff.contour.max_um, x.corrected.contour.max_um));
  fmt::print("end (µm): distance of the tip from the programmed end point after the runs stand {:.2f} s longer at the end "
             "(until the model's predicted error and then the measured positions settle); the corrected program's "
             "figures are those of the written program re-run with that rest\n",
             x.end_rest_added_s + x.measured_rest_added_s);
  for (const SimulatedRun* r : {&x.without_ff, &x.with_ff, &x.corrected})
    for (int a = 0; a < kAxisCount; ++a)
      if (r->saturated_periods[a] > 0)
        fmt::print(stderr, "warning: {}: drive {} at its current limit for {} servo periods\n", r->label, m.axis_names()[a],
                   r->saturated_periods[a]);
}

void Setup(CLI::App& app) {
  auto* five = app.add_subcommand("fiveaxis", "Five-axis contour error: servo model, feed-forward, command correction");
  five->require_subcommand(1);
  {
    auto* cmd = five->add_subcommand("identify", "Run sine tests of each axis on the virtual machine and fit the tracking-error model");
    auto machine = std::make_shared<std::string>();
    auto out = std::make_shared<std::string>();
    cmd->add_option("--machine", *machine, "five-axis machine TOML")->required();
    cmd->add_option("--out,-o", *out, "model JSON to write")->required();
    cmd->callback([machine, out] {
      RefuseOutputOverInput(*out, {*machine}, "--out");
      const FiveAxisMachine m = ReadFiveAxisMachineFile(*machine);
      const TrackingErrorModel model = IdentifyTrackingModel(m, AxisTestOptions{}, VirtualMachineRunner(m));
      const auto names = m.axis_names();
      fmt::print("{:<5} {:>12} {:>12} {:>12} {:>12} {:>14} {:>16}\n", "axis", "c_v kf=0 ms", "c_a kf=1 ms²",
                 "c_j kf=1 ms³", "test rms", "fit residual", "drive mode");
      for (int a = 0; a < kAxisCount; ++a) {
        const auto& ax = model.axes[a];
        fmt::print("{:<5} {:>12.4f} {:>12.5f} {:>12.6f} {:>12.5f} {:>14.6f} {:>16}\n", names[a], ax.without_ff[0] * 1e3,
                   ax.full_ff[1] * 1e6, ax.full_ff[2] * 1e9, ax.signal_rms, ax.fit_rms,
                   ax.mode.present() ? fmt::format("{:.1f} Hz ζ {:.2f}", ax.mode.frequency_hz, ax.mode.damping) : "none");
      }
      WarnAboutModelFit(model, m);
      WriteTextFile(*out, ModelToJson(model, names));
      fmt::print("model written to {}\n", *out);
    });
  }
  {
    auto* cmd = five->add_subcommand("simulate", "Run a tool path on the virtual machine and print its contour error");
    auto o = std::make_shared<PathOptions>();
    auto kf = std::make_shared<double>(0.0);
    auto aff = std::make_shared<double>(0.0);
    auto reference = std::make_shared<std::string>();
    auto csv = std::make_shared<std::string>();
    AddPathOptions(cmd, o.get());
    cmd->add_option("--kf", *kf, "velocity feed-forward coefficient of every drive")->capture_default_str();
    cmd->add_option("--aff", *aff, "acceleration (torque) feed-forward, 0..1 of the drive's inertia")->capture_default_str();
    cmd->add_option("--reference", *reference, "judge against this program's path (e.g. the original of a corrected program)");
    cmd->add_option("--csv", *csv, "write time, commanded and actual joints, contour error per servo period");
    auto end_rest = std::make_shared<double>(0.5);
    cmd->add_option("--end-rest-s", *end_rest, "the machine stands this long at the end before the end point is judged")
        ->capture_default_str();
    cmd->callback([o, kf, aff, reference, csv, end_rest] {
      RefuseOutputOverInput(*csv, {o->machine, o->program, *reference}, "--csv");
      if (*kf < 0 || *kf > 1.5 || *aff < 0 || *aff > 1.5)
        throw InputError("command line", 0, "--kf", "feed-forward coefficients must lie in 0 … 1.5");
      const FiveAxisMachine m = ReadFiveAxisMachineFile(o->machine);
      const ToolPath path = LoadPath(*o, m);
      const ToolPath judge = reference->empty() ? path : ReadProgramFile(*reference, m, o->feed);
      const Kinematics kin(m.kinematics);
      if (!(*end_rest >= 0 && *end_rest <= 10))
        throw InputError("command line", 0, "--end-rest-s", "the rest at the end must lie in 0 … 10 s");
      Trajectory t = Interpolate(path, m);
      t.joints.resize(t.joints.size() + static_cast<std::size_t>(std::lround(*end_rest / t.dt_s)), t.joints.back());
      SimulatedRun run = SimulateRun(m, t.joints, *kf, *aff);
      for (int a = 0; a < kAxisCount; ++a)
        if (run.saturated_periods[a] > 0)
          fmt::print(stderr, "warning: drive {} at its current limit for {} servo periods\n", m.axis_names()[a],
                     run.saturated_periods[a]);
      run.contour = EvaluateContour(judge, kin, run.actual);
      fmt::print("{} on {}: {:.3f} s, kf = {:g}\ncontour error rms {:.3f} µm, max {:.3f} µm; orientation rms {:.2f} µrad, max {:.2f} µrad\n",
                 path.name, m.name, t.joints.size() * t.dt_s, *kf, run.contour.rms_um, run.contour.max_um,
                 run.contour.rms_urad, run.contour.max_urad);
      fmt::print("end point: {:.3f} µm, {:.2f} µrad from the {} end after {:.3f} s at rest\n", run.contour.end_point_um,
                 run.contour.end_orientation_urad, reference->empty() ? "program's" : "reference's", *end_rest);
      if (!csv->empty()) {
        const auto names = m.axis_names();
        std::string text = "time_s";
        for (const auto& n : names) text += ",cmd_" + n;
        for (const auto& n : names) text += ",act_" + n;
        text += ",contour_um,orientation_urad\n";
        for (std::size_t i = 0; i < t.joints.size(); ++i) {
          text += fmt::format("{:.6f}", i * t.dt_s);
          for (double v : t.joints[i]) text += fmt::format(",{:.6f}", v);
          for (double v : run.actual[i]) text += fmt::format(",{:.6f}", v);
          text += fmt::format(",{:.4f},{:.3f}\n", run.contour.position_um[i], run.contour.orientation_urad[i]);
        }
        WriteTextFile(*csv, text);
      }
    });
  }
  {
    auto* cmd = five->add_subcommand(
        "correct", "No FF / averaged FF / FF + corrected program on the virtual machine; writes the corrected program and a report");
    auto o = std::make_shared<PathOptions>();
    auto model_path = std::make_shared<std::string>();
    auto out = std::make_shared<std::string>();
    auto report = std::make_shared<std::string>();
    auto block = std::make_shared<int>(1);
    auto iterations = std::make_shared<int>(ExperimentOptions{}.correction_iterations);
    auto method = std::make_shared<std::string>("inverse");
    AddPathOptions(cmd, o.get());
    AddMethodOption(cmd, method.get());
    cmd->add_option("--iterations", *iterations, "--method passes: correction passes (1 = a one-shot correction)")
        ->capture_default_str();
    cmd->add_option("--model", *model_path, "tracking-error model from `fiveaxis identify` (default: identify now)");
    cmd->add_option("--out,-o", *out, "corrected program to write (.csv for CSV, else G-code)");
    cmd->add_option("--report", *report, "HTML report to write");
    cmd->add_option("--block-samples", *block, "servo periods per block of the corrected program")->capture_default_str();
    cmd->callback([o, model_path, out, report, block, iterations, method] {
      RefuseOutputOverInput(*out, {o->machine, o->program, *model_path}, "--out");
      RefuseOutputOverInput(*report, {o->machine, o->program, *model_path, *out}, "--report");
      const FiveAxisMachine m = ReadFiveAxisMachineFile(o->machine);
      const ToolPath path = LoadPath(*o, m);
      const TrackingErrorModel model = LoadOrIdentify(*model_path, m);
      ExperimentOptions eo;
      eo.correction_method = MethodFromOption(*method);
      eo.samples_per_block = *block;
      eo.correction_iterations = *iterations;
      if (*iterations < 1) throw InputError("command line", 0, "--iterations", "must be at least 1");
      if (*block < 1) throw InputError("command line", 0, "--block-samples", "must be at least 1");
      const Experiment x = RunExperiment(m, model, path, eo);
      fmt::print("{} on {} ({:.3f} s)\n", path.name, m.name, x.trajectory.joints.size() * x.trajectory.dt_s);
      PrintRuns(x, m);
      if (!out->empty()) {
        const bool csv = out->size() >= 4 && out->substr(out->size() - 4) == ".csv";
        WriteTextFile(*out, csv ? WriteCsvProgram(x.corrected_program, m) : x.corrected_gcode);
        fmt::print("corrected program ({} blocks) written to {}\n", x.corrected_program.vertices.size(), *out);
      }
      if (!report->empty()) {
        BuildExperimentReport(x, m, model).Save(*report);
        fmt::print("report written to {}\n", *report);
      }
    });
  }
  {
    auto* cmd = five->add_subcommand(
        "bench", "Every test path at two feeds on the machine and on machines with varied drive parameters (Markdown table)");
    auto machine = std::make_shared<std::string>();
    auto feeds = std::make_shared<std::vector<double>>(std::vector<double>{3000, 6000});
    auto variants = std::make_shared<int>(0);
    auto seed = std::make_shared<unsigned>(1);
    auto markdown = std::make_shared<std::string>();
    auto iterations = std::make_shared<int>(ExperimentOptions{}.correction_iterations);
    auto filter_ms = std::make_shared<double>(ExperimentOptions{}.correction_filter_s * 1e3);
    auto method = std::make_shared<std::string>("inverse");
    AddMethodOption(cmd, method.get());
    cmd->add_option("--iterations", *iterations, "--method passes: correction passes")->capture_default_str();
    cmd->add_option("--filter-ms", *filter_ms, "--method passes: zero-phase low-pass of the later passes' updates (0 = none)")
        ->capture_default_str();
    cmd->add_option("--machine", *machine, "five-axis machine TOML")->required();
    cmd->add_option("--feeds", *feeds, "feeds (mm/min), comma separated")->delimiter(',')->capture_default_str();
    cmd->add_option("--variants", *variants, "also this many machines with randomly varied drives")->capture_default_str();
    cmd->add_option("--seed", *seed, "random seed of the variations")->capture_default_str();
    cmd->add_option("--markdown", *markdown, "write the table as Markdown");
    cmd->callback([machine, feeds, variants, seed, markdown, iterations, filter_ms, method] {
      ExperimentOptions eo;
      eo.correction_method = MethodFromOption(*method);
      eo.correction_iterations = *iterations;
      eo.correction_filter_s = *filter_ms * 1e-3;
      if (*iterations < 1 || *filter_ms < 0) throw InputError("command line", 0, "--iterations", "passes >= 1, filter >= 0");
      for (double feed : *feeds)
        if (auto why = ImplausibleFeedMmPerMin(feed)) throw InputError("command line", 0, "--feeds", *why);
      const FiveAxisMachine base = ReadFiveAxisMachineFile(*machine);
      std::string md = "| machine | path | feed (mm/min) | kf | no FF rms / max (µm) | FF rms / max (µm) | FF + corr. rms / max (µm) | rms reduction vs FF | max reduction vs FF | end point FF / corr. (µm) |\n|---|---|---|---|---|---|---|---|---|---|\n";
      double worst = INFINITY, worst_end_um = 0;
      std::string worst_row;
      for (int v = 0; v <= *variants; ++v) {
        const FiveAxisMachine m = v == 0 ? base : VaryMachine(base, *seed + v);
        const TrackingErrorModel model = IdentifyTrackingModel(m, AxisTestOptions{}, VirtualMachineRunner(m));
        WarnAboutModelFit(model, m);
        for (const std::string& name : TestPathNames())
          for (double feed : *feeds) {
            ToolPath path = MakeTestPath(name, Kinematics(m.kinematics), feed);
            path.feed_field = "--feeds";
            const Experiment x = RunExperiment(m, model, path, eo);
            const double red = ReductionPercent(x.with_ff.contour.rms_um, x.corrected.contour.rms_um);
            const std::string row = fmt::format(
                "| {} | {} | {:g} | {:.3f} | {:.2f} / {:.2f} | {:.3f} / {:.3f} | {:.3f} / {:.3f} | {:.1f} % | {:.1f} % | "
                "{:.3f} / {:.3f} |",
                m.name, name, feed, x.feed_forward.averaged, x.without_ff.contour.rms_um, x.without_ff.contour.max_um,
                x.with_ff.contour.rms_um, x.with_ff.contour.max_um, x.corrected.contour.rms_um,
                x.corrected.contour.max_um, red, ReductionPercent(x.with_ff.contour.max_um, x.corrected.contour.max_um),
                x.with_ff.contour.end_point_um, x.corrected.contour.end_point_um);
            fmt::print("{}\n", row);
            md += row + "\n";
            if (red < worst) worst = red, worst_row = row;
            worst_end_um = std::max(worst_end_um, x.corrected.contour.end_point_um);
          }
      }
      fmt::print("worst rms reduction: {:.1f} %  {}\nworst end point of a corrected program: {:.3f} µm\n", worst, worst_row,
                 worst_end_um);
      if (!markdown->empty())
        WriteTextFile(*markdown, md + fmt::format("\nWorst RMS reduction: {:.1f} %; worst end point of a corrected program: "
                                                  "{:.3f} µm\n",
                                                  worst, worst_end_um));
    });
  }
}

CommandRegistrar reg("fiveaxis", Setup);

}  // namespace
}  // namespace trueaxis::cli
