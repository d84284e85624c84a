// --journal-sync: when journal entries reach stable storage, and the group commit of the router
// (batch: INTEGRATE replies wait for one sync of their group). Also: every mode survives
// kill -9 (the entry reached the OS before append returned).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <lcm/lcm-cpp.hpp>
#include <vector>

#include "service/journal.hpp"
#include "service/request_gate.hpp"
#include "service/request_router.hpp"
#include "service_test_helpers.hpp"

namespace socc::service {
namespace {

using test::scan;

const std::vector<std::uint8_t> kEntry(1000, 0x42);

void appendEntries(Journal& journal, int n) {
  for (int i = 0; i < n; ++i) journal.append(kEntry.data(), kEntry.size());
}

TEST(JournalSync, NamesRoundTrip) {
  for (const auto sync : {JournalSync::kNone, JournalSync::kBatch, JournalSync::kAlways})
    EXPECT_EQ(parseJournalSync(journalSyncName(sync)), sync);
  EXPECT_FALSE(parseJournalSync("fsync"));
  EXPECT_FALSE(parseJournalSync(""));
}

TEST(JournalSync, AlwaysSyncsEveryEntry) {
  test::TempDir dir;
  Journal journal(dir.path() / "j.lcmlog", 0, JournalSync::kAlways);
  appendEntries(journal, 3);
  EXPECT_EQ(journal.syncs(), 3);
  journal.sync();  // nothing pending
  EXPECT_EQ(journal.syncs(), 3);
}

TEST(JournalSync, BatchSyncsOncePerGroup) {
  test::TempDir dir;
  Journal journal(dir.path() / "j.lcmlog", 0, JournalSync::kBatch);
  appendEntries(journal, 5);
  EXPECT_EQ(journal.syncs(), 0);
  journal.sync();
  journal.sync();
  EXPECT_EQ(journal.syncs(), 1);
  appendEntries(journal, 1);
  journal.sync();
  EXPECT_EQ(journal.syncs(), 2);
}

TEST(JournalSync, NoneNeverSyncs) {
  test::TempDir dir;
  Journal journal(dir.path() / "j.lcmlog", 0, JournalSync::kNone);
  appendEntries(journal, 3);
  journal.sync();
  EXPECT_EQ(journal.syncs(), 0);
  EXPECT_EQ(Journal::read(dir.path() / "j.lcmlog").requests.size(), 3u);
}

// A child process appends n entries with the weakest mode and is killed with SIGKILL while
// the journal is still open: every entry it appended is in the file.
TEST(JournalSync, EveryModeSurvivesKill9) {
  test::TempDir dir;
  const auto file = dir.path() / "j.lcmlog";
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    Journal journal(file, 7, JournalSync::kNone);
    appendEntries(journal, 4);
    const char done = 1;
    (void)!::write(ready[1], &done, 1);
    ::pause();  // killed here, journal open
    ::_exit(0);
  }
  char done = 0;
  ASSERT_EQ(::read(ready[0], &done, 1), 1);
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  ::close(ready[0]);
  ::close(ready[1]);
  ASSERT_TRUE(WIFSIGNALED(status));
  const JournalContents contents = Journal::read(file);
  EXPECT_EQ(contents.base_sequence, 7);
  ASSERT_EQ(contents.requests.size(), 4u);
  EXPECT_EQ(contents.requests[3], kEntry);
}

// The real router on memq:// over a service journaling with the given mode.
class SyncHarness {
 public:
  explicit SyncHarness(JournalSync sync) : service(test::smallConfig(dir.path())) {
    Durability durability{dir.path() / "map.snap", dir.path() / "journal.lcmlog"};
    durability.show_progress = false;
    durability.journal_sync = sync;
    service.openDurability(durability, std::nullopt);
    router.emplace(lcm, service, gate, false);
    lcm_subscribe(lcm.getUnderlyingLCM(), "SOCC/.*/REP/.*", &SyncHarness::onReply, this);
  }

  void send(const integrate_request_t& request) {
    const auto bytes = test::encode(request);
    lcm.publish(channels::request(channels::kIntegrate), bytes.data(),
                static_cast<unsigned>(bytes.size()));
    while (lcm.handleTimeout(0) > 0) {
    }
  }
  /// Replies published so far (commit() publishes through the same LCM: handle them too).
  int replies() {
    while (lcm.handleTimeout(0) > 0) {
    }
    return received;
  }

  test::TempDir dir;
  lcm::LCM lcm{"memq://"};
  MapService service;
  AllowAllGate gate;
  std::optional<RequestRouter> router;
  int received = 0;

 private:
  static void onReply(const lcm_recv_buf_t*, const char*, void* self) {
    ++static_cast<SyncHarness*>(self)->received;
  }
};

TEST(JournalSync, BatchAcknowledgesIntegratesAfterOneSync) {
  SyncHarness h(JournalSync::kBatch);
  h.send(scan("robot1", 1));
  h.send(scan("robot2", 1, 1.0));
  EXPECT_EQ(h.service.integrations(), 2) << "applied at once";
  EXPECT_EQ(h.replies(), 0) << "not acknowledged before the sync";
  EXPECT_EQ(h.router->deferredReplies(), 2u);
  h.router->commit();
  EXPECT_EQ(h.replies(), 2);
  EXPECT_EQ(h.service.journal()->syncs(), 1) << "one sync for the group";
  h.router->commit();  // nothing pending: no sync
  EXPECT_EQ(h.service.journal()->syncs(), 1);
}

TEST(JournalSync, RefusedIntegratesAreAnsweredAtOnce) {
  SyncHarness h(JournalSync::kBatch);
  integrate_request_t wrong_channel = scan("robot1", 1);
  wrong_channel.header.reply_channel = channels::reply(channels::kIntegrate, "robot1") + "x";
  h.send(wrong_channel);
  EXPECT_EQ(h.replies(), 1);
  EXPECT_EQ(h.router->deferredReplies(), 0u);
}

TEST(JournalSync, AlwaysAndNoneAcknowledgeAtOnce) {
  for (const auto sync : {JournalSync::kAlways, JournalSync::kNone}) {
    SyncHarness h(sync);
    h.send(scan("robot1", 1));
    EXPECT_EQ(h.replies(), 1) << journalSyncName(sync);
    EXPECT_EQ(h.service.journal()->syncs(), sync == JournalSync::kAlways ? 1 : 0);
  }
}

}  // namespace
}  // namespace socc::service
