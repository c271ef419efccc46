#pragma once
// Reads the cell values of an Excel workbook (.xlsx, Office Open XML) so recordings shipped as
// spreadsheets can be read like CSV: a ZIP container (minizip) of XML parts (pugixml) —
// xl/workbook.xml lists the sheets, xl/_rels/workbook.xml.rels where each sheet's part is,
// xl/sharedStrings.xml the shared strings. Cell values come as the text Excel stored: numbers in
// full precision, shared and inline strings, booleans as 0/1, formulas by their cached value.
// Styles (dates shown as dates) are not applied: a date cell reads as its serial number.
#include <string>
#include <vector>

namespace trueaxis {

struct WorkbookSheet {
  std::string name;
  // One entry per spreadsheet row from row 1 to the last row with a value (rows Excel left out
  // are empty), one string per column from A to the row's last cell ("" for an empty cell).
  std::vector<std::vector<std::string>> rows;

  // The sheet as CSV text: line k is spreadsheet row k, fields quoted where needed (RFC 4180),
  // so a CSV reader's line numbers are the spreadsheet's row numbers.
  std::string ToCsv() const;
};

// True when the file starts with a ZIP signature (what an .xlsx is).
bool IsZipFile(const std::string& path);

// Every worksheet in workbook order. InputError naming the file (and the part) when it is not a
// readable workbook.
std::vector<WorkbookSheet> ReadXlsxWorkbook(const std::string& path);

}  // namespace trueaxis
