// trueaxis vision render|calibrate|reference|measure|run — seed 001: spindle
// growth read by a camera from a marker drawn on the spindle (docs/vision.md).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <fstream>
#include <memory>
#include <sstream>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>

#include "command.hpp"
#include "trueaxis/core/output_path.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/install_paths.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/core/text_lines.hpp"
#include "trueaxis/vision/camera_calibration.hpp"
#include "trueaxis/vision/credibility.hpp"
#include "trueaxis/vision/image_file.hpp"
#include "trueaxis/runtime/cycle_step.hpp"
#include "trueaxis/sim/machine_description.hpp"
#include "trueaxis/vision/vision_day.hpp"
#include "trueaxis/vision/vision_loop.hpp"
#include "trueaxis/vision/vision_report.hpp"

namespace trueaxis::cli {
namespace {
using namespace trueaxis::vision;
namespace fs = std::filesystem;

struct DayArgs {
  std::string marker, camera;
  double hours = 10;
  double interval_s = 1800;
  std::string disturb = "clean";
  std::string program;  // empty: the heating/cooling day
  std::uint64_t seed = 1;
  int average = 1;
  int scale_average = 12;
};

void AddDayArgs(CLI::App* cmd, DayArgs* a) {
  cmd->add_option("--marker", a->marker, "marker TOML (docs/vision.md)")->required();
  cmd->add_option("--camera", a->camera, "camera YAML (OpenCV camera_matrix, distortion_coefficients, image size)")
      ->required();
  cmd->add_option("--hours", a->hours, "length of the day")->capture_default_str();
  cmd->add_option("--interval-s", a->interval_s, "seconds between frames")->capture_default_str();
  cmd->add_option("--disturb", a->disturb,
                  "comma list of: clean, noise, blur, light, glints, droplets, chips, drift, wear, rotation, all")
      ->capture_default_str();
  cmd->add_option("--speeds", a->program, "spindle speed program seconds:rpm,… (default: heating/steady/cooling day)");
  cmd->add_option("--seed", a->seed, "random seed (same seed, same images)")->capture_default_str();
  cmd->add_option("--average", a->average, "run: the Z term is the mean of the last N credible readings")->capture_default_str();
  cmd->add_option("--scale-average", a->scale_average, "with a reference scale ([scale]): mean of its last N readings")
      ->capture_default_str();
}

VisionDayOptions MakeDayOptions(const DayArgs& a) {
  if (!(a.hours > 0 && a.hours <= 72)) throw InputError("command line", 0, "--hours", "must be in (0, 72]");
  if (!(a.interval_s >= 1)) throw InputError("command line", 0, "--interval-s", "must be ≥ 1 s");
  if (a.hours * 3600 / a.interval_s > 20000) throw InputError("command line", 0, "--interval-s", "more than 20000 frames");
  VisionDayOptions o;
  o.hours = a.hours;
  o.frame_interval_s = a.interval_s;
  o.seed = a.seed;
  if (a.average < 1 || a.average > 1000) throw InputError("command line", 0, "--average", "must be 1…1000");
  o.average_frames = a.average;
  if (a.scale_average < 1 || a.scale_average > 1000) throw InputError("command line", 0, "--scale-average", "must be 1…1000");
  o.scale_average_frames = a.scale_average;
  o.program = sim::SpindleSpeedProgram::HeatingCoolingDay(a.hours);
  if (!a.program.empty()) {
    try {
      o.program = sim::SpindleSpeedProgram::Parse(a.program);
    } catch (const std::invalid_argument& e) {
      throw InputError("command line", 0, "--speeds", e.what());
    }
  }
  std::stringstream ss(a.disturb);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!ApplyDisturbance(std::string(Trim(item)), o))
      throw InputError("command line", 0, "--disturb", "'" + item + "' is not one of clean, noise, blur, light, glints, droplets, chips, drift, wear, rotation, all");
  return o;
}

// Images measured against a marker file and a camera file (reference, measure).
struct ImageArgs {
  std::vector<std::string> images;
  std::string marker, camera;
};

void AddImageArgs(CLI::App* cmd, ImageArgs* a, const std::string& images_help) {
  cmd->add_option("images", a->images, images_help)->required();
  cmd->add_option("--marker", a->marker, "marker TOML")->required();
  cmd->add_option("--camera", a->camera, "camera YAML")->required();
}

MarkerDescription ReadMarker(const std::string& path) {
  MarkerDescription m = ReadMarkerFile(path);
  if (!m.EpsilonInSeedRange())
    fmt::print(stderr, "warning: {}: credibility.epsilon = {:g} is outside the marker method's range 0.1 %…5 %\n", path, m.epsilon);
  return m;
}

cv::Mat ReadImage(const std::string& path) {
  if (!fs::exists(path)) throw InputError(path, "no such image file");
  // Grey, keeping 16-bit depth (colour and alpha are converted by OpenCV).
  cv::Mat img = DecodeImageFile(path, cv::IMREAD_GRAYSCALE | cv::IMREAD_ANYDEPTH);
  if (img.empty()) throw InputError(path, "empty or unreadable image (not a PNG/JPEG/TIFF/BMP OpenCV can decode)");
  return img;
}

void WriteImage(const std::string& path, const cv::Mat& img) {
  if (!cv::imwrite(path, img)) throw InputError(path, "cannot write the image");
}

// Picks up to four example frames: first, peak growth, first rejected, last.
std::vector<std::size_t> ExampleIndices(const std::vector<ReportRow>& rows) {
  std::vector<std::size_t> idx;
  if (rows.empty()) return idx;
  idx.push_back(0);
  std::size_t peak = 0, rejected = rows.size();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].reading.credible() && rows[i].reading.growth_um > rows[peak].reading.growth_um) peak = i;
    if (!rows[i].reading.credible() && rejected == rows.size()) rejected = i;
  }
  for (std::size_t i : {peak, rejected, rows.size() - 1})
    if (i < rows.size() && std::find(idx.begin(), idx.end(), i) == idx.end()) idx.push_back(i);
  return idx;
}

