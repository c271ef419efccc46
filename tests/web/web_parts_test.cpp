// The web front end's parts on their own: password hashes, the user database, sessions, the
// login limiter, the alarm book, the live ring, the overview query.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <vector>

#include <gtest/gtest.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/web/access_db.hpp"
#include "trueaxis/web/alarm_book.hpp"
#include "trueaxis/web/live_ring.hpp"
#include "trueaxis/web/login_limiter.hpp"
#include "trueaxis/web/machine_query.hpp"
#include "trueaxis/web/password_hash.hpp"
#include "trueaxis/web/session_store.hpp"

namespace trueaxis::web {
namespace {

namespace fs = std::filesystem;

fs::path TempFile(const std::string& name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path p = fs::temp_directory_path() / ("trueaxis_webparts_" + std::to_string(::getpid()) + "_" + info->name() + "_" + name);
  fs::remove(p);
  return p;
}

TEST(PasswordHash, IsArgon2idSaltedAndVerifiesOnlyTheRightPassword) {
  const std::string a = HashPassword("correct horse", HashCost::kMinimum);
  const std::string b = HashPassword("correct horse", HashCost::kMinimum);
  EXPECT_EQ(a.rfind("$argon2id$", 0), 0u);
  EXPECT_NE(a, b) << "a random salt per hash";
  EXPECT_EQ(a.find("correct horse"), std::string::npos);
  EXPECT_TRUE(VerifyPassword(a, "correct horse"));
  EXPECT_FALSE(VerifyPassword(a, "correct horsE"));
  EXPECT_FALSE(VerifyPassword("not a hash", "correct horse"));
  EXPECT_EQ(RandomToken().size(), 64u);
  EXPECT_NE(RandomToken(), RandomToken());
}

TEST(AccessDb, StoresHashesNeverPasswordsAndRefusesBadInput) {
  const fs::path p = TempFile("users.db");
  {
    AccessDb db(p.string());
    db.AddUser("alice", Role::kOperator, "alice-secret-9", HashCost::kMinimum);
    EXPECT_THROW(db.AddUser("alice", Role::kAdmin, "another-pass", HashCost::kMinimum), InputError);
    EXPECT_THROW(db.AddUser("bob", Role::kAdmin, "short", HashCost::kMinimum), InputError);
    EXPECT_THROW(db.AddUser("bo b", Role::kAdmin, "long-enough-1", HashCost::kMinimum), InputError);
    EXPECT_THROW(db.AddUser("", Role::kAdmin, "long-enough-1", HashCost::kMinimum), InputError);
    const auto alice = db.FindUser("alice");
    ASSERT_TRUE(alice);
    EXPECT_EQ(alice->role, Role::kOperator);
    EXPECT_TRUE(VerifyPassword(alice->password_hash, "alice-secret-9"));
    db.SetPassword("alice", "alice-new-pass", HashCost::kMinimum);
    EXPECT_FALSE(VerifyPassword(db.FindUser("alice")->password_hash, "alice-secret-9"));
    EXPECT_THROW(db.SetPassword("nobody", "whatever-pass", HashCost::kMinimum), InputError);
    db.Record({0, "", 0, "alice", "operator", "127.0.0.1:5", "axis_enable", "m1/X", "disable", "ok"});
    const auto log = db.RecentAudit(10);
    ASSERT_EQ(log.size(), 1u);
    EXPECT_EQ(log[0].action, "axis_enable");
    EXPECT_FALSE(log[0].time_utc.empty());
    EXPECT_TRUE(db.RemoveUser("alice"));
    EXPECT_FALSE(db.RemoveUser("alice"));
  }
  std::ifstream in(p, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(bytes.find("alice-secret-9"), std::string::npos);
  EXPECT_EQ(bytes.find("alice-new-pass"), std::string::npos);
  fs::remove(p);
}

TEST(AccessDb, RefusesAFileThatIsNotItsOwn) {
  const fs::path text = TempFile("text.db");
  std::ofstream(text) << "hello, not a database at all, just some text that is long enough\n";
  EXPECT_THROW(AccessDb(text.string()), InputError);
  fs::remove(text);
}

TEST(SessionStore, IdleAndAbsoluteTimeoutsEndSessions) {
  SessionStore store(SessionTimeouts{10, 100, 1000});
  const Session s = store.Create("u", Role::kViewer, "h", 0);
  EXPECT_NE(s.id, s.csrf_token);
  EXPECT_TRUE(store.Touch(s.id, 9));
  EXPECT_TRUE(store.Touch(s.id, 18));   // idle clock restarted at 9
  EXPECT_FALSE(store.Touch(s.id, 29));  // 11 s idle
  const Session t = store.Create("u", Role::kViewer, "h", 0);
  for (double now = 5; now < 100; now += 5) EXPECT_TRUE(store.Touch(t.id, now)) << now;
  EXPECT_FALSE(store.Touch(t.id, 101)) << "absolute timeout despite activity";
  EXPECT_FALSE(store.Touch("", 0));
  const Session a = store.Create("x", Role::kAdmin, "h", 0), b = store.Create("x", Role::kAdmin, "h", 0);
  store.RemoveUser("x");
  EXPECT_FALSE(store.Touch(a.id, 1));
  EXPECT_FALSE(store.Touch(b.id, 1));
}

TEST(SessionStore, MemoryIsBounded) {
  SessionStore store(SessionTimeouts{1e9, 1e9, 50});
  for (int i = 0; i < 200; ++i) store.Create("u", Role::kViewer, "h", i);
  EXPECT_LE(store.Count(), 50u);
}

TEST(LoginLimiter, LocksANameAfterNFailuresThenLetsItTryAgain) {
  LoginLimiter lim(LoginLimits{3, 60, 30, 10, 1000});
  EXPECT_EQ(lim.LockedForS("u", "a", 0), 0);
  lim.Reserve("u", "a", 0).Failed(0);
  lim.Reserve("u", "a", 1).Failed(1);
  EXPECT_EQ(lim.LockedForS("u", "a", 1), 0);
  lim.Reserve("u", "a", 2).Failed(2);
  EXPECT_NEAR(lim.LockedForS("u", "a", 2), 30, 1e-9);
  EXPECT_EQ(lim.LockedForS("v", "b", 2), 0) << "another name from another address";
  EXPECT_EQ(lim.LockedForS("u", "a", 33), 0);
  // Failures spread beyond the window do not add up.
  LoginLimiter slow(LoginLimits{3, 60, 30, 10, 1000});
  for (int i = 0; i < 6; ++i) slow.Reserve("u", "a", i * 61.0).Failed(i * 61.0);
  EXPECT_EQ(slow.LockedForS("u", "a", 400), 0);
}

TEST(LoginLimiter, OneAddressTryingManyNamesIsLockedToo) {
  LoginLimiter lim(LoginLimits{5, 60, 30, 4, 1000});
  for (int i = 0; i < 4; ++i) lim.Reserve("name" + std::to_string(i), "10.0.0.9", i).Failed(i);
  EXPECT_GT(lim.LockedForS("fresh-name", "10.0.0.9", 5), 0);
  EXPECT_EQ(lim.LockedForS("fresh-name", "10.0.0.10", 5), 0);
}

TEST(LoginLimiter, AttemptsInProgressCountBeforeTheirPasswordIsChecked) {
  LoginLimiter lim(LoginLimits{3, 60, 30, 10, 1000, 8});
  std::vector<LoginLimiter::Attempt> checking;
  for (int i = 0; i < 3; ++i) checking.push_back(lim.Reserve("u", "a", 0));
  for (const auto& a : checking) EXPECT_TRUE(a.granted());
  auto fourth = lim.Reserve("u", "a", 0);
  EXPECT_EQ(fourth.verdict(), LoginLimiter::Verdict::kPending) << "three guesses are being checked already";
  EXPECT_GT(fourth.retry_after_s(), 0);
  for (auto& a : checking) a.Failed(1);
  EXPECT_NEAR(lim.LockedForS("u", "a", 1), 30, 1e-9);
  EXPECT_EQ(lim.hashes_in_flight(), 0);
  // A success among them clears the name; an attempt dropped unfinished counts as failed.
  LoginLimiter ok(LoginLimits{3, 60, 30, 10, 1000, 8});
  { auto dropped = ok.Reserve("u", "a", 0); }
  ok.Reserve("u", "a", 0).Failed(0);
  ok.Reserve("u", "a", 0).Succeeded();
  EXPECT_TRUE(ok.Reserve("u", "a", 0).granted());
  LoginLimiter drop(LoginLimits{2, 60, 30, 10, 1000, 8});
  { auto dropped = drop.Reserve("u", "a", 0); }
  drop.Reserve("u", "a", 0).Failed(0);
  EXPECT_GT(drop.LockedForS("u", "a", 0), 0);
}

TEST(LoginLimiter, PasswordChecksInFlightAreBounded) {
  LoginLimiter lim(LoginLimits{5, 60, 30, 20, 1000, 2});
  auto a = lim.Reserve("u1", "a", 0), b = lim.Reserve("u2", "a", 0);
  EXPECT_TRUE(a.granted() && b.granted());
  auto c = lim.Reserve("u3", "a", 0);
  EXPECT_EQ(c.verdict(), LoginLimiter::Verdict::kBusy);
  EXPECT_EQ(c.retry_after_s(), 1);
  a.Failed(0);
  EXPECT_TRUE(lim.Reserve("u3", "a", 0).granted()) << "a finished check frees its place";
}

TEST(AlarmBook, OpensClosesAndAcknowledgesOnce) {
  AlarmBook book(100);
  book.Update("m1", {"sensor_held"}, 10);
  book.Update("m2", {"link_read", "no_model"}, 11);
  book.Update("m1", {"sensor_held"}, 12);  // still the same alarm
  auto list = book.Newest(10);
  ASSERT_EQ(list.size(), 3u);
  book.Update("m1", {}, 13);
  list = book.Newest(10);
  int active = 0;
  for (const auto& a : list) active += a.active;
  EXPECT_EQ(active, 2);
  EXPECT_FALSE(list.back().active) << "cleared alarms come after the active ones";
  const std::string id = list[0].id;
  book.Acknowledge(id, "op", 20);
  EXPECT_THROW(book.Acknowledge(id, "op", 21), BackendError);
  EXPECT_THROW(book.Acknowledge("m9:1", "op", 21), BackendError);
  // A returning alarm is a new entry.
  book.Update("m1", {"sensor_held"}, 30);
  EXPECT_EQ(book.Newest(10).size(), 4u);
}

TEST(AlarmBook, ForgetsOldClearedAlarmsBeyondItsCapacity) {
  AlarmBook book(10);
  for (int i = 0; i < 100; ++i) {
    book.Update("m", {"a"}, i);
    book.Update("m", {}, i + 0.5);
  }
  EXPECT_LE(book.Newest(1000).size(), 10u);
}

TEST(LiveRing, GivesWhatIsNewerThanTheClientsSequence) {
  LiveRing ring(5);
  for (int i = 0; i < 8; ++i) ring.Push(LiveSample{0, static_cast<double>(i), {1.0 * i}, {}});
  EXPECT_EQ(ring.last_sequence(), 8u);
  std::vector<LiveSample> out;
  ring.CopyAfter(0, 100, out);
  ASSERT_EQ(out.size(), 5u);
  EXPECT_EQ(out.front().sequence, 4u);
  ring.CopyAfter(6, 100, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].sequence, 7u);
  ring.CopyAfter(8, 100, out);
  EXPECT_TRUE(out.empty());
  ring.CopyAfter(0, 2, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].sequence, 8u) << "the newest when limited";
}

TEST(MachineQuery, FiltersSortsAndPages) {
  std::vector<MachineSummary> ms;
  for (int i = 0; i < 30; ++i) {
    MachineSummary m;
    m.id = "k" + std::to_string(100 + i);
    m.name = i % 2 ? "lathe" : "mill";
    m.connected = i % 7 != 0;
    if (i % 5 == 0) m.alarms = {"sensor_held"};
    m.channels = {{"a", i == 3 ? std::nan("") : 20.0 + (i * 37 % 30), "ok"}};
    m.axes = {{.name = "X", .enabled = true, .state = "full", .position_mm = 0, .correction_um = -1.0 * i}};
    ms.push_back(m);
  }
  auto page = ApplyQuery(ms, MachineQuery{"LATHE", "id", true, false, false, 0, 5});
  EXPECT_EQ(page.total, 30u);
  EXPECT_EQ(page.matched, 15u);
  ASSERT_EQ(page.machines.size(), 5u);
  EXPECT_EQ(page.machines[0].id, "k129");
  page = ApplyQuery(ms, MachineQuery{"sensor", "id", false, true, false, 0, 100});
  EXPECT_EQ(page.matched, 6u);
  page = ApplyQuery(ms, MachineQuery{"", "max_correction", true, false, false, 0, 1});
  EXPECT_EQ(page.machines[0].id, "k129");
  page = ApplyQuery(ms, MachineQuery{"", "max_temp", true, false, false, 0, 100});
  EXPECT_EQ(page.machines.back().id, "k103") << "an unknown temperature sorts last";
  page = ApplyQuery(ms, MachineQuery{"", "id", false, false, true, 28, 100});
  EXPECT_EQ(page.matched, 5u);
  EXPECT_TRUE(page.machines.empty()) << "an offset past the end gives an empty page";
  EXPECT_THROW(ApplyQuery(ms, MachineQuery{"", "bogus"}), std::invalid_argument);
}

}  // namespace
}  // namespace trueaxis::web
