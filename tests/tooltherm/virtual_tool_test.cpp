#include "trueaxis/tooltherm/virtual_tool.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/tooltherm/thermal_camera.hpp"

namespace trueaxis::tooltherm {
namespace {

ToolDescription LongHss() {
  ToolDescription t;
  t.number = 2;
  t.length_mm = 90;
  t.diameter_mm = 8;
  t.material = "hss";
  t.holder_length_mm = 70;
  t.holder_diameter_mm = 32;
  t.cutting_heat_share = 0.005;
  t.zones = DefaultToolZones(t);
  return t;
}

double Tv(const VirtualTool& vt) {
  std::vector<double> tr, sr;
  for (const auto& z : vt.tool().zones) {
    double sum = 0;
    for (int k = 0; k < 20; ++k) sum += vt.SurfaceC(z.from_mm + (k + 0.5) / 20 * (z.to_mm - z.from_mm));
    tr.push_back(sum / 20);
    sr.push_back(z.area_mm2);
  }
  return WeightedMeanTemperatureC(tr, sr);
}

TEST(VirtualTool, SoakedAtStandardTemperatureHasNoError) {
  VirtualTool vt(LongHss(), 20, 20);
  vt.Advance(600, {true, 20, 0, 0, false, 20, 20});
  EXPECT_NEAR(vt.TipErrorUm(), 0, 1e-9);
}

TEST(VirtualTool, CuttingHeatsTheTipFirstAndTheToolGrowsTowardsTheWork) {
  VirtualTool vt(LongHss(), 20, 20);
  const ToolConditions cut{true, 20, 3000, 1200, false, 20, 20};
  for (int i = 0; i < 120; ++i) vt.Advance(1, cut);
  EXPECT_GT(vt.SegmentC(0), vt.SegmentC(2));
  EXPECT_GT(vt.SegmentC(2), vt.SegmentC(4));
  EXPECT_GT(vt.GrowthUm(), 1);
  EXPECT_DOUBLE_EQ(vt.TipErrorUm(), -vt.GrowthUm());  // docs/sign-convention.md: longer tool, tip low
}

TEST(VirtualTool, GrowthAtTheSameTvDiffersBetweenHeatingAndCooling) {
  // Heat by cutting for 40 min, then stop and cool: record (Tv, growth) both ways and compare
  // the growth where Tv crosses the same value — the hysteresis seed 001 is about.
  VirtualTool vt(LongHss(), 20, 20);
  std::vector<std::pair<double, double>> up, down;
  for (int i = 0; i < 2400; ++i) {
    vt.Advance(1, {true, 20, 3000, 1200, false, 20, 20});
    up.emplace_back(Tv(vt), vt.GrowthUm());
  }
  for (int i = 0; i < 4800; ++i) {
    vt.Advance(1, {true, 20, 0, 0, false, 20, 20});
    down.emplace_back(Tv(vt), vt.GrowthUm());
  }
  auto growth_at = [](const std::vector<std::pair<double, double>>& s, double tv) {
    for (std::size_t i = 1; i < s.size(); ++i)
      if ((s[i - 1].first - tv) * (s[i].first - tv) <= 0) return s[i].second;
    return std::nan("");
  };
  const double peak = up.back().first;
  const double tv = 20 + 0.5 * (peak - 20);
  const double g_up = growth_at(up, tv), g_down = growth_at(down, tv);
  ASSERT_TRUE(std::isfinite(g_up) && std::isfinite(g_down)) << "Tv " << tv << " peak " << peak;
  EXPECT_GT(std::abs(g_up - g_down), 0.05 * std::abs(up.back().second)) << g_up << " vs " << g_down;
}

TEST(VirtualTool, InTheMagazineItCoolsMoreSlowlyThanInTheSpindle) {
  VirtualTool a(LongHss(), 20, 20), b(LongHss(), 20, 20);
  for (int i = 0; i < 600; ++i) {
    a.Advance(1, {true, 20, 3000, 1200, false, 20, 20});
    b.Advance(1, {true, 20, 3000, 1200, false, 20, 20});
  }
  for (int i = 0; i < 300; ++i) {
    a.Advance(1, {false, 20, 0, 0, false, 20, 20});  // magazine: air only
    b.Advance(1, {true, 20, 0, 0, false, 20, 20});   // spindle nose at 20 °C drains the holder
  }
  EXPECT_GT(a.GrowthUm(), b.GrowthUm());
}

TEST(ThermalCamera, ZonesOfTheImageReadTheToolsSurface) {
  VirtualTool vt(LongHss(), 20, 20);
  for (int i = 0; i < 900; ++i) vt.Advance(1, {true, 20, 3000, 1200, false, 20, 20});
  ThermalCameraOptions o;
  o.emissivity_true = o.emissivity_set;  // no radiometric error
  o.noise_c = 0.05;
  o.reflection_probability = 0;
  std::mt19937_64 rng(5);
  const cv::Mat img = RenderThermalImage(vt, {false, 20, 20}, o, rng);
  const ZoneFile zf{"geometry", ImageZonesFor(vt.tool(), o)};
  const auto tr = ZoneMeansC(img, zf, "frame");
  ASSERT_EQ(tr.size(), 4u);
  for (std::size_t z = 0; z < tr.size(); ++z) {
    const auto& band = vt.tool().zones[z];
    EXPECT_NEAR(tr[z], vt.SurfaceC(0.5 * (band.from_mm + band.to_mm)), 0.15 * (vt.SegmentC(0) - 20) + 0.2) << band.name;
  }
  EXPECT_NEAR(WeightedMeanTemperatureC(tr, ZoneAreas(zf.zones)), Tv(vt), 0.5);
}

TEST(ToolFile, ReadsTheExampleAndDerivesZoneAreasFromGeometry) {
  const ToolTable t = ReadToolFile(std::string(TRUEAXIS_SOURCE_DIR) + "/examples/tool/tools.toml");
  ASSERT_EQ(t.tools.size(), 3u);
  const ToolDescription& fm = *t.Find(3);
  ASSERT_EQ(fm.zones.size(), 3u);
  EXPECT_NEAR(fm.zones[0].area_mm2, M_PI * 50 * 20, 1e-9);   // on the tool
  EXPECT_NEAR(fm.zones[2].area_mm2, M_PI * 63 * 50, 1e-9);   // on the holder
  EXPECT_EQ(t.Find(1)->zones.size(), 4u);                    // default bands
}

void ExpectToolError(const std::string& text, int line, const std::string& field) {
  try {
    ParseToolToml(text, "tools.toml");
    FAIL() << "accepted:\n" << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
  }
}

TEST(ToolFile, BadToolFilesNameLineAndField) {
  const std::string ok = "[[tool]]\nnumber = 1\nlength_mm = 40\ndiameter_mm = 10\n";
  ExpectToolError(ok + "material = \"cheese\"\n", 5, "tool[0].material");
  ExpectToolError("[[tool]]\nnumber = 1\nlength_mm = -4\ndiameter_mm = 10\n", 3, "tool[0].length_mm");
  ExpectToolError(ok + ok, 6, "tool[1].number");
  ExpectToolError(ok + "[[tool.zone]]\nfrom_mm = 30\nto_mm = 50\n", 7, "tool[0].zone[0].to_mm");  // straddles the step
  ExpectToolError(ok + "lenght_mm = 3\n", 5, "tool[0].lenght_mm");
  ExpectToolError("standard_temp_c = 20\n", 0, "tool");
}

}  // namespace
}  // namespace trueaxis::tooltherm
