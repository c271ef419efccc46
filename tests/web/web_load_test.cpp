// Load, as a correctness test (speed is in bench_web): 100 concurrent viewers on live charts of a
// 1,000-machine shop plus overview viewers, all at once; every request must be answered and every
// viewer must see its machine's values advance.
#include <atomic>
#include <thread>
#include <vector>

#include "web_fixture.hpp"

namespace trueaxis::web::testing {
namespace {

class LoadTest : public WebServerTest {
 protected:
  LoadTest() { machines_ = 1000; }
};

TEST_F(LoadTest, HundredViewersOfAThousandMachinesAreAllServed) {
  shop_->Start(0.25);
  std::atomic<int> failed{0}, advanced{0}, answered{0};
  std::vector<std::thread> viewers;
  for (int k = 0; k < 110; ++k)
    viewers.emplace_back([&, k] {
      const LoggedIn s = LoginAs("viewer", kViewerPassword);
      const bool overview = k >= 100;
      char id[8];
      std::snprintf(id, sizeof id, "m%04d", k * 9 % 1000 + 1);
      const std::string live = std::string("/api/machines/") + id + "/live?after=";
      std::uint64_t first = 0, last = 0;
      for (int i = 0; i < 12; ++i) {
        auto r = overview ? Get(s, "/api/machines?sort=max_correction&order=desc&limit=100")
                          : Get(s, live + std::to_string(last));
        if (!r || r->status != 200) {
          ++failed;
          continue;
        }
        ++answered;
        if (!overview) {
          last = nlohmann::json::parse(r->body)["last_seq"].get<std::uint64_t>();
          if (i == 0) first = last;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(250));
      }
      if (overview || last > first) ++advanced;
    });
  for (auto& t : viewers) t.join();
  shop_->Stop();
  EXPECT_EQ(failed.load(), 0);
  EXPECT_EQ(answered.load(), 110 * 12);
  EXPECT_EQ(advanced.load(), 110) << "every viewer's machine moved on while it watched";
}

}  // namespace
}  // namespace trueaxis::web::testing
