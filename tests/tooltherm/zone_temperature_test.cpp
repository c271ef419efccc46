#include "trueaxis/tooltherm/zone_temperature.hpp"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "support/png_bomb.hpp"
#include "trueaxis/core/input_error.hpp"

namespace trueaxis::tooltherm {
namespace {

// 4×6 image with known values: zone A = rows 0–1, cols 0–2; zone B = rows 2–3, cols 3–5.
cv::Mat SmallImage() {
  cv::Mat m(4, 6, CV_32F);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 6; ++c) m.at<float>(r, c) = static_cast<float>(20 + r * 6 + c);
  return m;
}

const char* kZones = R"([[zone]]
name = "a"
row_from = 0
row_to = 1
col_from = 0
col_to = 2
area_mm2 = 100

[[zone]]
name = "b"
row_from = 2
row_to = 3
col_from = 3
col_to = 5
area_mm2 = 300
)";

TEST(ZoneTemperature, TvIsTheAreaWeightedMeanOfHandComputedZoneMeans) {
  const ZoneFile zones = ParseZoneToml(kZones, "zones.toml");
  const auto tr = ZoneMeansC(SmallImage(), zones, "img");
  // By hand: zone a holds 20,21,22,26,27,28 → 24; zone b holds 35,36,37,41,42,43 → 39.
  ASSERT_EQ(tr.size(), 2u);
  EXPECT_NEAR(tr[0], 24.0, 1e-9);
  EXPECT_NEAR(tr[1], 39.0, 1e-9);
  // Tv = (24·100 + 39·300) / 400 = 35.25
  EXPECT_NEAR(WeightedMeanTemperatureC(tr, ZoneAreas(zones.zones)), 35.25, 1e-9);
}

TEST(ZoneTemperature, SpotsAreAveragedPerZone) {
  const auto tr = SpotZoneMeansC({{0, 30}, {0, 34}, {1, 50}}, 2);
  EXPECT_NEAR(tr[0], 32, 1e-12);
  EXPECT_NEAR(tr[1], 50, 1e-12);
  EXPECT_THROW(SpotZoneMeansC({{0, 30}}, 2), std::invalid_argument);  // zone 1 has no spot
}

void ExpectInputError(const std::string& text, int line, const std::string& field) {
  try {
    ParseZoneToml(text, "z.toml");
    FAIL() << "accepted:\n" << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "z.toml");
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
  }
}

TEST(ZoneTemperature, BadZoneFilesNameLineAndField) {
  ExpectInputError("[[zone]]\nrow_from = 0\nrow_to = 1\ncol_from = 0\ncol_to = 2\n", 1, "zone[0].area_mm2");
  ExpectInputError("[[zone]]\nrow_from = 5\nrow_to = 1\ncol_from = 0\ncol_to = 2\narea_mm2 = 1\n", 3, "zone[0].row_to");
  ExpectInputError("[[zone]]\nrow_from = 0\nrow_to = 1\ncol_from = 0\ncol_to = 2\narea_mm2 = -4\n", 6, "zone[0].area_mm2");
  ExpectInputError("[[zone]]\nrow_from = 0\nrow_to = 1\ncol_from = 0\ncol_to = 2\narea_mm2 = 1\ncolour = 3\n", 7,
                   "zone[0].colour");
  ExpectInputError("[[zone]]\nrow_from = 0\nrow_to = 1\ncol_from = 0\narea_mm2 = 1\n", 1, "zone[0].col_to");
  ExpectInputError("[[zone]]\nrow_from = 0\nrow_to = 1\ncol_from = 0\ncol_to = 2\narea_mm2 = 1 2\n", 6, "");
  ExpectInputError("title = 3\n", 0, "zone");
}