std::string Caption(const ReportRow& r) {
  return fmt::format("{} at {:.2f} h: {}{}", r.name, r.time_s / 3600.0, ReadingStatusName(r.reading.status),
                     r.reading.measured() ? fmt::format(", Δz {:+.1f} µm", r.reading.growth_um) : "");
}

void WriteReadingsCsv(const std::string& path, const std::vector<ReportRow>& rows) {
  std::ofstream f(path);
  if (!f) throw InputError(path, "cannot write");
  f << "frame,time_s,status,cb1_mm,cb2_mm,k1,k2,czs_mm,growth_um,true_growth_um,stop,reason\n";
  for (const auto& r : rows)
    f << fmt::format("{},{:.1f},{},{:.6f},{:.6f},{:.9f},{:.9f},{:.6f},{:.3f},{},{},\"{}\"\n", r.name, r.time_s,
                     ReadingStatusName(r.reading.status), r.reading.cb1_mm, r.reading.cb2_mm, r.reading.k1, r.reading.k2,
                     r.reading.czs_mm, r.reading.growth_um,
                     r.true_growth_um ? fmt::format("{:.3f}", *r.true_growth_um) : "", r.stop ? 1 : 0, r.reading.reason);
}

void PrintReading(const ReportRow& r) {
  if (r.reading.measured())
    fmt::print("{}: {}  K1 {:.7f}  K2 {:.7f}  Δz {:+.1f} µm{}{}\n", r.name, ReadingStatusName(r.reading.status), r.reading.k1,
               r.reading.k2, r.reading.growth_um,
               r.true_growth_um ? fmt::format(" (truth {:+.1f})", *r.true_growth_um) : "",
               r.reading.reason.empty() ? "" : "  — " + r.reading.reason);
  else
    fmt::print("{}: {} — {}\n", r.name, ReadingStatusName(r.reading.status), r.reading.reason);
}

