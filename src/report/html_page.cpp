#include "trueaxis/report/html_page.hpp"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/text_file.hpp"

namespace trueaxis::report {
namespace {

// Plain print-friendly style; no external fonts or scripts.
constexpr const char* kStyle = R"(
body { font-family: -apple-system, "Segoe UI", Roboto, "Helvetica Neue", Arial, sans-serif; color: #222;
       max-width: 1000px; margin: 24px auto; padding: 0 16px; line-height: 1.45; }
h1 { font-size: 1.6em; border-bottom: 2px solid #0072B2; padding-bottom: 4px; }
h2 { font-size: 1.25em; margin-top: 1.6em; color: #0b3d61; }
h3 { font-size: 1.05em; }
table { border-collapse: collapse; margin: 8px 0 16px 0; font-size: 0.9em; }
caption { text-align: left; font-weight: bold; padding: 4px 0; }
th, td { border: 1px solid #ccc; padding: 3px 8px; }
th { background: #eef3f8; text-align: left; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
tr:nth-child(even) td { background: #fafafa; }
.note { color: #666; font-size: 0.9em; }
pre { white-space: pre-wrap; overflow-wrap: anywhere; font-size: 0.85em; }  /* fit text stays on the page */
details { margin: 8px 0 16px 0; }
summary { cursor: pointer; color: #0b3d61; font-weight: bold; }
svg.chart { display: block; margin: 8px 0 16px 0; border: 1px solid #eee; max-width: 100%; height: auto; }
@media print { body { max-width: none; } svg.chart { page-break-inside: avoid; } }
)";

bool LooksNumeric(const std::string& s) {
  if (s.empty()) return false;
  if (ParseDouble(s)) return true;
  // "12.3 µm" or "+0.5 mm": a number and at most one unit word read best right-aligned;
  // "5 from 15 to 55.8 mm" is prose and stays left-aligned.
  const auto sp = s.find(' ');
  if (sp == std::string::npos || s.find(' ', sp + 1) != std::string::npos) return false;
  return ParseDouble(s.substr(0, sp)).has_value();
}

}  // namespace

std::string EscapeHtml(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

HtmlTable::HtmlTable(std::vector<std::string> header, std::string caption)
    : header_(std::move(header)), caption_(std::move(caption)) {
  if (header_.empty()) throw std::invalid_argument("HtmlTable needs at least one column");
}

HtmlTable& HtmlTable::AddRow(std::vector<std::string> cells) {
  if (cells.size() != header_.size())
    throw std::invalid_argument(
        fmt::format("HtmlTable row has {} cells, the header has {} columns", cells.size(), header_.size()));
  rows_.push_back(std::move(cells));
  return *this;
}

std::string HtmlTable::Render() const {
  std::string out = "<table>\n";
  if (!caption_.empty()) out += "<caption>" + EscapeHtml(caption_) + "</caption>\n";
  out += "<thead><tr>";
  for (const auto& h : header_) out += "<th>" + EscapeHtml(h) + "</th>";
  out += "</tr></thead>\n<tbody>\n";
  for (const auto& row : rows_) {
    out += "<tr>";
    for (const auto& c : row) out += (LooksNumeric(c) ? "<td class=\"num\">" : "<td>") + EscapeHtml(c) + "</td>";
    out += "</tr>\n";
  }
  out += "</tbody></table>\n";
  return out;
}

HtmlPage::HtmlPage(std::string title) : title_(std::move(title)) {}

HtmlPage& HtmlPage::AddHeading(std::string_view text, int level) {
  level = std::clamp(level, 1, 4);
  blocks_.push_back(fmt::format("<h{0}>{1}</h{0}>\n", level, EscapeHtml(text)));
  return *this;
}

HtmlPage& HtmlPage::AddParagraph(std::string_view text) {
  blocks_.push_back("<p>" + EscapeHtml(text) + "</p>\n");
  return *this;
}

HtmlPage& HtmlPage::AddNote(std::string_view text) {
  blocks_.push_back("<p class=\"note\">" + EscapeHtml(text) + "</p>\n");
  return *this;
}

HtmlPage& HtmlPage::AddTable(const HtmlTable& table) {
  blocks_.push_back(table.Render());
  return *this;
}

HtmlPage& HtmlPage::AddKeyValueTable(const std::vector<std::pair<std::string, std::string>>& rows,
                                     std::string caption) {
  HtmlTable t({"item", "value"}, std::move(caption));
  for (const auto& [k, v] : rows) t.AddRow({k, v});
  return AddTable(t);
}

HtmlPage& HtmlPage::AddChart(const SvgChart& chart) {
  blocks_.push_back(chart.Render());
  return *this;
}

HtmlPage& HtmlPage::BeginDetails(std::string_view summary, bool open) {
  blocks_.push_back(std::string(open ? "<details open>" : "<details>") + "<summary>" + EscapeHtml(summary) +
                    "</summary>\n");
  ++open_details_;
  return *this;
}

HtmlPage& HtmlPage::EndDetails() {
  if (open_details_ > 0) {
    blocks_.push_back("</details>\n");
    --open_details_;
  }
  return *this;
}

HtmlPage& HtmlPage::AddRawHtml(std::string html) {
  blocks_.push_back(std::move(html));
  return *this;
}

std::string HtmlPage::Render() const {
  std::string out = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  out += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  out += "<title>" + EscapeHtml(title_) + "</title>\n<style>" + kStyle + "</style>\n</head>\n<body>\n";
  out += "<h1>" + EscapeHtml(title_) + "</h1>\n";
  for (const auto& b : blocks_) out += b;
  for (int i = 0; i < open_details_; ++i) out += "</details>\n";
  out += "</body>\n</html>\n";
  return out;
}

void HtmlPage::Save(const std::string& path) const { WriteTextFile(path, Render()); }

}  // namespace trueaxis::report
