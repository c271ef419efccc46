#include "trueaxis/core/text_lines.hpp"

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

std::vector<std::string_view> SplitCsvFields(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  while (true) {
    const auto pos = line.find(',', start);
    out.push_back(Trim(line.substr(start, pos == std::string_view::npos ? std::string_view::npos : pos - start)));
    if (pos == std::string_view::npos) break;
    start = pos + 1;
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

}  // namespace trueaxis