// truth.csv written by `vision render`: file,time_s,rpm,true_k,true_growth_um
std::map<std::string, std::pair<double, double>> ReadTruth(const std::string& path) {
  std::map<std::string, std::pair<double, double>> out;
  std::stringstream ss(ReadTextFile(path));
  std::string line;
  int n = 0;
  while (std::getline(ss, line)) {
    ++n;
    if (n == 1 || Trim(line).empty()) continue;
    const auto f = SplitCsvFields(line);
    if (f.size() < 5) throw InputError(path, n, "", "want file,time_s,rpm,true_k,true_growth_um");
    const auto t = ParseDouble(f[1]), g = ParseDouble(f[4]);
    if (!t) throw InputError(path, n, "time_s", "not a number");
    if (!g) throw InputError(path, n, "true_growth_um", "not a number");
    out[std::string(f[0])] = {*t, *g};
  }
  return out;
}

void WriteAlarm(const std::string& path, const CredibilityMonitor& m) {
  if (path.empty()) return;
  std::ofstream f(path);
  if (!f) throw InputError(path, "cannot write");
  f << fmt::format("{{\"feed_hold\": {}, \"rejected_in_row\": {}, \"growth_um\": {:.3f}, \"message\": \"{}\"}}\n",
                   m.stop() ? "true" : "false", m.rejected_in_row(), m.growth_um(), m.message());
}

