#include "trueaxis/core/text_lines.hpp"

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"

namespace trueaxis {

bool LineCursor::Next() {
  if (pos_ > text_.size()) return false;
  const auto nl = text_.find('\n', pos_);
  std::string_view raw = text_.substr(pos_, nl == std::string_view::npos ? std::string_view::npos : nl - pos_);
  pos_ = (nl == std::string_view::npos) ? text_.size() + 1 : nl + 1;
  ++number_;
  if (number_ == 1 && raw.size() >= 3 && raw.substr(0, 3) == "\xEF\xBB\xBF") raw.remove_prefix(3);
  line_ = Trim(raw);
  return true;
}

std::string CsvField(std::string_view field) {
  if (field.find_first_of(",\"\n\r") == std::string_view::npos) return std::string(field);
  std::string out = "\"";
  for (char c : field) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::vector<std::string_view> SplitCsvFields(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  while (true) {
    // RFC 4180: a field in double quotes may hold commas; the quotes are not part of the value.
    std::size_t scan = start;
    while (scan < line.size() && (line[scan] == ' ' || line[scan] == '\t')) ++scan;
    if (scan < line.size() && line[scan] == '"') {
      std::size_t close = scan + 1;
      while (close < line.size()) {
        if (line[close] == '"' && close + 1 < line.size() && line[close + 1] == '"') close += 2;  // "" inside
        else if (line[close] == '"') break;
        else ++close;
      }
      if (close < line.size()) {
        const auto pos = line.find(',', close);
        out.push_back(line.substr(scan + 1, close - scan - 1));
        if (pos == std::string_view::npos) break;
        start = pos + 1;
        continue;
      }
    }
    const auto pos = line.find(',', start);
    out.push_back(Trim(line.substr(start, pos == std::string_view::npos ? std::string_view::npos : pos - start)));
    if (pos == std::string_view::npos) break;
    start = pos + 1;
  }
  return out;
}

std::string CanonicalCsv(std::string_view text) {
  // The header (first line that is neither empty nor a comment) tells the separator.
  LineCursor cursor(text);
  bool semicolons = false;
  while (cursor.Next()) {
    const auto line = cursor.line();
    if (line.empty() || line[0] == '#') continue;
    semicolons = line.find(';') != std::string_view::npos && line.find(',') == std::string_view::npos;
    break;
  }
  std::string out(text);
  if (!semicolons) return out;
  // A German/Chinese-locale Excel export: ';' between fields, ',' as the decimal mark.
  bool comment = false, line_start = true;
  for (auto& c : out) {
    if (line_start) comment = (c == '#');
    if (!comment && c != ' ' && c != '\t') line_start = false;
    if (c == '\n') {
      line_start = true;
      comment = false;
      continue;
    }
    if (comment) continue;
    if (c == ',') c = '.';
    else if (c == ';') c = ',';
  }
  return out;
}

std::optional<std::pair<std::string_view, std::string_view>> ParseMetadataComment(std::string_view line) {
  line = Trim(line);
  if (line.empty() || line.front() != '#') return std::nullopt;
  const auto body = Trim(line.substr(1));
  const auto colon = body.find(':');
  if (colon == std::string_view::npos || colon == 0) return std::nullopt;
  return std::make_pair(Trim(body.substr(0, colon)), Trim(body.substr(colon + 1)));
}

void RefuseEmptyHeaderField(const std::vector<std::string_view>& header, const std::string& source, int line) {
  for (std::size_t c = 0; c < header.size(); ++c)
    if (header[c].empty())
      throw InputError(source, line, "header",
                       fmt::format("column {} of {} has no name (an empty field: ',,' or a comma at the end?)", c + 1,
                                   header.size()));
}

}  // namespace trueaxis
