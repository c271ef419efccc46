#include "trueaxis/store/history_export.hpp"

#include <cstdlib>
#include <filesystem>

#include <gtest/gtest.h>

#include "support/cli_runner.hpp"
#include "test_dir.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/store/history_writer.hpp"

namespace trueaxis::store {
namespace {

namespace fs = std::filesystem;

class HistoryExportTest : public testing::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    db_path_ = Path("h.db");
    HistoryWriter w(db_path_);
    // 2026-11-22T08:00:00Z + i minutes
    for (int i = 0; i < 60; ++i) {
      const double t = 1795334400.0 + 60.0 * i;
      w.PushTemperature(t, "x_nut", 22 + 0.05 * i, 22 + 0.05 * i - 0.01, "ok");
      w.PushTemperature(t, "ambient", 20.0, 20.0, i == 30 ? "hardware_fault" : "ok");
      w.PushCompensation(t, "X", 250, -1.5 * i, "active");
    }
    w.PushAlarm(1795334400.0 + 1800, "fault", "ambient", "hardware fault, using last good value");
    w.PushModelChange(1795334400.0, std::string(64, 'c'), "r7", "refit, day 2");
  }
  std::string db_path_;
};

// Unzips with Python's zipfile (independent of libxlsxwriter) and prints the
// archive's names and one member.
std::string Unzip(const std::string& xlsx, const std::string& member) {
  const std::string out = xlsx + ".listing";
  const std::string cmd = "/usr/bin/python3 -c \"import sys, zipfile; z = zipfile.ZipFile(sys.argv[1]); "
                          "assert z.testzip() is None; print('\\n'.join(z.namelist())); "
                          "print(z.read(sys.argv[2]).decode())\" '" +
                          xlsx + "' '" + member + "' > '" + out + "' 2>&1";
  if (std::system(cmd.c_str()) != 0) return "UNZIP FAILED: " + ReadTextFile(out);
  return ReadTextFile(out);
}

TEST_F(HistoryExportTest, CsvOfATimeRangeAndChannel) {
  HistoryDb db(db_path_, HistoryDb::Mode::kReadOnly);
  ExportRequest req;
  req.range = {1795334400.0 + 600, 1795334400.0 + 1200};  // 08:10 .. 08:20 inclusive
  req.channels = {"x_nut"};
  const auto result = ExportCsv(db, HistoryTable::kTemperature, req, Path("t.csv"));
  EXPECT_EQ(result.temperature_rows, 11);
  const std::string csv = ReadTextFile(Path("t.csv"));
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "time_s,time_utc,channel,raw_c,filtered_c,status");
  EXPECT_NE(csv.find("1795335000,2026-11-22T08:10:00.000Z,x_nut,22.5,22.49,ok\n"), std::string::npos) << csv;
  EXPECT_EQ(csv.find("ambient"), std::string::npos);
  EXPECT_FALSE(fs::exists(Path("t.csv.tmp")));
  ExportCsv(db, HistoryTable::kAlarm, {}, Path("a.csv"));
  EXPECT_NE(ReadTextFile(Path("a.csv")).find("fault,ambient,\"hardware fault, using last good value\""), std::string::npos);
  ExportCsv(db, HistoryTable::kModelChange, {}, Path("m.csv"));
  EXPECT_NE(ReadTextFile(Path("m.csv")).find("r7,\"refit, day 2\""), std::string::npos);
  const auto comp = ExportCsv(db, HistoryTable::kCompensation, {}, Path("c.csv"));
  EXPECT_EQ(comp.compensation_rows, 60);
}

