#include "trueaxis/export/fanuc_table.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <regex>
#include <vector>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_lines.hpp"
#include "trueaxis/core/number_text.hpp"

namespace trueaxis::exporter {

bool FanucOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (axis_number < 1 || axis_number > 32) return fail("--fanuc-axis: controlled axis number 1…32");
  if (axes_sharing_pool < 1 || axes_sharing_pool > 32) return fail("--fanuc-axes: axes sharing the point pool, 1…32");
  if (!(detection_unit_um > 0) || !std::isfinite(detection_unit_um)) return fail("--detection-unit-um: must be > 0");
  if (magnification < 0 || magnification > 100) return fail("--fanuc-magnification: 1…100 (0 = choose)");
  if (point_limit < 1 || point_limit > 127) return fail("--fanuc-point-limit: 1…127");
  if (max_point_number < 1 || max_point_number > 9999) return fail("--fanuc-max-point: 1…9999");
  if (reference_point_number < -1 || reference_point_number > max_point_number)
    return fail("--fanuc-reference-number: 0…max point number (−1 = derive)");
  return true;
}

std::string FanucResult::Instructions() const {
  std::string s = fmt::format(
      "FANUC: load the tape in EDIT/MDI with parameter write enabled, then power OFF/ON and return to the reference "
      "position.\n  3620 reference point number {}, 3621 {}, 3622 {}, 3623 magnification {}\n",
      reference_point_number, min_point_number, max_point_number, magnification);
  if (reverse_min_point_number >= 0)
    s += fmt::format("  bidirectional: set bit 3605#0 = 1 yourself (the tape does not write 3605, a bit parameter "
                     "whose other bits belong to the machine); 3626 = {}\n",
                     reverse_min_point_number);
  else
    s += "  unidirectional: the tape writes the backlash to parameter 1851\n";
  s += fmt::format("  largest rounding at a point: {:.3f} um\n", max_rounding_um);
  return s;
}

namespace {

long long RoundHalfAway(double v) { return static_cast<long long>(std::llround(v)); }

// Increments (point number → value) of one column with carried rounding.
// Returns the cumulative integers per table index (relative to the reference).
std::vector<long long> Cumulative(const std::vector<double>& column_um, std::size_t ref, double unit_um) {
  std::vector<long long> s(column_um.size());
  for (std::size_t i = 0; i < column_um.size(); ++i) s[i] = RoundHalfAway((column_um[i] - column_um[ref]) / unit_um);
  return s;
}

}  // namespace

