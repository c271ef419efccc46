#pragma once
// HtmlPage: builds one self-contained HTML file (inline CSS, inline SVG, no
// scripts, no external resources) from headings, paragraphs, tables and
// SvgCharts, so a report can be mailed or archived as a single file.
//
//   report::HtmlPage page("ISO 230-2 evaluation — X axis");
//   page.AddHeading("Setup");
//   page.AddKeyValueTable({{"machine", "VMC-850"}, {"axis", "X"}});
//   report::HtmlTable t({"target (mm)", "x̄↑ (µm)"});
//   t.AddRow({"0", "1.2"});
//   page.AddTable(t);
//   page.AddChart(chart);
//   page.Save("report.html");   // atomic write; InputError names the path on failure
//
// Every text argument is HTML-escaped; only AddRawHtml inserts markup as is.
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "trueaxis/report/svg_chart.hpp"

namespace trueaxis::report {

// Escapes & < > " ' for text and attribute content.
std::string EscapeHtml(std::string_view text);

class HtmlTable {
 public:
  explicit HtmlTable(std::vector<std::string> header, std::string caption = "");
  // Throws std::invalid_argument when the row width differs from the header.
  HtmlTable& AddRow(std::vector<std::string> cells);
  // Cells that parse as numbers are right-aligned automatically.
  std::string Render() const;
  std::size_t row_count() const { return rows_.size(); }

 private:
  std::vector<std::string> header_;
  std::string caption_;
  std::vector<std::vector<std::string>> rows_;
};

class HtmlPage {
 public:
  explicit HtmlPage(std::string title);

  HtmlPage& AddHeading(std::string_view text, int level = 2);  // level 1..4
  HtmlPage& AddParagraph(std::string_view text);
  // A muted note, e.g. "forward = approach in + direction".
  HtmlPage& AddNote(std::string_view text);
  HtmlPage& AddTable(const HtmlTable& table);
  HtmlPage& AddKeyValueTable(const std::vector<std::pair<std::string, std::string>>& rows,
                             std::string caption = "");
  HtmlPage& AddChart(const SvgChart& chart);
  // A folded section (<details>): the blocks added until EndDetails() show when the reader opens
  // it; `open`: unfolded at first. A section left open is closed by Render().
  HtmlPage& BeginDetails(std::string_view summary, bool open = false);
  HtmlPage& EndDetails();
  // Markup inserted verbatim (caller is responsible for escaping).
  HtmlPage& AddRawHtml(std::string html);

  std::string Render() const;
  void Save(const std::string& path) const;

 private:
  std::string title_;
  std::vector<std::string> blocks_;
  int open_details_ = 0;
};

}  // namespace trueaxis::report
