#include "trueaxis/campaign/laser_program.hpp"

#include <algorithm>
#include <cctype>
#include <map>
#include <cmath>
#include <memory>

#include <fmt/format.h>

#include "trueaxis/core/ascii_case.hpp"
#include "trueaxis/sim/laser_interferometer.hpp"

namespace trueaxis::campaign {

std::vector<ProgramStep> LaserTestSteps(const AxisTargets& t, int runs) {
  std::vector<ProgramStep> steps;
  sim::RunBidirectionalCycle(
      t.targets_mm, runs, t.overrun_mm, [&](double x) { steps.push_back({x, false}); },
      [&](int, Direction, double target) { steps.push_back({target, true}); });
  return steps;
}

namespace {

// A HEIDENHAIN program name: letters and digits.
std::string HeidenhainName(const std::string& what) {
  std::string n = "TA";
  for (char ch : what)
    if (std::isalnum(static_cast<unsigned char>(ch))) n += static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  return n;
}

long long Um(double mm) { return std::llround(mm * 1000.0); }
std::string Mm(long long um) {  // 3 decimals, exact from integer micrometres
  const long long a = um < 0 ? -um : um;
  return fmt::format("{}{}.{:03}", um < 0 ? "-" : "", a / 1000, a % 1000);
}
std::string SignedMm(long long um) { return (um >= 0 ? "+" : "") + Mm(um); }
std::string Feed(double f) { return fmt::format("{}", std::llround(f)); }

// One dialect: how a program starts and ends, moves, dwells, loops and comments.
class Dialect {
 public:
  virtual ~Dialect() = default;
  virtual void Begin(const std::vector<std::string>& comments) = 0;
  virtual void Comment(const std::string& text) = 0;
  // All axes of `to` together, in machine coordinates, at `feed` (path feed).
  virtual void Move(const std::vector<std::pair<std::string, long long>>& to_um, double feed) = 0;
  virtual void Dwell(double s) = 0;
  virtual void LoopBegin() = 0;
  virtual void LoopEnd() = 0;
  virtual void End() = 0;
  std::string text;

 protected:
  void Line(const std::string& l) { text += l + "\n"; }
  // Comments in plain ASCII without parentheses: older controls stop at anything else.
  static std::string Ascii(const std::string& s) {
    std::string out;
    for (unsigned char c : s) out += (c < 0x20 || c > 0x7e || c == '(' || c == ')') ? ' ' : static_cast<char>(c);
    return out;
  }
};

class LinuxCnc : public Dialect {
 public:
  void Begin(const std::vector<std::string>& comments) override {
    Line("%");
    for (const auto& c : comments) Comment(c);
    Line("G21 G17 G40 G49 G80 G90 G94 (mm, absolute, feed per minute)");
  }
  void Comment(const std::string& t) override { Line("(" + Ascii(t) + ")"); }
  void Move(const std::vector<std::pair<std::string, long long>>& to, double feed) override {
    std::string l = "G53 G1";
    for (const auto& [a, um] : to) l += " " + a + Mm(um);
    Line(l + " F" + Feed(feed));
  }
  void Dwell(double s) override { Line(fmt::format("G4 P{}", s)); }
  void LoopBegin() override { Line("o100 repeat [10000]"); }
  void LoopEnd() override { Line("o100 endrepeat"); }
  void End() override {
    Line("M2");
    Line("%");
  }
};

class Fanuc : public Dialect {
 public:
  explicit Fanuc(int number) : number_(number) {}
  void Begin(const std::vector<std::string>& comments) override {
    Line("%");
    Line(fmt::format("O{:04} (TRUEAXIS)", number_));
    for (const auto& c : comments) Comment(c);
    Line("G21 G17 G40 G49 G80 G94");
  }
  void Comment(const std::string& t) override {
    std::string s = Ascii(t);
    for (auto& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    Line("(" + s + ")");
  }
  void Move(const std::vector<std::pair<std::string, long long>>& to, double feed) override {
    if (at_.empty()) {  // the start: absolute, machine coordinates, at rapid (G53 is one-shot and rapid on FANUC)
      std::string l = "G90 G53";
      for (const auto& [a, um] : to) l += " " + a + Mm(um);
      Line(l);
      Line("G91 (INCREMENTAL FROM HERE)");
      for (const auto& [a, um] : to) at_[a] = um;
      return;
    }
    std::string l = "G01";
    for (const auto& [a, um] : to) {
      l += " " + a + Mm(um - at_[a]);
      at_[a] = um;
    }
    Line(l + " F" + Feed(feed) + ".");
  }
  void Dwell(double s) override { Line(fmt::format("G04 X{:.1f}", s)); }
  void LoopBegin() override {}
  void LoopEnd() override { loop_ = true; }
  void End() override {
    Line("G90");
    Line(loop_ ? "M99 (REPEATS UNTIL RESET)" : "M30");
    Line("%");
  }

 private:
  int number_;
  bool loop_ = false;
  std::map<std::string, long long> at_;
};

class Sinumerik : public Dialect {
 public:
  void Begin(const std::vector<std::string>& comments) override {
    for (const auto& c : comments) Comment(c);
    Line("G71 G17 G40 G90 G94 ; mm, absolute, feed per minute");
  }
  void Comment(const std::string& t) override { Line("; " + Ascii(t)); }
  void Move(const std::vector<std::pair<std::string, long long>>& to, double feed) override {
    std::string l = "G1 SUPA";
    for (const auto& [a, um] : to) l += " " + a + "=" + Mm(um);
    Line(l + " F" + Feed(feed));
  }
  void Dwell(double s) override { Line(fmt::format("G4 F{}", s)); }
  void LoopBegin() override { Line("LOOP"); }
  void LoopEnd() override { Line("ENDLOOP"); }
  void End() override { Line("M30"); }
};

class Heidenhain : public Dialect {
 public:
  explicit Heidenhain(std::string name) : name_(std::move(name)) {}
  void Begin(const std::vector<std::string>& comments) override {
    Block("BEGIN PGM " + name_ + " MM");
    for (const auto& c : comments) Comment(c);
  }
  void Comment(const std::string& t) override { Block("; " + Ascii(t)); }
  void Move(const std::vector<std::pair<std::string, long long>>& to, double feed) override {
    std::string l = "L";
    for (const auto& [a, um] : to) l += " " + a + SignedMm(um);
    Block(l + " R0 F" + Feed(feed) + " M91");
  }
  void Dwell(double s) override {
    Block("CYCL DEF 9.0 DWELL TIME");
    Block(fmt::format("CYCL DEF 9.1 DWELL {}", s));
  }
  void LoopBegin() override { Block("LBL 1"); }
  void LoopEnd() override { Block("CALL LBL 1 REP 9999"); }
  void End() override { Block("END PGM " + name_ + " MM"); }