TEST(ZoneTemperature, AZoneBeyondTheImageNamesTheZoneFileLine) {
  const ZoneFile zones = ParseZoneToml(std::string(kZones) + "\n[[zone]]\nname = \"c\"\nrow_from = 0\nrow_to = 9\n"
                                                             "col_from = 0\ncol_to = 1\narea_mm2 = 5\n",
                                       "zones.toml");
  try {
    ZoneMeansC(SmallImage(), zones, "img.png");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 17);
    EXPECT_EQ(e.field(), "zone[2].row_to");
    EXPECT_NE(std::string(e.what()).find("img.png"), std::string::npos);
  }
}

class ThermalImageFiles : public ::testing::Test {
 protected:
  std::filesystem::path dir = std::filesystem::temp_directory_path() / ("tooltherm_img_" + std::to_string(::getpid()));
  void SetUp() override { std::filesystem::create_directories(dir); }
  void TearDown() override { std::filesystem::remove_all(dir); }
  std::string Write(const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  }
};

TEST_F(ThermalImageFiles, SixteenBitPngAndCsvGiveTheSameTv) {
  cv::Mat raw(4, 6, CV_16U);
  std::string csv;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 6; ++c) {
      raw.at<std::uint16_t>(r, c) = static_cast<std::uint16_t>(29315 + 100 * (r * 6 + c));  // centi-kelvin
      csv += (c ? "," : "") + std::to_string(29315 + 100 * (r * 6 + c));
    }
    csv += "\n";
  }
  const std::string png = (dir / "t.png").string();
  ASSERT_TRUE(cv::imwrite(png, raw));
  const ZoneFile zones = ParseZoneToml(kZones, "zones.toml");
  const double tv_png = WeightedMeanTemperatureC(ZoneMeansC(ReadThermalImage(png, 0.01, -273.15), zones, png),
                                                 ZoneAreas(zones.zones));
  const std::string csv_path = Write("t.csv", csv);
  const double tv_csv = WeightedMeanTemperatureC(ZoneMeansC(ReadThermalImage(csv_path, 0.01, -273.15), zones, csv_path),
                                                 ZoneAreas(zones.zones));
  // Pixel (r, c) = 20 + (r·6 + c) °C, as SmallImage: Tv = 35.25.
  EXPECT_NEAR(tv_png, 35.25, 1e-6);
  EXPECT_NEAR(tv_csv, 35.25, 1e-6);
}

TEST_F(ThermalImageFiles, BadImagesAreRefusedWithFileAndPlace) {
  const std::string ragged = Write("r.csv", "1,2,3\n4,5\n");
  try {
    ReadThermalImage(ragged, 1, 0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.field(), "columns");
  }
  const std::string word = Write("w.csv", "1,2,3\n4,hot,6\n");
  try {
    ReadThermalImage(word, 1, 0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.field(), "column 2");
  }
  EXPECT_THROW(ReadThermalImage(Write("not.png", "this is not a png"), 1, 0), InputError);
  EXPECT_THROW(ReadThermalImage((dir / "missing.png").string(), 1, 0), InputError);
  cv::Mat eight(3, 3, CV_8U, cv::Scalar(100));
  const std::string png8 = (dir / "e.png").string();
  ASSERT_TRUE(cv::imwrite(png8, eight));
  EXPECT_THROW(ReadThermalImage(png8, 1, 0), InputError);
  EXPECT_THROW(ReadThermalImage(ragged, 0, 0), InputError);  // scale 0
}

// The sweep's A3: a PNG header claiming 100000×100000 px let OpenCV's
// assertion escape (exit 1, no file named).
TEST_F(ThermalImageFiles, AnImageBombIsAnInputErrorNamingTheFile) {
  const std::string bomb = (dir / "bomb.png").string();
  trueaxis::testing::WritePngBomb(bomb);
  try {
    ReadThermalImage(bomb, 0.01, -273.15);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), bomb);
    EXPECT_EQ(e.field(), "image");
    EXPECT_EQ(std::string(e.what()).find("OpenCV("), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace trueaxis::tooltherm
