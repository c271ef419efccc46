#include "trueaxis/core/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include <fmt/format.h>

namespace trueaxis {
namespace {

bool Continuation(char c) { return (static_cast<unsigned char>(c) & 0xC0) == 0x80; }

// The first `width` characters of `text`, "…" in the last place when it was longer.
std::string Shorten(std::string_view text, std::size_t width) {
  if (Utf8Width(text) <= width) return std::string(text);
  std::size_t cut = 0;
  for (std::size_t n = 0; cut < text.size() && n + 1 < width; ++n) {
    ++cut;
    while (cut < text.size() && Continuation(text[cut])) ++cut;
  }
  return std::string(text.substr(0, cut)) + "…";
}

}  // namespace

std::size_t Utf8Width(std::string_view text) {
  return static_cast<std::size_t>(std::count_if(text.begin(), text.end(), [](char c) { return !Continuation(c); }));
}

std::vector<std::string> WrapText(std::string_view text, std::size_t width, std::string_view indent) {
  std::vector<std::string> lines;
  std::string line;
  std::size_t i = 0;
  // Leading spaces of the text are kept (an indented block stays indented).
  while (i < text.size() && text[i] == ' ') line += text[i++];
  const std::size_t lead = line.size();
  // Continuation lines: indented past the line's own indent.
  const std::string continuation = line + std::string(indent);
  while (i < text.size()) {
    std::size_t j = i;
    while (j < text.size() && text[j] != ' ') ++j;
    const std::string_view word = text.substr(i, j - i);
    if (!word.empty()) {
      const bool fresh = line.size() == (lines.empty() ? lead : continuation.size());
      if (!fresh && Utf8Width(line) + 1 + Utf8Width(word) > width) {
        lines.push_back(std::move(line));
        line = continuation;
      } else if (!fresh) {
        line += ' ';
      }
      line += word;
    }
    i = j;
    while (i < text.size() && text[i] == ' ') ++i;
  }
  lines.push_back(std::move(line));
  return lines;
}

ProgressLine::ProgressLine(std::string task, bool terminal, Sink sink)
    : task_(std::move(task)), terminal_(terminal), sink_(std::move(sink)) {}

ProgressLine ProgressLine::OnStderr(std::string task) {
  return ProgressLine(std::move(task), isatty(STDERR_FILENO) == 1, [](std::string_view s) {
    std::fwrite(s.data(), 1, s.size(), stderr);
    std::fflush(stderr);
  });
}

ProgressLine::~ProgressLine() {
  if (sink_) Finish();
}

void ProgressLine::Step(std::size_t done, std::size_t total, std::string_view what) {
  if (!sink_) return;
  const bool counted = total > 0;
  const std::size_t percent = counted ? std::min<std::size_t>(100, done * 100 / total) : 0;
  std::string text = task_.empty() ? std::string() : "[" + task_ + "] ";
  if (counted) text += fmt::format("{:3d} % ", percent);
  text += what;
  if (terminal_) {
    text = Shorten(text, kMaxWidth);
    const std::size_t width = Utf8Width(text);
    std::string out = "\r" + text;
    if (width < shown_) out += std::string(shown_ - width, ' ');  // erase the rest of the longer status
    shown_ = width;
    sink_(out);
    return;
  }
  // Not a terminal: one plain line per tenth of the work, nothing for uncounted statuses.
  if (!counted) return;
  const int tenth = static_cast<int>(percent / 10);
  if (tenth == plain_tenth_) return;
  plain_tenth_ = tenth;
  sink_(Shorten(text, kMaxWidth) + "\n");
}

void ProgressLine::Clear() {
  if (terminal_ && shown_ > 0) {
    sink_("\r" + std::string(shown_, ' ') + "\r");
    shown_ = 0;
  }
}

std::string WrapLines(std::string_view text, std::size_t width) {
  std::string out;
  std::size_t start = 0;
  while (start < text.size() || (start == 0 && text.empty())) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    for (const auto& l : WrapText(text.substr(start, end - start), width)) out += l + "\n";
    start = end + 1;
  }
  return out;
}

void ProgressLine::Note(std::string_view line) {
  if (!sink_) return;
  Clear();
  sink_(WrapLines(line, kMaxWidth));
}

void ProgressLine::Finish() {
  if (sink_) Clear();
}

}  // namespace trueaxis
