// The workshop server's history on a database server (issue 11, "when one box is not enough"):
// the shop file's `history` names a PostgreSQL URL, the shop's machines write through the same
// HistoryWriter, and psql (an independent reader) finds every machine's rows.
#include <gtest/gtest.h>

#include "server/shop_fixture.hpp"
#include "postgres_server.hpp"
#include "trueaxis/server/shop.hpp"
#include "trueaxis/store/history_writer.hpp"
#include "trueaxis/store/open_history_sink.hpp"
#include "trueaxis/store_postgres/postgres_history_sink.hpp"

namespace trueaxis::server {
namespace {

using testing::ConfigFor;
using testing::StartVirtualShop;
using testing::TempDir;
using testing::WaitFor;
using testing::WaitUntilEveryMachineReads;
using testing::WriteModel;

TEST(ShopPostgres, EveryMachinesHistoryLandsInPostgresql) {
  trueaxis::testing::PostgresServer pg;
  ASSERT_TRUE(pg.Start()) << pg.error();
  const std::string dir = TempDir("pg");
  auto vshop = StartVirtualShop(2);
  ASSERT_TRUE(vshop);
  ShopConfig config = ConfigFor(*vshop, WriteModel(dir + "/model.json"));
  config.history = pg.Url();
  store::EnablePostgresHistory();
  store::HistoryWriter writer(store::OpenHistorySink(config.history));
  {
    Shop shop(config, &writer);
    shop.Start();
    ASSERT_TRUE(WaitUntilEveryMachineReads(shop));
    // rows with temperatures of every machine (a record every record_interval_s per machine)
    const std::uint64_t at_connect = writer.Stats().accepted;
    ASSERT_TRUE(WaitFor([&] { return writer.Stats().accepted > at_connect + 4 * config.machines.size(); }, 20));
    shop.Stop();
  }
  writer.Close();
  EXPECT_EQ(writer.Stats().failed, 0u) << writer.Stats().BriefReport();
  for (const auto& m : config.machines) {
    const std::string axis = m.name + "/" + m.axes[0], channel = m.name + "/" + m.channels[0];
    EXPECT_NE(pg.Psql("SELECT count(*) FROM compensation c JOIN axis a ON a.id = c.axis_id WHERE a.name = '" + axis + "'"), "0") << axis;
    EXPECT_NE(pg.Psql("SELECT count(*) FROM temperature t JOIN channel c ON c.id = t.channel_id WHERE c.name = '" + channel +
                      "' AND t.raw_c IS NOT NULL"),
              "0")
        << channel;
  }
}

}  // namespace
}  // namespace trueaxis::server