TEST_F(HistoryExportTest, XlsxIsAValidWorkbookWithOneSheetPerTable) {
  HistoryDb db(db_path_, HistoryDb::Mode::kReadOnly);
  ExportRequest req;
  req.channels = {"x_nut", "ambient"};
  const auto result = ExportXlsx(db, req, Path("h.xlsx"));
  EXPECT_EQ(result.temperature_rows, 120);
  EXPECT_EQ(result.compensation_rows, 60);
  EXPECT_EQ(result.alarm_rows, 1);
  EXPECT_EQ(result.model_change_rows, 1);
  const std::string workbook = Unzip(Path("h.xlsx"), "xl/workbook.xml");
  ASSERT_EQ(workbook.find("UNZIP FAILED"), std::string::npos) << workbook;
  for (const char* member : {"xl/worksheets/sheet1.xml", "xl/worksheets/sheet5.xml", "[Content_Types].xml"})
    EXPECT_NE(workbook.find(member), std::string::npos) << member;
  for (const char* sheet : {"name=\"temperature\"", "name=\"compensation\"", "name=\"alarms\"", "name=\"model_changes\"",
                            "name=\"info\""})
    EXPECT_NE(workbook.find(sheet), std::string::npos) << sheet;
  const std::string sheet1 = Unzip(Path("h.xlsx"), "xl/worksheets/sheet1.xml");
  EXPECT_NE(sheet1.find("x_nut"), std::string::npos);
  EXPECT_NE(sheet1.find("hardware_fault"), std::string::npos);
  EXPECT_NE(sheet1.find("<row r=\"121\""), std::string::npos);  // header + 120 readings
  EXPECT_EQ(sheet1.find("<row r=\"122\""), std::string::npos);
  EXPECT_FALSE(fs::exists(Path("h.xlsx.tmp")));
}