FanucResult WriteFanucPitchTape(const CompensationTable& t, const FanucOptions& o, const std::string& source) {
  std::string why;
  if (!o.IsValid(&why)) throw InputError(source, 0, why.substr(0, why.find(':')), why.substr(why.find(':') + 2));
  ValidateTable(t, source);
  if (t.thermal_tan_beta_um_per_mm != 0)
    throw InputError(source, 0, "thermal", "FANUC pitch compensation has no temperature line; freeze the thermal part");
  const double step = t.UniformSpacingMm();
  if (std::isnan(step) || t.size() < 2)
    throw InputError(source, 0, "--spacing", "FANUC pitch compensation points are equidistant (parameter 3624)");
  const double interval_units_real = step * 1000.0 / o.detection_unit_um;
  const long long interval_units = RoundHalfAway(interval_units_real);
  if (std::abs(interval_units_real - static_cast<double>(interval_units)) > 1e-6)
    throw InputError(source, 0, "--spacing",
                     fmt::format("{} mm is not a whole number of detection units ({} um)", FormatShortest(step),
                                 FormatShortest(o.detection_unit_um)));
  if (!std::isnan(o.max_feed_mm_per_min) && step < o.max_feed_mm_per_min / 7500.0)
    throw InputError(source, 0, "--spacing",
                     fmt::format("FANUC requires interval >= max feedrate/7500 = {:.3f} mm; {} mm is too small",
                                 o.max_feed_mm_per_min / 7500.0, FormatShortest(step)));
  // Reference position must be a table point.
  const double ref = t.reference_position_mm;
  std::size_t r = t.size();
  for (std::size_t i = 0; i < t.size(); ++i)
    if (!std::isnan(ref) && std::abs(t.position_mm[i] - ref) < 1e-6) r = i;
  if (r == t.size())
    throw InputError(source, 0, "--reference-mm",
                     fmt::format("FANUC counts compensation points from the reference position; {} mm is not a table "
                                 "point (the grid is aligned on it unless --start moves it)",
                                 FormatShortest(ref)));

  // Columns as applied (unidirectional: the mean curve; backlash separately).
  const std::vector<double>& fwd = t.forward_um;
  const std::vector<double>& rev = t.reverse_um;

  FanucResult res;
  const int below = static_cast<int>(r);
  // The point numbers are one pool shared by every axis of the control: by default each axis
  // gets its own block of it (A1 from 0, A2 from pool/axes_sharing, ...), so tapes written for
  // X and Y with the defaults can both be loaded; an explicit 3620 places the axis anywhere.
  const bool derived = o.reference_point_number < 0;
  const int axis_block = (o.max_point_number + 1) / o.axes_sharing_pool;
  const int axis_first = (o.axis_number - 1) % o.axes_sharing_pool * axis_block;
  res.reference_point_number = derived ? axis_first + std::max(below - 1, 0) : o.reference_point_number;
  res.min_point_number = std::min(res.reference_point_number, res.reference_point_number - below + 1);
  res.max_point_number = res.reference_point_number + static_cast<int>(t.size() - 1 - r);
  if (res.min_point_number < 0)
    throw InputError(source, 0, "--fanuc-reference-number",
                     fmt::format("{} points below the reference need a reference point number of at least {}", below,
                                 below - 1));
  const int block = res.max_point_number - res.min_point_number + 1;
  if (t.bidirectional) {
    res.reverse_min_point_number = o.reverse_first_number >= 0 ? o.reverse_first_number : res.max_point_number + 1;
    const bool overlap = res.reverse_min_point_number <= res.max_point_number &&
                         res.reverse_min_point_number + block - 1 >= res.min_point_number;
    if (overlap)
      throw InputError(source, 0, "--fanuc-reverse-number",
                       fmt::format("the reverse block {}…{} overlaps the forward block {}…{}", res.reverse_min_point_number,
                                   res.reverse_min_point_number + block - 1, res.min_point_number, res.max_point_number));
  }
  const int last_number = t.bidirectional ? std::max(res.max_point_number, res.reverse_min_point_number + block - 1)
                                          : res.max_point_number;
  if (derived && o.reverse_first_number < 0 && last_number >= axis_first + axis_block)
    throw InputError(source, 0, "--spacing",
                     fmt::format("axis A{} needs point numbers {}…{} ({} per direction), beyond its default block "
                                 "{}…{} ({} numbers shared by {} axes): choose a larger --spacing, or place the axis "
                                 "with --fanuc-reference-number / --fanuc-reverse-number (e.g. a single-axis control)",
                                 o.axis_number, res.min_point_number, last_number, block, axis_first,
                                 axis_first + axis_block - 1, o.max_point_number + 1, o.axes_sharing_pool));
  if (last_number > o.max_point_number)
    throw InputError(source, 0, "--spacing",
                     fmt::format("compensation point numbers up to {} exceed the control's {} ({} points per direction); "
                                 "choose a larger --spacing",
                                 last_number, o.max_point_number, block));

  // Magnification: given, or the smallest that keeps every increment in range.
  auto increments = [&](const std::vector<double>& col, int mag) {
    const auto s = Cumulative(col, r, mag * o.detection_unit_um);
    std::vector<long long> inc(t.size(), 0);  // inc[i] = over [x_{i-1}, x_i], i ≥ 1
    for (std::size_t i = 1; i < t.size(); ++i) inc[i] = s[i] - s[i - 1];
    return std::make_pair(s, inc);
  };
  auto worst = [&](int mag) {
    long long w = 0;
    for (const auto* col : {&fwd, &rev}) {
      if (col == &rev && !t.bidirectional) break;
      for (long long v : increments(*col, mag).second) w = std::max(w, std::llabs(v));
    }
    return w;
  };
  int mag = o.magnification;
  if (mag == 0) {
    for (int m = 1; m <= 100 && mag == 0; ++m)
      if (worst(m) <= o.point_limit) mag = m;
    if (mag == 0)
      throw InputError(source, 0, "--spacing",
                       fmt::format("increments of up to {} detection units per interval do not fit ±{} even at "
                                   "magnification 100; choose a smaller --spacing",
                                   worst(1), o.point_limit));
  } else if (worst(mag) > o.point_limit) {
    throw InputError(source, 0, "--fanuc-magnification",
                     fmt::format("at magnification {} an increment reaches {} units, beyond the per-point limit ±{}", mag,
                                 worst(mag), o.point_limit));
  }
  res.magnification = mag;
  const double unit = mag * o.detection_unit_um;

  const auto [sf, inc_f] = increments(fwd, mag);
  for (std::size_t i = 0; i < t.size(); ++i)
    res.max_rounding_um = std::max(res.max_rounding_um, std::abs(sf[i] * unit - (fwd[i] - fwd[r])));

  const int A = o.axis_number;
  std::string tape = "%\n";
  auto param = [&](int number, long long value) { tape += fmt::format("N{:05d}A{}P{}\n", number, A, value); };
  if (!t.bidirectional) param(1851, RoundHalfAway(t.backlash_um / o.detection_unit_um));
  param(3620, res.reference_point_number);
  param(3621, res.min_point_number);
  param(3622, res.max_point_number);
  param(3623, mag);
  param(3624, interval_units);
  long long ref_rev_units = 0;
  std::vector<long long> inc_r;
  if (t.bidirectional) {
    param(3626, res.reverse_min_point_number);
    ref_rev_units = RoundHalfAway((rev[r] - fwd[r]) / o.detection_unit_um);
    param(3627, ref_rev_units);
    const auto [sr, ir] = increments(rev, mag);
    inc_r = ir;
    for (std::size_t i = 0; i < t.size(); ++i)
      res.max_rounding_um = std::max(res.max_rounding_um,
                                     std::abs(sr[i] * unit + ref_rev_units * o.detection_unit_um - (rev[i] - fwd[r])));
  }
  // Point number of table index i (i ≥ 1): min + (i − 1) when below ≥ 1.
  auto number_of = [&](std::size_t i) { return res.reference_point_number + static_cast<int>(i) - below; };
  auto emit_block = [&](const std::vector<long long>& inc, int offset) {
    for (int n = res.min_point_number; n <= res.max_point_number; ++n) {
      long long v = 0;
      for (std::size_t i = 1; i < t.size(); ++i)
        if (number_of(i) == n) v = inc[i];
      tape += fmt::format("N{}P{}\n", 10000 + n + offset, v);
    }
  };
  emit_block(inc_f, 0);
  if (t.bidirectional) emit_block(inc_r, res.reverse_min_point_number - res.min_point_number);
  tape += "%\n";
  res.tape = std::move(tape);
  return res;
}

