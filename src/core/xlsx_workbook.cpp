#include "trueaxis/core/xlsx_workbook.hpp"

#include <minizip/unzip.h>

#include <cstdio>
#include <fstream>
#include <map>
#include <memory>

#include <fmt/format.h>
#include <pugixml.hpp>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis {
namespace {

constexpr std::size_t kMaxPartBytes = 512u << 20;  // a sheet larger than this is no recording

struct ZipCloser {
  void operator()(void* z) const { unzClose(z); }
};
using Zip = std::unique_ptr<void, ZipCloser>;

// The uncompressed bytes of one part; nullopt-like empty + false when absent.
bool ReadPart(unzFile zip, const std::string& path, const std::string& part, std::string* out) {
  if (unzLocateFile(zip, part.c_str(), 0) != UNZ_OK) return false;
  unz_file_info64 info{};
  if (unzGetCurrentFileInfo64(zip, &info, nullptr, 0, nullptr, 0, nullptr, 0) != UNZ_OK)
    throw InputError(path, 0, part, "unreadable entry in the workbook");
  if (info.uncompressed_size > kMaxPartBytes)
    throw InputError(path, 0, part, fmt::format("{} bytes uncompressed: too large", info.uncompressed_size));
  if (unzOpenCurrentFile(zip) != UNZ_OK) throw InputError(path, 0, part, "cannot open the entry in the workbook");
  out->assign(static_cast<std::size_t>(info.uncompressed_size), '\0');
  const int got = out->empty() ? 0 : unzReadCurrentFile(zip, out->data(), static_cast<unsigned>(out->size()));
  const int closed = unzCloseCurrentFile(zip);
  if (got != static_cast<int>(out->size()) || closed != UNZ_OK)
    throw InputError(path, 0, part, "the workbook entry is damaged (CRC or length mismatch)");
  return true;
}

pugi::xml_document ParseXml(const std::string& path, const std::string& part, const std::string& bytes) {
  pugi::xml_document doc;
  const pugi::xml_parse_result r = doc.load_buffer(bytes.data(), bytes.size());
  if (!r) throw InputError(path, 0, part, fmt::format("not well-formed XML at byte {}: {}", r.offset, r.description()));
  return doc;
}

// "BC12" -> column index 54 (0-based); -1 when the reference has no letters.
int ColumnOf(const char* ref) {
  int col = 0, letters = 0;
  for (const char* p = ref; *p >= 'A' && *p <= 'Z'; ++p, ++letters) col = col * 26 + (*p - 'A' + 1);
  return letters ? col - 1 : -1;
}

// Text of a string item (<si> or <is>): plain <t> or rich-text runs <r><t>.
std::string ItemText(const pugi::xml_node& item) {
  std::string text = item.child("t").text().get();
  for (const auto& run : item.children("r")) text += run.child("t").text().get();
  return text;
}

// "xl/worksheets/sheet1.xml" from a relationship target relative to xl/ (or absolute "/xl/...").
std::string PartPath(const std::string& target) {
  if (!target.empty() && target.front() == '/') return target.substr(1);
  return "xl/" + target;
}

}  // namespace

std::string WorkbookSheet::ToCsv() const {
  std::string out;
  for (const auto& row : rows) {
    for (std::size_t c = 0; c < row.size(); ++c) {
      if (c) out += ',';
      const std::string& v = row[c];
      if (v.find_first_of(",\"\r\n;") == std::string::npos) {
        out += v;
      } else {
        out += '"';
        for (char ch : v) out += ch == '"' ? std::string("\"\"") : std::string(1, ch);
        out += '"';
      }
    }
    out += '\n';
  }
  return out;
}

bool IsZipFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char sig[4] = {};
  in.read(sig, 4);
  return in.gcount() == 4 && sig[0] == 'P' && sig[1] == 'K' && sig[2] == 3 && sig[3] == 4;
}