TEST_F(HistoryExportTest, WideLayoutHasOneRowPerInstantAndAColumnPerChannel) {
  HistoryDb db(db_path_, HistoryDb::Mode::kReadOnly);
  ExportRequest req;
  req.wide = true;
  req.range = {1795334400.0 + 1740, 1795334400.0 + 1800};  // 08:29 .. 08:30
  const auto result = ExportCsv(db, HistoryTable::kTemperature, req, Path("w.csv"));
  EXPECT_EQ(result.temperature_rows, 4);  // readings
  const std::string csv = ReadTextFile(Path("w.csv"));
  EXPECT_EQ(csv,
            "time_s,time_utc,ambient_c,x_nut_c,ambient_status,x_nut_status\n"
            "1795336140,2026-11-22T08:29:00.000Z,20," + FormatShortest(22 + 0.05 * 29 - 0.01) + ",ok,ok\n"
            "1795336200,2026-11-22T08:30:00.000Z,20," + FormatShortest(22 + 0.05 * 30 - 0.01) + ",hardware_fault,ok\n");
  req.channels = {"x_nut"};
  ExportXlsx(db, req, Path("w.xlsx"));
  const std::string workbook = Unzip(Path("w.xlsx"), "xl/workbook.xml");
  EXPECT_NE(workbook.find("name=\"temperature\""), std::string::npos);
  EXPECT_NE(workbook.find("name=\"temperature_long\""), std::string::npos);
  const std::string sheet1 = Unzip(Path("w.xlsx"), "xl/worksheets/sheet1.xml");
  EXPECT_NE(sheet1.find("x_nut_c"), std::string::npos);
  EXPECT_EQ(sheet1.find("ambient_c"), std::string::npos);
  EXPECT_NE(sheet1.find("<row r=\"3\""), std::string::npos);  // header + 2 instants
  EXPECT_EQ(sheet1.find("<row r=\"4\""), std::string::npos);
  auto r = testing::RunCli("history export --db " + db_path_ + " --layout wide --format csv --out " + Path("cli_w.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string cli = ReadTextFile(Path("cli_w.csv"));
  EXPECT_EQ(std::count(cli.begin(), cli.end(), '\n'), 61);  // header + 60 instants
  r = testing::RunCli("history export --db " + db_path_ + " --layout tall --format csv --out " + Path("x.csv"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
}

TEST_F(HistoryExportTest, XlsxContinuesOnNextSheetAtTheRowLimit) {
  HistoryDb db(db_path_, HistoryDb::Mode::kReadOnly);
  ExportRequest req;
  req.max_rows_per_sheet = 50;  // stands in for Excel's 1,048,575
  const auto result = ExportXlsx(db, req, Path("split.xlsx"));
  EXPECT_EQ(result.temperature_rows, 120);
  const std::string workbook = Unzip(Path("split.xlsx"), "xl/workbook.xml");
  for (const char* sheet : {"name=\"temperature\"", "name=\"temperature_2\"", "name=\"temperature_3\"",
                            "name=\"compensation\"", "name=\"compensation_2\""})
    EXPECT_NE(workbook.find(sheet), std::string::npos) << sheet;
  EXPECT_EQ(workbook.find("name=\"temperature_4\""), std::string::npos);
  EXPECT_EQ(workbook.find("name=\"compensation_3\""), std::string::npos);
  // 50 + 50 + 20 rows: the third temperature sheet (sheet3.xml) ends at row 21.
  const std::string third = Unzip(Path("split.xlsx"), "xl/worksheets/sheet3.xml");
  EXPECT_NE(third.find("<row r=\"21\""), std::string::npos);
  EXPECT_EQ(third.find("<row r=\"22\""), std::string::npos);
}

TEST_F(HistoryExportTest, ReaderWorksWhileTheWriterIsRunning) {
  // The runtime keeps writing while an engineer exports: WAL lets both work.
  HistoryWriter writer(db_path_);
  for (int i = 0; i < 500; ++i) writer.PushTemperature(1795400000.0 + i, "x_nut", 30, 30, "ok");
  writer.Flush();
  auto r = testing::RunCli("history export --db " + db_path_ + " --from 1795400000 --format csv --out " + Path("live.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("500 temperature readings"), std::string::npos) << r.output;
  for (int i = 0; i < 100; ++i) writer.PushTemperature(1795401000.0 + i, "x_nut", 31, 31, "ok");
  writer.Flush();
  HistoryDb reader(db_path_, HistoryDb::Mode::kReadOnly);
  EXPECT_EQ(reader.QueryTemperatures({1795400000.0, 1e12}).size(), 600u);
  EXPECT_EQ(writer.Stats().failed, 0u);
}

TEST_F(HistoryExportTest, XlsxWithUnknownChannelWritesNothing) {
  HistoryDb db(db_path_, HistoryDb::Mode::kReadOnly);
  ExportRequest req;
  req.channels = {"z_nut"};
  EXPECT_THROW(ExportXlsx(db, req, Path("h.xlsx")), InputError);
  EXPECT_FALSE(fs::exists(Path("h.xlsx")));
  EXPECT_FALSE(fs::exists(Path("h.xlsx.tmp")));
}

TEST_F(HistoryExportTest, CliExportQueryAndInfo) {
  auto r = testing::RunCli("history export --db " + db_path_ +
                           " --from 2026-11-22T08:10:00Z --to 2026-11-22T08:19:59Z --channels x_nut --format csv --out " +
                           Path("cli.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("10 temperature readings"), std::string::npos) << r.output;
  const std::string csv = ReadTextFile(Path("cli.csv"));
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 11);
  r = testing::RunCli("history export --db " + db_path_ + " --format xlsx --out " + Path("cli.xlsx"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(Unzip(Path("cli.xlsx"), "xl/workbook.xml").find("name=\"temperature\""), std::string::npos);
  r = testing::RunCli("history query --db " + db_path_ + " --channels ambient --limit 3");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 4) << r.output;
  EXPECT_NE(r.output.find(",ambient,20,20,ok"), std::string::npos) << r.output;
  r = testing::RunCli("history query --db " + db_path_ + " --table alarms");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("using last good value"), std::string::npos);
  r = testing::RunCli("history query --db " + db_path_ + " --table compensation --channels X --from 1795334400 --to 1795334460");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(",X,250,-1.5,active"), std::string::npos) << r.output;
  r = testing::RunCli("history info --db " + db_path_);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("120 rows"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("2026-11-22T08:00:00.000Z"), std::string::npos) << r.output;
}

TEST_F(HistoryExportTest, CliBadInputsExitTwoAndChangeNothing) {
  const std::string before = ReadFileBytes(db_path_);
  auto r = testing::RunCli("history export --db " + db_path_ + " --channels nope --format csv --out " + Path("x.csv"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("channels"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("ambient, x_nut"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(Path("x.csv")));
  r = testing::RunCli("history export --db " + db_path_ + " --from tomorrow --format csv --out " + Path("x.csv"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--from"), std::string::npos) << r.output;
  r = testing::RunCli("history export --db " + db_path_ + " --from 2000 --to 1000 --format csv --out " + Path("x.csv"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = testing::RunCli("history export --db " + db_path_ + " --format pdf --out " + Path("x.pdf"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--format"), std::string::npos) << r.output;
  r = testing::RunCli("history query --db " + db_path_ + " --table sensors");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = testing::RunCli("history export --db " + db_path_ + " --format csv --out " + Path("no/such/dir/x.csv"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("x.csv"), std::string::npos) << r.output;
  r = testing::RunCli("history info --db " + Path("missing.db"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("no such history database"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(Path("missing.db")));
  WriteTextFile(Path("corrupt.db"), std::string(4096, 'x'));
  r = testing::RunCli("history export --db " + Path("corrupt.db") + " --format xlsx --out " + Path("x.xlsx"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("corrupt.db"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("not a trueaxis history database"), std::string::npos) << r.output;
  EXPECT_EQ(ReadTextFile(Path("corrupt.db")), std::string(4096, 'x'));
  EXPECT_FALSE(fs::exists(Path("x.xlsx")));
  EXPECT_EQ(ReadFileBytes(db_path_), before);
}

TEST_F(HistoryExportTest, CliRefusesAnOutputThatIsTheDatabaseOrADirectory) {
  const std::string before = ReadFileBytes(db_path_);
  for (const char* format : {"csv", "xlsx"}) {
    const auto r = testing::RunCli(std::string("history export --db ") + db_path_ + " --format " + format + " --out " + db_path_);
    EXPECT_EQ(r.exit_code, 2) << format << ": " << r.output;
    EXPECT_NE(r.output.find("field '--out'"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("is the input file"), std::string::npos) << r.output;
    EXPECT_EQ(ReadFileBytes(db_path_), before) << format;
  }
  // The same file by another spelling (./dir/../h.db) is the same file.
  const std::string other_spelling = (dir_ / "." / ".." / dir_.filename() / "h.db").string();
  auto r = testing::RunCli("history export --db " + db_path_ + " --format csv --out " + other_spelling);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(ReadFileBytes(db_path_), before);
  r = testing::RunCli("history export --db " + db_path_ + " --format xlsx --out " + dir_.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("field '--out'"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("is a directory"), std::string::npos) << r.output;
}

// A database whose data pages are overwritten passes the header checks and fails on the first table read:
// that is a damaged input file (exit 2, the file named), and `query` prints no CSV header before the error.
TEST_F(HistoryExportTest, CliDamagedDatabaseExitsTwoNamingTheFile) {
  const std::string damaged = Path("damaged.db");
  {
    HistoryWriter w(damaged);
    for (int i = 0; i < 3000; ++i) w.PushTemperature(1795334400.0 + i, "x_nut", 22 + 0.001 * i, 22, "ok");
  }
  std::string bytes = ReadFileBytes(damaged);
  ASSERT_GT(bytes.size(), 8u * 4096u);
  std::uint32_t state = 12345;
  for (std::size_t i = 2 * 4096; i < bytes.size(); ++i) {  // pages 3…: table data, not the header or schema
    state = state * 1103515245u + 12345u;
    bytes[i] = static_cast<char>(state >> 24);
  }
  WriteTextFile(damaged, bytes);
  for (const std::string& cmd : std::vector<std::string>{"history info --db ", "history query --db ",
                                                         "history export --format csv --out " + Path("x.csv") + " --db "}) {
    const auto r = testing::RunCli(cmd + damaged);
    EXPECT_EQ(r.exit_code, 2) << cmd << r.output;
    EXPECT_NE(r.output.find("damaged.db"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("the history database is damaged"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("time_s,time_utc"), std::string::npos) << r.output;
  }
  EXPECT_EQ(ReadFileBytes(damaged), bytes);
}

// A database cut short (a copy interrupted) is refused from its header before SQLite opens it, so
// no -wal/-shm files appear beside a file the message says was not modified.
TEST_F(HistoryExportTest, CliDatabaseCutShortIsRefusedWithoutSideFiles) {
  const std::string cut = Path("cut.db");
  {
    HistoryWriter w(cut);
    for (int i = 0; i < 3000; ++i) w.PushTemperature(1795334400.0 + i, "x_nut", 22 + 0.001 * i, 22, "ok");
  }
  const std::string bytes = ReadFileBytes(cut);
  ASSERT_GT(bytes.size(), 8u * 4096u);
  WriteTextFile(cut, bytes.substr(0, bytes.size() / 2));
  const auto r = testing::RunCli("history info --db " + cut);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("cut.db: the history database is damaged: cut short"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(cut + "-wal"));
  EXPECT_FALSE(fs::exists(cut + "-shm"));
  EXPECT_EQ(ReadFileBytes(cut), bytes.substr(0, bytes.size() / 2));
}

}  // namespace
}  // namespace trueaxis::store
