// `campaign log`'s warm-up watch: from the manifest's tests and the logged nut sensor, when the
// next warm-up test is due by the campaign's warm-up rule.
#include <cmath>
#include <span>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "trueaxis/campaign/warmup_watch.hpp"

namespace trueaxis::campaign {
namespace {

TEST(WarmUpWatch, SaysWhenTheNextTestIsDue) {
  sim::WarmUpRule rule;
  // The log: every 60 s, nut 20 °C until the cold test ends at 600 s, then +1 °C per hour; X moving.
  std::vector<double> t, nut, travel;
  for (int i = 0; i <= 240; ++i) {
    t.push_back(60.0 * i);
    nut.push_back(t.back() <= 600 ? 20 : 20 + (t.back() - 600) / 3600);
    travel.push_back(100.0 * i);
  }
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  EXPECT_FALSE(WatchWarmUp(rule, 0.5, list, "X", t, nut, travel, 60).has_cold);
  list.push_back({{"axis", "X"}, {"state", "cold"}, {"start_time_s", 0}, {"end_time_s", 600},
                  {"mean_temperatures_c", {{"x_nut", 20.0}}}});
  // After 0.4 h: +0.4 °C, the first test at +0.5.
  auto upto = [&](double end_s) {
    std::size_t n = 0;
    while (n < t.size() && t[n] <= end_s) ++n;
    return WatchWarmUp(rule, 0.5, list, "X", std::span(t).first(n), std::span(nut).first(n), std::span(travel).first(n), 60);
  };
  auto st = upto(600 + 0.4 * 3600);
  EXPECT_TRUE(st.has_cold);
  EXPECT_NEAR(st.rise_c, 0.4, 0.01);
  EXPECT_DOUBLE_EQ(st.next_rise_c, 0.5);
  EXPECT_FALSE(st.due);
  st = upto(600 + 0.6 * 3600);
  EXPECT_TRUE(st.due) << st.Text();
  EXPECT_NE(st.Text().find("due now"), std::string::npos) << st.Text();
  // A warm test from 0.6 h to 0.8 h at +0.7: the next at +1.2 °C and after 0.1 h more machining.
  list.push_back({{"axis", "X"}, {"state", "warm"}, {"start_time_s", 600 + 0.6 * 3600}, {"end_time_s", 600 + 0.8 * 3600},
                  {"nut_rise_c", 0.7}});
  st = upto(600 + 0.85 * 3600);
  EXPECT_EQ(st.taken, 1);
  EXPECT_DOUBLE_EQ(st.next_rise_c, 1.2);
  EXPECT_NEAR(st.machining_left_s, 0.05 * 3600, 61);
  EXPECT_FALSE(st.due);
  st = upto(600 + 1.3 * 3600);
  EXPECT_TRUE(st.due) << st.Text();
  // The machine stood (no travel) since the test: not due, machining still to wait for.
  for (std::size_t i = 0; i < travel.size(); ++i)
    if (t[i] > 600 + 0.8 * 3600) travel[i] = travel[static_cast<std::size_t>((600 + 0.8 * 3600) / 60)];
  st = upto(600 + 1.3 * 3600);
  EXPECT_FALSE(st.due) << st.Text();
  EXPECT_GT(st.machining_left_s, 0);
  EXPECT_NE(st.Text().find("more machining"), std::string::npos) << st.Text();
}

}  // namespace
}  // namespace trueaxis::campaign
