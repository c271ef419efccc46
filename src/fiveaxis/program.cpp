// G-code subset and CSV tool-path readers/writers.
#include "trueaxis/fiveaxis/program.hpp"

#include <cctype>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/plausibility.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/core/text_lines.hpp"

namespace trueaxis::fiveaxis {
namespace {

constexpr const char* kSubset = "the supported subset is G0 G1 G20 G21 G90 G91 G93 G94, X Y Z {} C F N, M2 M30";

// Removes (comments) and everything after ';'.
std::string StripComments(std::string_view line, const std::string& source, int number) {
  std::string out;
  bool in_paren = false;
  for (char ch : line) {
    if (in_paren) {
      if (ch == ')') in_paren = false;
      continue;
    }
    if (ch == '(') in_paren = true;
    else if (ch == ';') break;
    else out.push_back(ch);
  }
  if (in_paren) throw InputError(source, number, "(", "comment not closed on this line");
  return out;
}

}  // namespace

ToolPath ParseGcodeProgram(const std::string& text, const std::string& source, const FiveAxisMachine& m) {
  const auto names = m.axis_names();
  const char tilt_letter = names[kTilt][0];
  ToolPath path;
  path.name = source;
  path.feed_field = "F";
  PathVertex current;  // machine starts at the workpiece origin, rotaries at 0
  current.move = MoveKind::kStart;
  path.vertices.push_back(current);
  bool absolute = true, inverse_time = false, ended = false;
  double scale = 1.0;  // mm per program unit
  int motion = -1;     // 0 / 1 once set
  double feed = 0;     // mm/min (G94), 0 = none yet
  LineCursor cursor(text);
  while (cursor.Next()) {
    const int number = cursor.number();
    const std::string line = StripComments(cursor.line(), source, number);
    std::string_view rest = Trim(line);
    if (rest.empty() || rest == "%") continue;
    if (ended) throw InputError(source, number, "", "text after the program end (M2/M30)");
    std::map<char, double> words;
    std::vector<int> g_codes;
    bool has_f = false;
    std::size_t i = 0;
    while (i < rest.size()) {
      if (std::isspace(static_cast<unsigned char>(rest[i]))) { ++i; continue; }
      const char letter = static_cast<char>(std::toupper(static_cast<unsigned char>(rest[i])));
      std::size_t j = i + 1;
      while (j < rest.size() && (std::isdigit(static_cast<unsigned char>(rest[j])) || rest[j] == '.' || rest[j] == '-' ||
                                 rest[j] == '+' || rest[j] == ' '))
        ++j;
      std::string number_text(Trim(rest.substr(i + 1, j - i - 1)));
      std::erase(number_text, ' ');
      const std::string word = std::string(1, letter) + number_text;
      if (!std::isalpha(static_cast<unsigned char>(letter)))
        throw InputError(source, number, std::string(1, rest[i]), "not a G-code word");
      const auto value = ParseDouble(number_text);
      if (!value || !std::isfinite(*value))
        throw InputError(source, number, word, "a word needs a number after its letter");
      i = j;
      if (letter == 'N') continue;
      if (letter == 'G') {
        const int g = static_cast<int>(std::lround(*value));
        if (std::abs(*value - g) > 1e-9 || !(g == 0 || g == 1 || g == 20 || g == 21 || g == 90 || g == 91 || g == 93 || g == 94))
          throw InputError(source, number, word, fmt::format("unknown word: {}", fmt::format(kSubset, tilt_letter)));
        g_codes.push_back(g);
        continue;
      }
      if (letter == 'M') {
        if (*value == 2 || *value == 30) { ended = true; continue; }
        throw InputError(source, number, word, fmt::format("unknown word: {}", fmt::format(kSubset, tilt_letter)));
      }
      const bool axis_letter = letter == 'X' || letter == 'Y' || letter == 'Z' || letter == tilt_letter || letter == 'C';
      if (!axis_letter && letter != 'F')
        throw InputError(source, number, word,
                         fmt::format("unknown word{}: {}",
                                     (letter == 'A' || letter == 'B') ? " for a " + FamilyName(m.kinematics.family) + " machine" : "",
                                     fmt::format(kSubset, tilt_letter)));
      if (words.count(letter)) throw InputError(source, number, word, "word given twice in one block");
      words[letter] = *value;
      if (letter == 'F') has_f = true;
    }
    for (int g : g_codes) {
      if (g == 0 || g == 1) motion = g;
      else if (g == 20) scale = 25.4;
      else if (g == 21) scale = 1.0;
      else if (g == 90) absolute = true;
      else if (g == 91) absolute = false;
      else if (g == 93) inverse_time = true;
      else if (g == 94) { inverse_time = false; feed = 0; }
    }
    double block_f = 0;
    if (has_f) {
      block_f = words['F'];
      if (block_f <= 0) throw InputError(source, number, fmt::format("F{}", block_f), "feed must be positive");
      if (!inverse_time) {
        feed = block_f * scale;
        if (auto why = ImplausibleFeedMmPerMin(feed)) throw InputError(source, number, fmt::format("F{}", block_f), *why);
      }
    }
    bool moves = false;
    PathVertex next = current;
    next.source_line = number;
    for (auto [letter, value] : words) {
      if (letter == 'F') continue;
      moves = true;
      const std::string word = fmt::format("{}{}", letter, FormatShortest(value));
      const bool linear = letter == 'X' || letter == 'Y' || letter == 'Z';
      const double v = linear ? value * scale : value;
      if (linear) {
        if (auto why = ImplausiblePositionMm(v)) throw InputError(source, number, word, *why);
        const int k = letter - 'X';
        next.tip_mm[k] = absolute ? v : next.tip_mm[k] + v;
      } else if (letter == 'C') {
        next.rot_deg = absolute ? v : next.rot_deg + v;
      } else {
        next.tilt_deg = absolute ? v : next.tilt_deg + v;
      }
    }
    if (!moves) continue;
    if (motion < 0) throw InputError(source, number, "G0/G1", "a move before any G0 or G1");
    if (motion == 0) {
      next.move = MoveKind::kRapid;
    } else if (inverse_time) {
      if (!has_f) throw InputError(source, number, "F", "missing feed: G93 (inverse time) needs F on every G1 block");
      next.move = MoveKind::kInverseTime;
      next.duration_s = 60.0 / block_f;
    } else {
      if (feed <= 0) throw InputError(source, number, "F", "missing feed: a G1 move needs a feed (F word) first");
      next.move = MoveKind::kFeed;
      next.feed_mm_per_min = feed;
    }
    if (path.vertices.size() == 1 && next.move == MoveKind::kRapid) {
      // The first G0 positions the machine: the path starts there.
      next.move = MoveKind::kStart;
      path.vertices.front() = next;
    } else {
      path.vertices.push_back(next);
    }
    current = next;
  }
  if (path.vertices.size() < 2) throw InputError(source, cursor.number(), "", "the program has no move after its start point");
  CheckAxisRanges(path, m, source);
  return path;
}

ToolPath ParseCsvProgram(const std::string& text, const std::string& source, const FiveAxisMachine& m,
                         double default_feed) {
  const auto names = m.axis_names();
  const Kinematics kin(m.kinematics);
  const std::string tilt_column = names[kTilt] == "A" ? "a_deg" : "b_deg";
  ToolPath path;
  path.name = source;
  const std::string canonical = CanonicalCsv(text);
  LineCursor cursor(canonical);
  std::vector<std::string> header;
  std::map<std::string, int> column;
  Kinematics::RotaryAngles prev;
  while (cursor.Next()) {
    if (cursor.line().empty() || cursor.line().front() == '#') continue;
    const auto fields = SplitCsvFields(cursor.line());
    const int number = cursor.number();
    if (header.empty()) {
      for (std::size_t c = 0; c < fields.size(); ++c) {
        header.emplace_back(fields[c]);
        column[header.back()] = static_cast<int>(c);
      }
      for (const char* need : {"x_mm", "y_mm", "z_mm"})
        if (!column.count(need)) throw InputError(source, number, need, "missing column (header: x_mm,y_mm,z_mm,i,j,k or " + tilt_column + ",c_deg)");
      for (const auto& h : header)
        if (!(h == "x_mm" || h == "y_mm" || h == "z_mm" || h == "i" || h == "j" || h == "k" || h == tilt_column ||
              h == "c_deg" || h == "feed_mm_per_min" || h == "duration_s"))
          throw InputError(source, number, h, "unknown column for a " + FamilyName(m.kinematics.family) + " machine");
      const bool vector = column.count("i") && column.count("j") && column.count("k");
      const bool angles = column.count(tilt_column) && column.count("c_deg");
      if (vector == angles)
        throw InputError(source, number, "header", "give the tool axis as i,j,k or the angles " + tilt_column + ",c_deg (one of them)");
      path.feed_field = column.count("duration_s") ? "duration_s" : column.count("feed_mm_per_min") ? "feed_mm_per_min" : "--feed";
      continue;
    }
    if (fields.size() != header.size())
      throw InputError(source, number, "", fmt::format("{} fields, the header has {}", fields.size(), header.size()));
    auto value = [&](const std::string& name) {
      const auto v = ParseDouble(fields[column.at(name)]);
      if (!v || !std::isfinite(*v)) throw InputError(source, number, name, "'" + std::string(fields[column.at(name)]) + "' is not a number");
      return *v;
    };
    PathVertex v;
    v.source_line = number;
    v.tip_mm = {value("x_mm"), value("y_mm"), value("z_mm")};
    for (int k = 0; k < 3; ++k)
      if (auto why = ImplausiblePositionMm(v.tip_mm[k])) throw InputError(source, number, header[k], *why);
    if (column.count("i")) {
      const Eigen::Vector3d axis(value("i"), value("j"), value("k"));
      if (axis.norm() < 1e-9) throw InputError(source, number, "i", "the tool axis i,j,k is zero");
      prev = kin.AnglesFor(axis, prev);
      v.tilt_deg = prev.tilt_deg;
      v.rot_deg = prev.rot_deg;
    } else {
      v.tilt_deg = value(tilt_column);
      v.rot_deg = value("c_deg");
    }
    if (path.vertices.empty()) {
      v.move = MoveKind::kStart;
    } else if (column.count("duration_s")) {
      v.move = MoveKind::kInverseTime;
      v.duration_s = value("duration_s");
      if (v.duration_s <= 0) throw InputError(source, number, "duration_s", "must be positive");
    } else {
      v.move = MoveKind::kFeed;
      const bool has_column = column.count("feed_mm_per_min") > 0;
      v.feed_mm_per_min = has_column ? value("feed_mm_per_min") : default_feed;
      if (!has_column && v.feed_mm_per_min == 0)
        throw InputError(source, number, "feed_mm_per_min", "missing feed: add a feed_mm_per_min column or give --feed");
      if (auto why = ImplausibleFeedMmPerMin(v.feed_mm_per_min))
        throw InputError(has_column ? source : "command line", has_column ? number : 0,
                         has_column ? "feed_mm_per_min" : "--feed", *why);
    }
    path.vertices.push_back(v);
  }
  if (path.vertices.size() < 2) throw InputError(source, cursor.number(), "", "a tool path needs at least two points");
  CheckAxisRanges(path, m, source);
  return path;
}

ToolPath ReadProgramFile(const std::string& path, const FiveAxisMachine& m, double default_feed) {
  const std::string text = ReadTextFile(path);
  const bool csv = path.size() >= 4 && path.substr(path.size() - 4) == ".csv";
  return csv ? ParseCsvProgram(text, path, m, default_feed) : ParseGcodeProgram(text, path, m);
}

std::string WriteGcodeProgram(const ToolPath& path, const FiveAxisMachine& m, const std::string& header_comment) {
  const auto names = m.axis_names();
  std::string out = "%\n";
  out += "(" + header_comment + ")\n";
  out += "G21 G90\n";
  MoveKind mode = MoveKind::kStart;
  for (const PathVertex& v : path.vertices) {
    std::string block;
    if (v.move == MoveKind::kStart || v.move == MoveKind::kRapid) {
      block = "G0";
    } else if (v.move == MoveKind::kInverseTime) {
      block = mode == MoveKind::kInverseTime ? "G1" : "G93 G1";
    } else {
      block = mode == MoveKind::kInverseTime ? "G94 G1" : "G1";
    }
    block += fmt::format(" X{:.6f} Y{:.6f} Z{:.6f} {}{:.6f} C{:.6f}", v.tip_mm.x(), v.tip_mm.y(), v.tip_mm.z(),
                         names[kTilt], v.tilt_deg, v.rot_deg);
    if (v.move == MoveKind::kInverseTime) block += fmt::format(" F{:.9g}", 60.0 / v.duration_s);
    if (v.move == MoveKind::kFeed) block += fmt::format(" F{:.6g}", v.feed_mm_per_min);
    out += block + "\n";
    if (v.move != MoveKind::kStart && v.move != MoveKind::kRapid) mode = v.move;
  }
  out += "M30\n%\n";
  return out;
}

std::string WriteCsvProgram(const ToolPath& path, const FiveAxisMachine& m) {
  const auto names = m.axis_names();
  bool timed = false;
  for (const auto& v : path.vertices) timed |= v.move == MoveKind::kInverseTime;
  std::string out = fmt::format("x_mm,y_mm,z_mm,{}_deg,c_deg,{}\n", names[kTilt] == "A" ? "a" : "b",
                                timed ? "duration_s" : "feed_mm_per_min");
  for (const PathVertex& v : path.vertices)
    out += fmt::format("{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.9g}\n", v.tip_mm.x(), v.tip_mm.y(), v.tip_mm.z(), v.tilt_deg,
                       v.rot_deg, timed ? (v.move == MoveKind::kStart ? 1.0 : v.duration_s) : v.feed_mm_per_min);
  return out;
}

}  // namespace trueaxis::fiveaxis
