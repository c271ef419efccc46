// The [web] table of the run config: the front end of `trueaxis run` named in the config file.
#include <gtest/gtest.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/station/site_config.hpp"

namespace trueaxis::station {
namespace {

constexpr const char* kHead = "[machine]\nkind = \"modbus\"\nport = 15020\n[model]\nfile = \"/m.json\"\n";

TEST(RunConfigWeb, ReadsTheFrontEndWithPathsRelativeToTheConfig) {
  const SiteConfig c = ParseSiteConfig(std::string(kHead) +
                                         "[web]\nlisten = \"127.0.0.1:8443\"\nusers = \"users.db\"\ncert = \"c.pem\"\n"
                                         "key = \"/etc/k.pem\"\nmachine_id = \"vmc7\"\n",
                                     "/etc/trueaxis/run.toml");
  EXPECT_EQ(c.web.listen, "127.0.0.1:8443");
  EXPECT_EQ(c.web.users, "/etc/trueaxis/users.db");
  EXPECT_EQ(c.web.cert, "/etc/trueaxis/c.pem");
  EXPECT_EQ(c.web.key, "/etc/k.pem");
  EXPECT_EQ(c.web.machine_id, "vmc7");
  EXPECT_TRUE(ParseSiteConfig(kHead, "run.toml").web.listen.empty()) << "no [web]: no front end";
}

TEST(RunConfigWeb, RefusesUnknownKeysAndWrongTypes) {
  EXPECT_THROW(ParseSiteConfig(std::string(kHead) + "[web]\npassword = \"x\"\n", "run.toml"), InputError);
  EXPECT_THROW(ParseSiteConfig(std::string(kHead) + "[web]\nlisten = 8080\n", "run.toml"), InputError);
}

}  // namespace
}  // namespace trueaxis::station
