#pragma once
// ProgressLine: what a long command is doing, on stderr, without flooding it.
//
//   auto progress = ProgressLine::OnStderr("fit");
//   progress.Step(2, 6, "axis Y: fallback without y_nut");   // "[fit] 33 % axis Y: fallback without y_nut"
//   progress.Note("axis Y fitted");                          // a line that stays
//   progress.Event("measuring X");  // a terminal: the status; a log: a line
//   progress.Finish();
//
// On a terminal the status is one line, rewritten in place ("\r", padded over the previous text),
// and notes are printed above it. When stderr is not a terminal (a log file, a pipe, a test) the
// status is quiet except for a plain line at each tenth of the work done; notes are printed as
// lines. Every line is kept under kMaxWidth characters: a status is shortened, a note wrapped at
// spaces (continuation lines indented), so nothing prints lines of thousands of characters.
#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace trueaxis {

class ProgressLine {
 public:
  static constexpr std::size_t kMaxWidth = 119;
  using Sink = std::function<void(std::string_view text)>;

  // `task` prefixes every status ("[task] "); `terminal`: rewrite the status in place.
  ProgressLine(std::string task, bool terminal, Sink sink);
  // On stderr; a terminal when stderr is one (isatty).
  static ProgressLine OnStderr(std::string task);
  ~ProgressLine();  // Finish()
  ProgressLine(ProgressLine&&) = default;
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  // `done` of `total` steps finished, now doing `what` (total 0: unknown, no percentage).
  void Step(std::size_t done, std::size_t total, std::string_view what);
  // A status without a count (terminal only; quiet otherwise).
  void Status(std::string_view what) { Step(0, 0, what); }
  // A line that stays, e.g. a result or a milestone (wrapped under kMaxWidth).
  void Note(std::string_view line);
  // An event of a log: on a terminal the status (rewritten by the next), otherwise a Note, so a
  // log file keeps every event.
  void Event(std::string_view line) { terminal_ ? Status(line) : Note(line); }
  // Clears the status line (terminal); idempotent.
  void Finish();
  bool terminal() const { return terminal_; }

 private:
  void Clear();
  std::string task_;
  bool terminal_;
  Sink sink_;
  std::size_t shown_ = 0;       // characters of the status on screen (terminal)
  int plain_tenth_ = -1;        // last tenth reported as a plain line
};

// `text` broken at spaces into lines of at most `width` characters (UTF-8 characters); a word
// longer than a line stays whole on its own line. Continuation lines start with the line's own
// leading spaces plus `indent`.
std::vector<std::string> WrapText(std::string_view text, std::size_t width, std::string_view indent = "  ");
// Every line of a multi-line `text` wrapped by WrapText; the result ends with '\n'.
std::string WrapLines(std::string_view text, std::size_t width = ProgressLine::kMaxWidth);
// Characters (not bytes) of UTF-8 text.
std::size_t Utf8Width(std::string_view text);

}  // namespace trueaxis