std::vector<WorkbookSheet> ReadXlsxWorkbook(const std::string& path) {
  Zip zip(unzOpen64(path.c_str()));
  if (!zip) throw InputError(path, 0, "", "not a readable .xlsx workbook (no ZIP directory)");
  std::string bytes;
  if (!ReadPart(zip.get(), path, "xl/workbook.xml", &bytes))
    throw InputError(path, 0, "xl/workbook.xml", "missing: a ZIP file but not an Excel workbook");
  const pugi::xml_document workbook = ParseXml(path, "xl/workbook.xml", bytes);

  std::map<std::string, std::string> targets;  // relationship id -> part path
  if (ReadPart(zip.get(), path, "xl/_rels/workbook.xml.rels", &bytes)) {
    const pugi::xml_document rels = ParseXml(path, "xl/_rels/workbook.xml.rels", bytes);
    for (const auto& rel : rels.child("Relationships").children("Relationship"))
      targets[rel.attribute("Id").value()] = PartPath(rel.attribute("Target").value());
  }
  std::vector<std::string> shared;
  if (ReadPart(zip.get(), path, "xl/sharedStrings.xml", &bytes)) {
    const pugi::xml_document sst = ParseXml(path, "xl/sharedStrings.xml", bytes);
    for (const auto& si : sst.child("sst").children("si")) shared.push_back(ItemText(si));
  }

  std::vector<WorkbookSheet> sheets;
  int index = 0;
  for (const auto& sheet : workbook.child("workbook").child("sheets").children("sheet")) {
    ++index;
    WorkbookSheet out;
    out.name = sheet.attribute("name").value();
    const std::string rid = sheet.attribute("r:id").value();
    std::string part = targets.count(rid) ? targets[rid] : fmt::format("xl/worksheets/sheet{}.xml", index);
    if (!ReadPart(zip.get(), path, part, &bytes))
      throw InputError(path, 0, part, fmt::format("sheet '{}' is listed but its part is missing", out.name));
    const pugi::xml_document ws = ParseXml(path, part, bytes);
    for (const auto& row : ws.child("worksheet").child("sheetData").children("row")) {
      const long number = row.attribute("r").as_int(static_cast<int>(out.rows.size()) + 1);
      if (number < 1 || number > 1048576)
        throw InputError(path, 0, part, fmt::format("row number {} is outside a worksheet", number));
      if (static_cast<std::size_t>(number) < out.rows.size() + 1)
        throw InputError(path, static_cast<int>(number), out.name, "rows out of order in the sheet");
      out.rows.resize(static_cast<std::size_t>(number));
      std::vector<std::string>& cells = out.rows.back();
      for (const auto& c : row.children("c")) {
        int col = ColumnOf(c.attribute("r").value());
        if (col < 0) col = static_cast<int>(cells.size());
        if (col > 16383) throw InputError(path, static_cast<int>(number), c.attribute("r").value(), "column outside a worksheet");
        if (static_cast<std::size_t>(col) >= cells.size()) cells.resize(static_cast<std::size_t>(col) + 1);
        const std::string type = c.attribute("t").value();
        std::string value;
        if (type == "s") {
          const long k = c.child("v").text().as_llong(-1);
          if (k < 0 || static_cast<std::size_t>(k) >= shared.size())
            throw InputError(path, static_cast<int>(number), c.attribute("r").value(),
                             fmt::format("shared string {} does not exist ({} in the workbook)", k, shared.size()));
          value = shared[static_cast<std::size_t>(k)];
        } else if (type == "inlineStr") {
          value = ItemText(c.child("is"));
        } else {
          value = c.child("v").text().get();  // number, boolean (0/1), formula's cached value, error text
        }
        cells[static_cast<std::size_t>(col)] = std::move(value);
      }
    }
    sheets.push_back(std::move(out));
  }
  if (sheets.empty()) throw InputError(path, 0, "xl/workbook.xml", "the workbook lists no sheet");
  return sheets;
}

}  // namespace trueaxis
