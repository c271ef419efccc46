// The files the package ships besides the program (packaging/, docs/install.md): the example
// configurations installed to /etc/trueaxis must be read by the commands their services run, and
// the program finds its pages and examples relative to itself.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <string>

#include "trueaxis/core/install_paths.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/server/shop_config.hpp"
#include "trueaxis/terminal/terminal_config.hpp"

namespace fs = std::filesystem;
using namespace trueaxis;

namespace {

const fs::path kPackaging = fs::path(TRUEAXIS_SOURCE_DIR) / "packaging";

bool UnderStateDir(const std::string& path) { return path.rfind("/var/lib/trueaxis/", 0) == 0; }

}  // namespace

// The server service runs with /etc read-only (ProtectSystem=strict): everything it writes, and the
// models it loads, must be named in its state folder, not relative to /etc/trueaxis.
TEST(PackagedFiles, ShopFileParsesAndKeepsStateInTheStateFolder) {
  const auto config = server::ParseShopConfig(ReadTextFile((kPackaging / "etc/shop.toml").string()), "/etc/trueaxis/shop.toml");
  ASSERT_EQ(config.machines.size(), 1u);
  EXPECT_TRUE(UnderStateDir(config.history)) << config.history;
  EXPECT_TRUE(UnderStateDir(config.audit_log)) << config.audit_log;
  EXPECT_TRUE(UnderStateDir(config.machines[0].model_file)) << config.machines[0].model_file;
  EXPECT_EQ(config.http_bind, "127.0.0.1");  // the control API has no authentication
}

// The terminal's shipped file reads the kernel's 1-Wire tree on MODBUS's port (the service's one
// capability) and serves the channels the shipped shop file's machine polls.
TEST(PackagedFiles, TerminalFileParsesAndServesTheShopMachinesChannels) {
  const auto terminal =
      terminal::ParseTerminalConfig(ReadTextFile((kPackaging / "etc/terminal.toml").string()), "/etc/trueaxis/terminal.toml");
  EXPECT_EQ(terminal.one_wire.options.root, "/sys/bus/w1/devices");
  EXPECT_EQ(terminal.server.port, 502);
  const auto shop = server::ParseShopConfig(ReadTextFile((kPackaging / "etc/shop.toml").string()), "/etc/trueaxis/shop.toml");
  ASSERT_EQ(shop.machines.size(), 1u);
  EXPECT_EQ(terminal.ChannelNames(), shop.machines[0].channels);
  EXPECT_EQ(terminal.server.port, shop.machines[0].port);
  EXPECT_EQ(terminal.server.first_rtd_unit_id, shop.machines[0].first_rtd_unit_id);
}

// This test program lies in the build tree: the installed place is tried first, then the source
// tree's folder.
TEST(InstallPaths, FromTheBuildTreeTheSourceFoldersAreFoundAfterTheInstalledPlace) {
  const DataFolder web = FindDataFolder("web", "src/web/static");
  ASSERT_EQ(web.looked_in.size(), 2u) << web.LookedIn();
  EXPECT_EQ(web.looked_in[0], (ExecutableDir() / "../share/trueaxis/web").lexically_normal());
  ASSERT_TRUE(web.found()) << web.LookedIn();
  EXPECT_TRUE(fs::equivalent(web.path, fs::path(TRUEAXIS_SOURCE_DIR) / "src/web/static"));
  EXPECT_TRUE(fs::exists(web.path / "login.html"));

  const DataFolder none = FindDataFolder("no-such-folder", "no/such/folder");
  EXPECT_FALSE(none.found());
  EXPECT_NE(none.LookedIn().find("no-such-folder"), std::string::npos);
  EXPECT_NE(none.LookedIn().find("no/such/folder"), std::string::npos);
}

TEST(InstallPaths, ExampleDefaultsComeFromTheExamplesFolderOutsideACheckout) {
  const auto cwd = fs::current_path();
  const fs::path empty = fs::temp_directory_path() / ("trueaxis-install-paths-" + std::to_string(::getpid()));
  fs::create_directories(empty);
  fs::current_path(empty);
  const std::string machine = DefaultExampleFile("machines/vmc850.toml");
  fs::current_path(cwd);
  fs::remove_all(empty);
  EXPECT_TRUE(fs::equivalent(machine, fs::path(TRUEAXIS_SOURCE_DIR) / "examples/machines/vmc850.toml")) << machine;
}