CompensationTable ReadFanucPitchTape(std::string_view text, int axis_number, double detection_unit_um,
                                     double reference_position_mm, const std::string& source) {
  static const std::regex kAxisParam(R"(N(\d{1,5})((?:A\d{1,2}P-?\d{1,9})+))");
  static const std::regex kAxisValue(R"(A(\d{1,2})P(-?\d{1,9}))");
  static const std::regex kPitch(R"(N(\d{5})P(-?\d{1,9}))");
  if (!(detection_unit_um > 0)) throw InputError(source, 0, "--detection-unit-um", "must be > 0");
  std::map<int, long long> params;
  std::map<int, long long> pitch;
  std::map<int, int> pitch_line;
  // Integers of at most 9 digits (the regexes bound the digit count), so no overflow.
  auto integer = [&](const std::string& digits, int line, const std::string& field) {
    auto v = ParseInt(digits);
    if (!v || *v > 999999999 || *v < -999999999)
      throw InputError(source, line, field, fmt::format("'{}' is out of range", digits));
    return *v;
  };
  std::map<int, int> param_line;
  int line_no = 0;
  int percent = 0;
  LineCursor cursor(text);
  while (cursor.Next()) {
    line_no = cursor.number();
    std::string line(cursor.line());
    if (!line.empty() && line.back() == ';') line.pop_back();
    if (line.empty()) continue;
    if (line == "%") {
      ++percent;
      continue;
    }
    std::smatch m;
    if (std::regex_match(line, m, kPitch) && integer(m[1], line_no, "N") >= 10000) {
      const int n = static_cast<int>(integer(m[1], line_no, "N")) - 10000;
      if (pitch.count(n)) throw InputError(source, line_no, fmt::format("N{}", m[1].str()), "pitch point given twice");
      pitch[n] = integer(m[2], line_no, fmt::format("N{}", m[1].str()));
      pitch_line[n] = line_no;
    } else if (std::regex_match(line, m, kAxisParam)) {
      const int number = static_cast<int>(integer(m[1], line_no, "N"));
      const std::string values = m[2];
      for (std::sregex_iterator it(values.begin(), values.end(), kAxisValue), e; it != e; ++it)
        if (integer((*it)[1], line_no, "A") == axis_number) {
          params[number] = integer((*it)[2], line_no, fmt::format("{}", number));
          param_line[number] = line_no;
        }
    } else {
      throw InputError(source, line_no, "block", fmt::format("not a parameter or pitch data block: '{}'", line));
    }
  }
  if (percent < 2) throw InputError(source, 0, "%", "a tape begins and ends with a '%' line");
  for (int p : {3620, 3621, 3622, 3623, 3624})
    if (!params.count(p))
      throw InputError(source, 0, fmt::format("{}", p), fmt::format("parameter missing for axis A{}", axis_number));
  const int nref = static_cast<int>(params[3620]), nmin = static_cast<int>(params[3621]),
            nmax = static_cast<int>(params[3622]);
  const long long mag = params[3623];
  const double interval_mm = static_cast<double>(params[3624]) * detection_unit_um / 1000.0;
  if (!(nmin <= nref && nref <= nmax)) throw InputError(source, param_line[3620], "3620", "must lie within 3621…3622");
  if (nmin < 0 || nmax > 89999) throw InputError(source, param_line[3622], "3622", "point numbers must be 0…89999");
  if (params.count(3626) && (params[3626] < 0 || params[3626] + (nmax - nmin) > 89999))
    throw InputError(source, param_line[3626], "3626", "reverse point numbers must be 0…89999");
  if (mag < 1 || mag > 100) throw InputError(source, param_line[3623], "3623", "magnification must be 1…100");
  if (!(interval_mm > 0)) throw InputError(source, param_line[3624], "3624", "interval must be > 0");
  const bool bidirectional = params.count(3626) > 0;
  const double unit = static_cast<double>(mag) * detection_unit_um;
  auto column = [&](int offset, double at_ref_um) {
    // Positions from point nmin − 1 (start of nmin's interval) to nmax;
    // cumulative sum from the reference outwards.
    const auto value = [&](int k) { return pitch.count(k + offset) ? pitch.at(k + offset) : 0LL; };
    std::vector<long long> s(static_cast<std::size_t>(nmax - nmin + 2), 0);
    auto at = [&](int n) -> long long& { return s[static_cast<std::size_t>(n - (nmin - 1))]; };
    for (int n = nref + 1; n <= nmax; ++n) at(n) = at(n - 1) + value(n);
    for (int n = nref - 1; n >= nmin - 1; --n) at(n) = at(n + 1) - value(n + 1);
    std::vector<double> c;
    for (long long v : s) c.push_back(static_cast<double>(v) * unit + at_ref_um);
    return c;
  };
  for (int n = nmin; n <= nmax; ++n)
    if (!pitch.count(n)) throw InputError(source, 0, fmt::format("N{}", 10000 + n), "pitch point missing");
  CompensationTable t;
  t.reference_position_mm = reference_position_mm;
  for (int n = nmin - 1; n <= nmax; ++n) t.position_mm.push_back(reference_position_mm + (n - nref) * interval_mm);
  t.forward_um = column(0, 0.0);
  if (bidirectional) {
    const int rmin = static_cast<int>(params[3626]);
    const double at_ref = params.count(3627) ? static_cast<double>(params[3627]) * detection_unit_um : 0.0;
    for (int n = nmin; n <= nmax; ++n)
      if (!pitch.count(n + rmin - nmin))
        throw InputError(source, 0, fmt::format("N{}", 10000 + n + rmin - nmin), "reverse pitch point missing");
    t.reverse_um = column(rmin - nmin, at_ref);
    t.bidirectional = true;
  } else {
    t.reverse_um = t.forward_um;
    t.bidirectional = false;
    t.backlash_um = params.count(1851) ? static_cast<double>(params[1851]) * detection_unit_um : 0.0;
  }
  // A point's value is the sum of the increments from the reference out to it: blame the line of the
  // last increment added (the forward block's; the reference point has none).
  std::vector<int> point_lines;
  for (int n = nmin - 1; n <= nmax; ++n) {
    const int last_increment = n > nref ? n : n + 1;  // below the reference the sum runs downwards
    point_lines.push_back(n == nref ? 0 : pitch_line.count(last_increment) ? pitch_line.at(last_increment) : 0);
  }
  ValidateReadTable(t, source, point_lines);
  return t;
}

}  // namespace trueaxis::exporter
