// A real browser on the pages: headless Chromium driven by tests/web/browser_check.py (Selenium)
// logs in, sees a live value change, operates as operator, is refused as viewer, logs out.
// Screenshots go to $TRUEAXIS_WEB_SCREENSHOT_DIR (docs/ for the README) or the test's folder.
// If Chromium cannot start, the test fails with the reason.
#include <array>
#include <cstdio>
#include <cstdlib>
#include <sys/wait.h>

#include "web_fixture.hpp"

namespace trueaxis::web::testing {
namespace {

class BrowserTest : public WebServerTest {
 protected:
  BrowserTest() { machines_ = 300; }
};

TEST_F(BrowserTest, LogsInSeesLiveValuesOperatesAndIsRefusedAsViewer) {
  shop_->Start(0.5);
  const char* shots_env = std::getenv("TRUEAXIS_WEB_SCREENSHOT_DIR");
  const std::string shots = shots_env ? shots_env : dir_.string();
  const std::string cmd = std::string("/usr/bin/python3 ") + TRUEAXIS_SOURCE_DIR + "/tests/web/browser_check.py " +
                          server_->Url() + " " + shots + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  ASSERT_NE(p, nullptr);
  std::string output;
  std::array<char, 4096> buf;
  std::size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) output.append(buf.data(), n);
  const int status = pclose(p);
  shop_->Stop();
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << output;
  EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(shots) / "web_overview.png"));
  EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(shots) / "web_machine.png"));
  // The server saw it all: the operator's operation and the viewer's refused attempt are audited.
  bool op_ok = false, viewer_refused = false;
  for (const auto& e : access_->RecentAudit(100)) {
    op_ok |= e.user == "op" && e.action == "axis_enable" && e.outcome == "ok";
    viewer_refused |= e.user == "viewer" && e.action == "axis_enable" && e.outcome.rfind("refused", 0) == 0;
  }
  EXPECT_TRUE(op_ok);
  EXPECT_TRUE(viewer_refused);
}

}  // namespace
}  // namespace trueaxis::web::testing