 private:
  void Block(const std::string& b) { Line(fmt::format("{} {}", n_++, b)); }
  std::string name_;
  int n_ = 0;
};

std::unique_ptr<Dialect> MakeDialect(Controller c, int number, const std::string& heidenhain_name) {
  switch (c) {
    case Controller::kLinuxCnc: return std::make_unique<LinuxCnc>();
    case Controller::kFanuc: return std::make_unique<Fanuc>(number);
    case Controller::kSinumerik: return std::make_unique<Sinumerik>();
    case Controller::kHeidenhain: return std::make_unique<Heidenhain>(heidenhain_name);
  }
  return std::make_unique<LinuxCnc>();
}

std::string FileName(Controller c, const std::string& what, int number) {
  switch (c) {
    case Controller::kLinuxCnc: return fmt::format("{}_linuxcnc.ngc", what);
    case Controller::kFanuc: return fmt::format("O{:04}_{}_fanuc.nc", number, what);
    case Controller::kSinumerik: {
      std::string u;
      for (char ch : what) u += static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
      return "TA_" + u + ".MPF";
    }
    case Controller::kHeidenhain: return HeidenhainName(what) + ".H";
  }
  return what;
}

}  // namespace

ProgramFile LaserTestProgram(Controller c, const CampaignMachine& machine, const CampaignAxis& axis,
                             const AxisTargets& t, int runs, int number) {
  const std::string what = fmt::format("{}_laser{}", axis.name, runs);  // the run count tells the two tests apart
  auto d = MakeDialect(c, number, HeidenhainName(what));
  d->Begin({fmt::format("trueaxis laser test, {} axis {}", machine.name, axis.name),
            fmt::format("{} targets {} to {} mm, {} runs both ways, {} s dwell at each target", t.targets_mm.size(),
                        t.targets_mm.front(), t.targets_mm.back(), runs, t.dwell_s),
            fmt::format("overrun {} mm beyond each end for the reversal, {} mm/min between targets", t.overrun_mm,
                        t.feed_mm_min),
            "machine coordinates; compensation of the axis OFF; laser zeroed at the reference"});
  const std::vector<ProgramStep> steps = LaserTestSteps(t, runs);
  int run = 0;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const bool run_start = !steps[i].dwell && (i == 0 || (i >= 1 && steps[i - 1].dwell &&
                                                         steps[i - 1].position_mm == t.targets_mm.front()));
    if (run_start) d->Comment(fmt::format("run {}", ++run));
    d->Move({{axis.name, Um(steps[i].position_mm)}}, t.feed_mm_min);
    if (steps[i].dwell) d->Dwell(t.dwell_s);
  }
  d->End();
  return {FileName(c, what, number), d->text};
}

ProgramFile WarmUpProgram(Controller c, const CampaignMachine& machine, const std::vector<std::string>& axes,
                          double feed_low, double feed_high, int number) {
  auto d = MakeDialect(c, number, HeidenhainName("warmup"));
  d->Begin({fmt::format("trueaxis warm-up, {}: axes {} reciprocating over their travel", machine.name,
                        fmt::join(axes, ", ")),
            fmt::format("strokes alternate {} and {} mm/min; runs until you stop it for a laser test", feed_low,
                        feed_high)});
  std::vector<std::pair<std::string, long long>> low, high;
  double longest = 0;
  for (const auto& name : axes) {
    const auto& a = machine.axes.at(static_cast<std::size_t>(machine.AxisIndex(name)));
    const double margin = std::min(10.0, a.TravelMm() * 0.02);  // as the virtual machine's warm-up
    low.emplace_back(a.name, Um(a.min_mm + margin));
    high.emplace_back(a.name, Um(a.max_mm - margin));
    longest = std::max(longest, a.TravelMm() - 2 * margin);
  }
  // Path feed so that the longest axis moves at the stroke's feed.
  double path = 0;
  for (std::size_t i = 0; i < low.size(); ++i) path += std::pow((high[i].second - low[i].second) / 1000.0, 2);
  const double scale = longest > 0 ? std::sqrt(path) / longest : 1;
  d->Move(low, feed_low * scale);
  d->LoopBegin();
  d->Move(high, feed_low * scale);
  d->Move(low, feed_high * scale);
  d->LoopEnd();
  d->End();
  return {FileName(c, "warmup", number), d->text};
}

}  // namespace trueaxis::campaign
