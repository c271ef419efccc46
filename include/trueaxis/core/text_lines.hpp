#pragma once
// Line-by-line reading shared by every text reader (measurement CSV, ecmc
// .dat, thermal series, calibration sessions, controller tables), so they
// agree on line numbers, line endings and the UTF-8 byte-order mark.
//
// LineCursor yields each line trimmed of blanks, "\r" and (on line 1) a BOM,
// numbered from 1. A text ending in "\n" has one more, empty, last line, so
// an error "after the last line" points one past it, as editors show it.
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace trueaxis {

class LineCursor {
 public:
  explicit LineCursor(std::string_view text) : text_(text) {}

  // Moves to the next line; false when there is none.
  bool Next();
  std::string_view line() const { return line_; }
  int number() const { return number_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::string_view line_;
  int number_ = 0;
};

// Splits a comma-separated line into its fields, each trimmed. A field in
// double quotes (RFC 4180, as spreadsheets write them) may hold commas; the
// view excludes the quotes.
std::vector<std::string_view> SplitCsvFields(std::string_view line);

// One field for a CSV file, quoted as RFC 4180 says when it holds a comma, a
// double quote (doubled inside), or a line break ('\n' or '\r'); as is otherwise.
// The inverse of SplitCsvFields for every writer (history export, `history query`).
std::string CsvField(std::string_view field);

// Throws InputError(source, line, "header", ...) when a field of a CSV header row is empty (",," or a
// trailing comma): a column without a name cannot be told apart or written back (`_c,_status`). Every
// reader of a header of named columns (calibration session, readings, thermal series) refuses it alike.
void RefuseEmptyHeaderField(const std::vector<std::string_view>& header, const std::string& source, int line);

// The CSV text in trueaxis's canonical dialect: a file whose header is
// separated by ';' (a German or Chinese locale's Excel export) has its ';'
// turned into ',' and its decimal commas into points, comment lines untouched.
// Any other text is returned unchanged.
std::string CanonicalCsv(std::string_view text);

// "# key: value" metadata comment → (key, value), both trimmed; nullopt for a
// line that is not a comment or a comment without "key:".
std::optional<std::pair<std::string_view, std::string_view>> ParseMetadataComment(std::string_view line);

}  // namespace trueaxis