void Setup(CLI::App& app) {
  auto* vision = app.add_subcommand("vision", "Spindle growth read by a camera from a marker on the spindle");
  vision->require_subcommand(1);

  {  // render
    auto* cmd = vision->add_subcommand("render", "Render a day of marker images (and calibration boards) with the virtual camera");
    auto a = std::make_shared<DayArgs>();
    auto out = std::make_shared<std::string>();
    auto boards = std::make_shared<int>(0);
    AddDayArgs(cmd, a.get());
    cmd->add_option("--out", *out, "folder for frame_NNNN.png, reference_N.png, truth.csv (and board_NN.png)")->required();
    cmd->add_option("--calibration-images", *boards, "also render this many 9×6 chessboards (8 mm squares)")
        ->capture_default_str();
    cmd->callback([a, out, boards] {
      const MarkerDescription marker = ReadMarker(a->marker);
      const CameraModel camera = ReadCameraFile(a->camera);
      VisionDayOptions o = MakeDayOptions(*a);
      fs::create_directories(*out);
      std::ofstream truth(fs::path(*out) / "truth.csv");
      truth << "file,time_s,rpm,true_k,true_growth_um\n";
      int n = 0;
      RunVisionDay(marker, camera, o, [&](const VisionFrame& f, const cv::Mat& img) {
        const std::string name = fmt::format("frame_{:04d}.png", n++);
        WriteImage((fs::path(*out) / name).string(), img);
        truth << fmt::format("{},{:.1f},{:.0f},{:.9f},{:.3f}\n", name, f.time_s, f.rpm, f.true_k, f.true_growth_um);
      });
      VirtualCamera cam(camera);
      for (int i = 0; i < 3; ++i) {  // standard temperature, for `vision reference`
        MarkerScene s;
        s.angle_deg = 42.0 + 3.0 * i;
        WriteImage((fs::path(*out) / fmt::format("reference_{}.png", i)).string(), cam.RenderMarker(marker, s, {}, 100 + i));
      }
      ChessboardSpec board;
      const auto poses = CalibrationPoses(board, marker.distance_mm, *boards);
      ImageDisturbances d;
      d.noise_grey = 1.0;
      for (int i = 0; i < *boards; ++i)
        WriteImage((fs::path(*out) / fmt::format("board_{:02d}.png", i)).string(),
                   cam.RenderChessboard(board.cols, board.rows, board.square_mm, poses[i].first, poses[i].second, d, 200 + i));
      fmt::print("{} frames, 3 reference images{} and truth.csv written to {}\n", n,
                 *boards ? fmt::format(", {} chessboards", *boards) : "", *out);
    });
  }
  {  // calibrate
    auto* cmd = vision->add_subcommand("calibrate", "Calibrate the camera from chessboard images (OpenCV)");
    auto images = std::make_shared<std::vector<std::string>>();
    auto out = std::make_shared<std::string>();
    auto board = std::make_shared<std::string>("9x6");
    auto square = std::make_shared<double>(8.0);
    cmd->add_option("images", *images, "chessboard images (PNG/JPEG/…)")->required();
    cmd->add_option("--board", *board, "inner corners, cols x rows")->capture_default_str();
    cmd->add_option("--square-mm", *square, "square size")->capture_default_str();
    cmd->add_option("--out", *out, "camera YAML to write")->required();
    cmd->callback([images, out, board, square] {
      RefuseOutputOverInput(*out, *images, "--out");
      ChessboardSpec spec;
      spec.square_mm = *square;
      if (std::sscanf(board->c_str(), "%dx%d", &spec.cols, &spec.rows) != 2)
        throw InputError("command line", 0, "--board", "'" + *board + "' is not COLSxROWS (e.g. 9x6)");
      std::vector<std::pair<std::string, cv::Mat>> imgs;
      for (const auto& p : *images) imgs.emplace_back(p, ReadImage(p));
      const auto r = CalibrateCamera(imgs, spec);
      for (const auto& s : r.skipped) fmt::print(stderr, "warning: {}\n", s);
      WriteCameraFile(*out, r.camera);
      fmt::print("{} of {} images used; fx {:.2f} fy {:.2f} cx {:.2f} cy {:.2f} k1 {:.5f} k2 {:.5f}; RMS reprojection {:.4f} px; "
                 "written to {}\n",
                 r.images_used, images->size(), r.camera.fx, r.camera.fy, r.camera.cx, r.camera.cy, r.camera.k1,
                 r.camera.k2, r.camera.rms_reprojection_px, *out);
    });
  }
  {  // reference
    auto* cmd = vision->add_subcommand("reference", "Read the marker at the standard temperature: the raw K1, K2 every later reading is divided by");
    auto a = std::make_shared<ImageArgs>();
    auto out = std::make_shared<std::string>();
    AddImageArgs(cmd, a.get(), "images taken at the standard temperature");
    cmd->add_option("--out", *out, "marker TOML to write, with [reference] k1, k2")->required();
    cmd->callback([a, out] {
      std::vector<std::string> images_and_camera = a->images;
      images_and_camera.push_back(a->camera);
      RefuseOutputOverInput(*out, images_and_camera, "--out");
      const auto* images = &a->images;
      MarkerDescription m = ReadMarker(a->marker);
      const CameraModel cam = ReadCameraFile(a->camera);
      m.reference_k1 = m.reference_k2 = 1.0;
      std::vector<MarkerReading> readings;
      for (const auto& p : *images) {
        readings.push_back(MeasureMarker(ReadImage(p), cam, m, p));
        if (!readings.back().measured())
          fmt::print(stderr, "warning: {}: {} — {}\n", p, ReadingStatusName(readings.back().status), readings.back().reason);
      }
      bool any = false;
      for (const auto& r : readings) any |= r.measured();
      if (!any) throw InputError(images->front(), 0, "", "the marker could not be measured in any reference image");
      std::tie(m.reference_k1, m.reference_k2) = ReferenceK(readings);
      std::ofstream f(*out);
      if (!f) throw InputError(*out, "cannot write");
      f << MarkerToml(m);
      fmt::print("reference raw K1 {:.7f}, K2 {:.7f} (from {} image(s)); written to {}\n", m.reference_k1, m.reference_k2,
                 images->size(), *out);
    });
  }
  {  // measure
    auto* cmd = vision->add_subcommand("measure", "Measure the marker in images: K1, K2, credibility, Δz, the stop rule");
    auto a = std::make_shared<ImageArgs>();
    auto truth_path = std::make_shared<std::string>();
    auto csv = std::make_shared<std::string>();
    auto report = std::make_shared<std::string>();
    auto alarm = std::make_shared<std::string>();
    auto scale_average = std::make_shared<int>(12);
    auto interval = std::make_shared<double>(60.0);
    AddImageArgs(cmd, a.get(), "images, in time order");
    cmd->add_option("--interval-s", *interval, "time between the images (the report's time axis; --truth overrides)")
        ->capture_default_str();
    cmd->add_option("--scale-average", *scale_average, "with a reference scale ([scale]): mean of its last N readings")
        ->capture_default_str();
    cmd->add_option("--truth", *truth_path, "truth.csv from `vision render` (adds the true Δz)");
    cmd->add_option("--csv", *csv, "write the readings as CSV");
    cmd->add_option("--report", *report, "write an HTML report");
    cmd->add_option("--alarm-out", *alarm, "write the stop rule's state as JSON (feed_hold, message) for a CNC bridge");
    cmd->callback([=] {
      std::vector<std::string> inputs = a->images;
      inputs.insert(inputs.end(), {a->marker, a->camera, *truth_path});
      RefuseOutputOverInput(*csv, inputs, "--csv");
      RefuseOutputOverInput(*report, inputs, "--report");
      RefuseOutputOverInput(*alarm, inputs, "--alarm-out");
      const auto* images = &a->images;
      const MarkerDescription m = ReadMarker(a->marker);
      const CameraModel cam = ReadCameraFile(a->camera);
      std::map<std::string, std::pair<double, double>> truth;
      if (!truth_path->empty()) truth = ReadTruth(*truth_path);
      CredibilityMonitor monitor(m.max_rejected_in_row);
      if (*scale_average < 1) throw InputError("command line", 0, "--scale-average", "must be ≥ 1");
      if (!(*interval > 0)) throw InputError("command line", 0, "--interval-s", "must be > 0");
      ScaleAverager scale_avg(*scale_average);
      std::vector<ReportRow> rows;
      std::vector<cv::Mat> kept;
      for (std::size_t i = 0; i < images->size(); ++i) {
        const std::string& p = (*images)[i];
        ReportRow row;
        row.name = fs::path(p).filename().string();
        row.time_s = static_cast<double>(i) * *interval;
        const cv::Mat img = ReadImage(p);
        row.reading = MeasureMarker(img, cam, m, p);
        scale_avg.Apply(row.reading, m);
        if (auto it = truth.find(row.name); it != truth.end()) row.time_s = it->second.first, row.true_growth_um = it->second.second;
        row.stop = monitor.Add(row.reading);
        PrintReading(row);
        if (row.stop) fmt::print(stderr, "ALARM: {}\n", monitor.message());
        rows.push_back(row);
        if (!report->empty()) kept.push_back(img);
      }
      if (!csv->empty()) WriteReadingsCsv(*csv, rows);
      WriteAlarm(*alarm, monitor);
      if (!report->empty()) {
        std::vector<ReportFrame> frames;
        for (std::size_t i : ExampleIndices(rows)) frames.push_back({Caption(rows[i]), DrawReading(kept[i], rows[i].reading)});
        int credible = 0;
        for (const auto& r : rows) credible += r.reading.credible();
        BuildVisionReport("Spindle growth from the marker", m, rows, frames,
                          {{"images", std::to_string(rows.size())}, {"credible", std::to_string(credible)},
                           {"stop rule", monitor.stop() ? monitor.message() : "not tripped"}})
            .Save(*report);
        fmt::print("report written to {}\n", *report);
      }
      if (monitor.stop()) throw std::runtime_error("the stop rule tripped (exit code 1): " + monitor.message());
    });
  }
  {  // run
    auto* cmd = vision->add_subcommand(
        "run", "The camera in the loop: virtual spindle and machine, Δz as the compensator's Z term, stop rule → feed hold");
    auto a = std::make_shared<DayArgs>();
    auto csv = std::make_shared<std::string>();
    auto loop_csv = std::make_shared<std::string>();
    auto report = std::make_shared<std::string>();
    auto machine = std::make_shared<std::string>();  // empty: the example VMC-850, found at run time
    auto relation_from = std::make_shared<std::string>();
    auto lo = std::make_shared<VisionLoopOptions>();
    AddDayArgs(cmd, a.get());
    cmd->add_option("--relation-from", *relation_from,
                    "calibrate the marker-to-spindle relation on a reference run of this speed program (seconds:rpm,…, over "
                    "--hours; the real growth measured beside the marker every 5 min) and read Δz through it");
    cmd->add_option("--csv", *csv, "write the readings and the truth as CSV");
    cmd->add_option("--loop-csv", *loop_csv, "write the Z error at the tool with/without the term, the correction and alarms per frame");
    cmd->add_option("--report", *report, "write an HTML report");
    cmd->add_option("--machine", *machine,
                    "machine TOML of the virtual machine the compensator runs against (default: "
                    "examples/machines/vmc850.toml of the working folder, else of the installed examples)");
    cmd->add_option("--z-axis", lo->z_axis, "the axis the spindle grows along")->capture_default_str();
    cmd->add_option("--cycle-s", lo->cycle_s, "compensator cycle (s)")->capture_default_str();
    cmd->add_option("--max-step-um", lo->compensator.shaper.max_step_um, "output shaper: change per cycle (µm)")->capture_default_str();
    cmd->add_option("--max-correction-um", lo->compensator.shaper.max_correction_um, "output shaper: bound (µm)")->capture_default_str();
    cmd->add_option("--term-valid-s", lo->term_valid_s, "how long a Δz reading stays in force (0: until the stop rule could trip)")
        ->capture_default_str();
    cmd->callback([a, csv, loop_csv, report, machine, relation_from, lo] {
      const MarkerDescription m = ReadMarker(a->marker);
      const CameraModel cam = ReadCameraFile(a->camera);
      VisionDayOptions o = MakeDayOptions(*a);
      if (!relation_from->empty()) {
        sim::SpindleSpeedProgram reference;
        try {
          reference = sim::SpindleSpeedProgram::Parse(*relation_from);
          o.relation = FitSpindleRelation(VirtualRelationReference(m, o, reference, a->hours, 300.0));
        } catch (const std::invalid_argument& e) {
          throw InputError("command line", 0, "--relation-from", e.what());
        }
        const SpindleRelation& rel = *o.relation;
        fmt::print("marker-to-spindle relation (reference run {}): Δz = {:.3f}·M + {:.3f}·lag(M) + {:.2f} µm·lag((n/{:.0f})²), "
                   "τ {:.0f} s, calibrated up to {:.0f} rpm, {:.2f} µm RMS on the reference\n",
                   *relation_from, rel.marker_gain, rel.marker_lag_gain, rel.speed_lag_um, rel.reference_rpm, rel.tau_s,
                   rel.calibrated_rpm_max, rel.calibration_rms_um);
      }
      if (!(lo->cycle_s > 0 && lo->cycle_s <= o.frame_interval_s))
        throw InputError("command line", 0, "--cycle-s", "must be > 0 and ≤ --interval-s");
      if (!(lo->term_valid_s >= 0)) throw InputError("command line", 0, "--term-valid-s", "must be ≥ 0");
      std::string why;
      if (!lo->compensator.IsValid(&why)) throw InputError("command line", 0, "--max-step-um/--max-correction-um", why);
      if (machine->empty()) *machine = trueaxis::DefaultExampleFile("machines/vmc850.toml");
      if (!std::filesystem::exists(*machine))
        throw InputError(*machine, 0, "--machine", "machine file not found");
      const sim::MachineDescription md = sim::ReadMachineFile(*machine);
      if (md.AxisIndex(lo->z_axis) < 0)
        throw InputError(*machine, 0, "axes", "has no axis '" + lo->z_axis + "' (--z-axis)");
      std::vector<ReportRow> rows;
      std::vector<std::pair<int, cv::Mat>> images;
      const auto lr = RunVisionLoop(m, cam, o, md, *lo, [&](const VisionFrame& f, const cv::Mat& img) {
        ReportRow row{fmt::format("frame {}", rows.size()), f.time_s, f.reading, f.true_growth_um, f.stop, f.marker_growth_um};
        rows.push_back(row);
        if (!report->empty()) images.emplace_back(static_cast<int>(rows.size()) - 1, img.clone());
      });
      const auto& r = lr.day;
      if (!r.relation_warning.empty()) fmt::print(stderr, "warning: {}\n", r.relation_warning);
      if (lr.feed_hold_at_s >= 0)
        fmt::print(stderr, "ALARM vision_stop at {:.2f} h: the virtual CNC is in feed hold. {}\n", lr.feed_hold_at_s / 3600.0,
                   lr.alarm_message);
      const auto summary = std::vector<std::pair<std::string, std::string>>{
          {"disturbances", a->disturb},
          {"frames", fmt::format("{} ({} credible, {} rejected)", r.frames.size(), r.credible, r.rejected)},
          {"rejections", fmt::format("{} of {} rejected frames were bad (unmeasurable or off by > {:g} µm); {} credible "
                                     "frames were off by > {:g} µm",
                                     r.rejected_bad, r.rejected, o.bad_um, r.accepted_bad, o.bad_um)},
          {"Δz − truth (credible)", fmt::format("RMS {:.2f} µm, max {:.2f} µm", r.rms_um, r.max_um)},
          {"Δz − Czb·(K_true − 1) (camera part)", fmt::format("RMS {:.2f} µm, max {:.2f} µm", r.rms_vs_marker_um, r.max_vs_marker_um)},
          {"Z error at the tool in the loop (every cycle, change from t = 0)",
           fmt::format("without the vision term RMS {:.2f} µm, max {:.2f} µm; with it RMS {:.2f} µm, max {:.2f} µm",
                       lr.without_rms_um, lr.without_max_um, lr.with_rms_um, lr.with_max_um)},
          {"compensator", fmt::format("{} ({}), cycle {:g} s, shaper {:g} µm/cycle, bound {:g} µm; largest Z output change "
                                      "{:.2f} µm/cycle; alarms seen: {}",
                                      md.name, lo->z_axis, lo->cycle_s, lo->compensator.shaper.max_step_um,
                                      lo->compensator.shaper.max_correction_um, lr.max_output_step_um,
                                      lr.alarms_seen ? runtime::AlarmNames(lr.alarms_seen) : "none")},
          {"Z error offline (frames, term = Δz in force, no limiter)",
           fmt::format("without {:.2f} µm RMS, with {:.2f} µm RMS (mean of the last {} credible)", r.z_error_without_rms_um,
                       r.z_error_with_rms_um, o.average_frames)},
          {"reference raw K1, K2", fmt::format("{:.7f}, {:.7f}", r.reference_k1, r.reference_k2)},
          {"stop rule", lr.feed_hold_at_s >= 0 ? fmt::format("feed hold at {:.2f} h, alarm vision_stop: {}",
                                                              lr.feed_hold_at_s / 3600.0, lr.alarm_message)
                                                : "not tripped"}};
      for (const auto& [k, v] : summary) fmt::print("{}: {}\n", k, v);
      if (!csv->empty()) WriteReadingsCsv(*csv, rows);
      if (!loop_csv->empty()) {
        std::ofstream f(*loop_csv);
        if (!f) throw InputError(*loop_csv, "cannot write");
        f << "frame,time_s,z_error_with_um,z_error_without_um,correction_um,feed_hold,alarms\n";
        for (std::size_t i = 0; i < lr.samples.size(); ++i) {
          const auto& s = lr.samples[i];
          f << fmt::format("{},{:.1f},{:.3f},{:.3f},{:.3f},{},{}\n", i, s.time_s, s.z_error_with_um, s.z_error_without_um,
                           s.correction_um, s.feed_hold ? 1 : 0, runtime::AlarmNames(s.alarms));
        }
      }
      if (!report->empty()) {
        std::vector<ReportFrame> frames;
        for (std::size_t i : ExampleIndices(rows)) frames.push_back({Caption(rows[i]), DrawReading(images[i].second, rows[i].reading)});
        BuildVisionReport("Spindle growth from the marker against the virtual spindle", m, rows, frames, summary)
            .Save(*report);
        fmt::print("report written to {}\n", *report);
      }
    });
  }
}

CommandRegistrar reg("vision", Setup);

}  // namespace
}  // namespace trueaxis::cli
