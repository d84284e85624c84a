// Snapshots + journal: a restarted service equals the one that crashed.
#include <gtest/gtest.h>

#include <fstream>
#include <type_traits>

#include "service/journal.hpp"
#include "service/journal_entry.hpp"
#include "service/snapshot_metadata.hpp"
#include "service_test_helpers.hpp"
#include "socc/rpc/safe_decode.hpp"

namespace socc::service {
namespace {

using test::scan;

struct Files {
  test::TempDir dir;
  Durability durability() const { return {dir.path() / "map.snap", dir.path() / "journal.lcmlog"}; }
};

TEST(Durability, SnapshotPlusJournalReplayEqualsLiveMap) {
  Files files;
  std::vector<std::uint8_t> live_content;
  std::int64_t live_integrations = 0;
  {
    MapService live(test::smallConfig(files.dir.path()));
    live.openDurability(files.durability(), std::nullopt);
    for (int seq = 1; seq <= 3; ++seq) live.integrate(scan("robot1", seq, 0.3 * seq));
    live.checkpoint();  // snapshot covers 3, journal restarts
    for (int seq = 4; seq <= 6; ++seq) live.integrate(scan("robot1", seq, 0.3 * seq));
    live.integrate(scan("robot2", 1, -2.0));
    live_content = test::content(live.getChunk(test::everything()));
    live_integrations = live.integrations();
    // No clean shutdown: the object is dropped like a killed process (nothing else written).
  }
  EXPECT_EQ(Journal::read(files.dir.path() / "journal.lcmlog").requests.size(), 4u);

  MapService restored(test::smallConfig(files.dir.path()));
  restored.openDurability(files.durability(), files.dir.path() / "map.snap");
  EXPECT_EQ(test::content(restored.getChunk(test::everything())), live_content);
  EXPECT_EQ(restored.integrations(), live_integrations);
  ASSERT_NE(restored.robots().find("robot1"), nullptr);
  EXPECT_EQ(restored.robots().find("robot1")->last_seq, 6);
  EXPECT_TRUE(restored.integrate(scan("robot1", 6)).duplicate) << "a client retry after restart";
  EXPECT_FALSE(restored.integrate(scan("robot1", 7)).duplicate);
}

TEST(Durability, AFoundingScanIsReplayedAndTheMapStaysFounded) {
  Files files;
  std::vector<std::uint8_t> live_content;
  {
    MapService live(test::smallConfig(files.dir.path()));
    live.openDurability(files.durability(), std::nullopt);
    integrate_request_t founding = scan("founder", 1);
    founding.map_epoch = integrate_request_t::FOUND_MAP;
    ASSERT_EQ(live.integrate(founding).header.status, +reply_header_t::OK);
    live.integrate(scan("founder", 2, 0.4));
    live_content = test::content(live.getChunk(test::everything()));
  }  // killed: the founding scan is in the journal only
  MapService restored(test::smallConfig(files.dir.path()));
  restored.openDurability(files.durability(), std::nullopt);
  EXPECT_EQ(test::content(restored.getChunk(test::everything())), live_content);
  integrate_request_t late = scan("late", 1, 2.0);
  late.map_epoch = integrate_request_t::FOUND_MAP;
  EXPECT_EQ(restored.integrate(late).header.status, +reply_header_t::FAILED_PRECONDITION);
}

TEST(Durability, JournalEntriesAlreadyInTheSnapshotAreSkipped) {
  // Crash between writing the snapshot and restarting the journal: both hold scans 1..2.
  Files files;
  MapService live(test::smallConfig(files.dir.path()));
  live.openDurability(files.durability(), std::nullopt);
  live.integrate(scan("robot1", 1));
  live.integrate(scan("robot1", 2, 1.0));
  live.saveSnapshot(files.dir.path() / "map.snap");
  const auto content = test::content(live.getChunk(test::everything()));

  MapService restored(test::smallConfig(files.dir.path()));
  restored.openDurability(files.durability(), files.dir.path() / "map.snap");
  EXPECT_EQ(restored.integrations(), 2);
  EXPECT_EQ(test::content(restored.getChunk(test::everything())), content);
}

TEST(Durability, TornLastJournalEventIsDropped) {
  Files files;
  std::vector<std::uint8_t> content_after_two;
  {
    MapService live(test::smallConfig(files.dir.path()));
    live.openDurability(files.durability(), std::nullopt);
    live.integrate(scan("robot1", 1));
    live.integrate(scan("robot1", 2, 1.0));
    content_after_two = test::content(live.getChunk(test::everything()));
    live.integrate(scan("robot1", 3, 2.0));
  }
  const auto journal = files.dir.path() / "journal.lcmlog";
  std::filesystem::resize_file(journal, std::filesystem::file_size(journal) - 100);

  MapService restored(test::smallConfig(files.dir.path()));
  restored.openDurability(files.durability(), files.dir.path() / "map.snap");
  EXPECT_EQ(restored.integrations(), 2);
  EXPECT_EQ(test::content(restored.getChunk(test::everything())), content_after_two);
}

TEST(Durability, CorruptSnapshotIsReportedAndNotLoaded) {
  Files files;
  {
    MapService live(test::smallConfig(files.dir.path()));
    live.integrate(scan("robot1", 1));
    live.saveSnapshot(files.dir.path() / "map.snap");
  }
  {
    std::fstream f(files.dir.path() / "map.snap", std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(200);
    f.put('\x5a').put('\x17');
  }
  MapService service(test::smallConfig(files.dir.path()));
  service.integrate(scan("robot9", 1));
  const auto content = test::content(service.getChunk(test::everything()));
  EXPECT_THROW(service.loadSnapshot(files.dir.path() / "map.snap"), std::runtime_error);
  EXPECT_EQ(test::content(service.getChunk(test::everything())), content);
  EXPECT_NE(service.robots().find("robot9"), nullptr);

  map_command_request_t load{};
  load.command = map_command_request_t::LOAD;
  load.path = "map.snap";
  EXPECT_EQ(service.command(load).header.status, +reply_header_t::INVALID_ARGUMENT);
  EXPECT_EQ(test::content(service.getChunk(test::everything())), content);
}

TEST(Durability, JournalThatDoesNotContinueTheSnapshotIsRefused) {
  Files files;
  {
    MapService live(test::smallConfig(files.dir.path()));
    live.openDurability(files.durability(), std::nullopt);
    live.integrate(scan("robot1", 1));
    live.checkpoint();
    live.integrate(scan("robot1", 2, 1.0));
  }
  MapService without_snapshot(test::smallConfig(files.dir.path()));
  EXPECT_THROW(without_snapshot.openDurability(files.durability(), std::nullopt),
               std::runtime_error);
}

TEST(Durability, JournalKeepsTheReceivedBytes) {
  // The router passes the bytes it decoded; they are journaled as they are (no re-encode).
  Files files;
  std::vector<std::uint8_t> content;
  std::vector<std::vector<std::uint8_t>> sent;
  {
    MapService live(test::smallConfig(files.dir.path()));
    live.openDurability(files.durability(), std::nullopt);
    for (int seq = 1; seq <= 2; ++seq) {
      sent.push_back(test::encode(scan("robot1", seq, 0.5 * seq)));
      const auto request = rpc::safeDecode<integrate_request_t>(
          sent.back().data(), static_cast<int>(sent.back().size()));
      ASSERT_TRUE(request);
      ASSERT_FALSE(live.integrate(*request, sent.back().data(), sent.back().size()).duplicate);
    }
    live.integrate(scan("robot2", 1, -1.0));  // in-process: re-encoded
    content = test::content(live.getChunk(test::everything()));
  }
  const JournalContents journal = Journal::read(files.dir.path() / "journal.lcmlog");
  ASSERT_EQ(journal.requests.size(), 3u);
  EXPECT_EQ(journal.requests[0], sent[0]);
  EXPECT_EQ(journal.requests[1], sent[1]);
  EXPECT_EQ(journal.requests[2], test::encode(scan("robot2", 1, -1.0)));

  MapService restored(test::smallConfig(files.dir.path()));
  restored.openDurability(files.durability(), files.dir.path() / "map.snap");
  EXPECT_EQ(restored.integrations(), 3);
  EXPECT_EQ(test::content(restored.getChunk(test::everything())), content);
}

// The request as an older server encoded it: before the gravity fields (v1, docs/lcm.md
// "Gravity reference") or before map_epoch (v2, docs/lcm.md "Which frame a pose is in").
template <class Older>
Older olderForm(const integrate_request_t& r) {
  Older old{};
  old.header = r.header;
  old.seq = r.seq;
  old.scan_utime = r.scan_utime;
  old.sensor_pose = r.sensor_pose;
  old.num_points = r.num_points;
  old.xyz_resolution = r.xyz_resolution;
  old.xyz = r.xyz;
  old.num_labels = r.num_labels;
  old.label = r.label;
  old.num_times = r.num_times;
  old.time = r.time;
  if constexpr (std::is_same_v<Older, integrate_request_v2_t>) {
    for (int i = 0; i < 3; ++i) old.gravity_up[i] = r.gravity_up[i];
    old.gravity_sigma = r.gravity_sigma;
  }
  return old;
}

// integrate_request_t's fingerprint before the fields (lcm-gen 1.3.1 on the .lcm of the commit
// before them): a journal of such a server holds exactly these bytes, which the journal reader
// tells apart from the others by it.
template <class Older>
void expectTheOlderFormDecodes(std::uint64_t fingerprint) {
  EXPECT_EQ(static_cast<std::uint64_t>(Older::getHash()), fingerprint);
  EXPECT_NE(Older::getHash(), integrate_request_t::getHash());
  const integrate_request_t now = scan("robot1", 1);  // map_epoch 0, no gravity reference
  const auto now_bytes = test::encode(now);
  const auto old_bytes = test::encode(olderForm<Older>(now));
  EXPECT_FALSE(rpc::safeDecode<Older>(now_bytes.data(), static_cast<int>(now_bytes.size())));
  EXPECT_FALSE(
      rpc::safeDecode<integrate_request_t>(old_bytes.data(), static_cast<int>(old_bytes.size())));
  const auto decoded = decodeJournalEntry(old_bytes.data(), old_bytes.size());
  ASSERT_TRUE(decoded);
  EXPECT_EQ(decoded->gravity_sigma, 0.f);
  EXPECT_EQ(decoded->map_epoch, 0);
  EXPECT_EQ(test::encode(*decoded), now_bytes);  // the same request
  EXPECT_FALSE(decodeJournalEntry(old_bytes.data(), old_bytes.size() - 1));
}

TEST(Durability, OlderRequestTypesHaveTheOldFingerprints) {
  expectTheOlderFormDecodes<integrate_request_v1_t>(0x818a59ffcd162226ull);  // pre-gravity
  expectTheOlderFormDecodes<integrate_request_v2_t>(0x9444d59e41a31640ull);  // pre-epoch
}

TEST(Durability, APreEpochEntryKeepsItsGravityReference) {
  integrate_request_t now = scan("robot1", 1);
  now.gravity_up[2] = 1.f;
  now.gravity_sigma = 0.02f;
  const auto old_bytes = test::encode(olderForm<integrate_request_v2_t>(now));
  const auto decoded = decodeJournalEntry(old_bytes.data(), old_bytes.size());
  ASSERT_TRUE(decoded);
  EXPECT_EQ(test::encode(*decoded), test::encode(now));
}

// A journal written by an older server: its entries are the old encoding.
template <class Older>
void expectAnOlderJournalReplays() {
  Files files;
  std::vector<std::uint8_t> content;
  {
    MapService live(test::smallConfig(files.dir.path()));
    Journal old_server(files.dir.path() / "journal.lcmlog", 0);
    for (int seq = 1; seq <= 3; ++seq) {
      const integrate_request_t request = scan("robot1", seq, 0.4 * seq);
      const auto bytes = test::encode(olderForm<Older>(request));
      old_server.append(bytes.data(), bytes.size());
      live.integrate(request);
    }
    content = test::content(live.getChunk(test::everything()));
  }
  MapService restored(test::smallConfig(files.dir.path()));
  restored.openDurability(files.durability(), std::nullopt);
  EXPECT_EQ(restored.integrations(), 3);
  EXPECT_EQ(test::content(restored.getChunk(test::everything())), content);
  EXPECT_EQ(restored.robots().find("robot1")->last_seq, 3);
}

TEST(Durability, OlderJournalsReplay) {
  expectAnOlderJournalReplays<integrate_request_v1_t>();
  expectAnOlderJournalReplays<integrate_request_v2_t>();
}

TEST(Durability, ClearAndLoadRestartTheJournal) {
  Files files;
  MapService live(test::smallConfig(files.dir.path()));
  live.openDurability(files.durability(), std::nullopt);
  live.integrate(scan("robot1", 1));
  map_command_request_t clear{};
  clear.command = map_command_request_t::CLEAR;
  ASSERT_EQ(live.command(clear).header.status, +reply_header_t::OK);
  live.integrate(scan("robot1", 2, 1.0));
  const auto content = test::content(live.getChunk(test::everything()));

  MapService restored(test::smallConfig(files.dir.path()));
  restored.openDurability(files.durability(), files.dir.path() / "map.snap");
  EXPECT_EQ(test::content(restored.getChunk(test::everything())), content);
}

TEST(Durability, MetadataRoundTripAndGarbage) {
  SnapshotMetadata metadata;
  metadata.journal_sequence = 42;
  robot_state_t state{};
  state.robot_id = "r";
  state.last_seq = 7;
  metadata.robots.push_back(state);
  const auto decoded = decodeSnapshotMetadata(encodeSnapshotMetadata(metadata));
  ASSERT_TRUE(decoded);
  EXPECT_EQ(decoded->journal_sequence, 42);
  ASSERT_EQ(decoded->robots.size(), 1u);
  EXPECT_EQ(decoded->robots[0].last_seq, 7);
  EXPECT_TRUE(decoded->histories.empty());
  EXPECT_FALSE(decodeSnapshotMetadata("not an lcm message"));
  EXPECT_TRUE(decodeSnapshotMetadata(""));

  // With pose histories (and auth counters after them).
  pose_history_t h{};
  h.robot_id = "r";
  h.num_poses = 2;
  h.seq = {6, 7};
  h.scan_utime = {600, 700};
  h.translation.assign(3, {1.0, 2.0});
  h.quaternion.assign(4, {0.5, 0.5});
  metadata.histories.push_back(h);
  metadata.auth_counters["client"] = 3;
  const std::string blob = encodeSnapshotMetadata(metadata);
  const auto full = decodeSnapshotMetadata(blob);
  ASSERT_TRUE(full);
  ASSERT_EQ(full->histories.size(), 1u);
  EXPECT_EQ(full->histories[0].seq, h.seq);
  EXPECT_EQ(full->histories[0].translation[2], h.translation[2]);
  EXPECT_EQ(full->auth_counters.at("client"), 3);
  // Damaged: every truncation of the binary part is refused, never misread.
  const std::size_t binary = blob.find("\nSOCC-AUTH-COUNTERS");
  for (std::size_t n = 1; n < binary; n += 7) {
    const auto cut = decodeSnapshotMetadata(blob.substr(0, n) + blob.substr(binary));
    EXPECT_TRUE(!cut || cut->histories.empty()) << n;
  }
}

std::string fromHex(const std::string& hex) {
  std::string bytes;
  for (std::size_t i = 0; i + 1 < hex.size(); i += 2)
    bytes.push_back(static_cast<char>(std::stoi(hex.substr(i, 2), nullptr, 16)));
  return bytes;
}

TEST(Durability, MetadataWithoutTrackingFieldsStillLoads) {
  // The metadata of a snapshot written before robot_state_t had the tracking fields (map_stats_t
  // encoded by the types of then): car1 seq 6 at (1.5, -2, 0.25), car2 seq 3 at (-4, -2, 0.25).
  const std::string old_blob = fromHex(
      "de2b7c79f2ca2e59000000000000000000000000000000000000000000000000"
      "0000000000000000000000000000000000000000000000000000000000000000"
      "0000000000000000000000000000000700000000000000000000000000000000"
      "0000000000000000000000000000000000000002000000056361723100000000"
      "000000000600000000000927c000000000000000073ff8000000000000c00000"
      "00000000003fd00000000000003ff00000000000000000000000000000000000"
      "0000000000000000000000000000000005636172320000000000000000030000"
      "0000000493e00000000000000002c010000000000000c0000000000000003fd0"
      "0000000000003ff0000000000000000000000000000000000000000000000000"
      "000000000000");
  const auto decoded = decodeSnapshotMetadata(old_blob);
  ASSERT_TRUE(decoded);
  EXPECT_EQ(decoded->journal_sequence, 7);
  ASSERT_EQ(decoded->robots.size(), 2u);
  const robot_state_t& car1 = decoded->robots[0];
  EXPECT_EQ(car1.robot_id, "car1");
  EXPECT_EQ(car1.last_seq, 6);
  EXPECT_EQ(car1.last_scan_utime, 600000);
  EXPECT_EQ(car1.integrations, 7);
  EXPECT_EQ(car1.last_pose.translation[0], 1.5);
  EXPECT_EQ(car1.last_pose.translation[2], 0.25);
  EXPECT_EQ(car1.last_pose.quaternion[0], 1.0);
  EXPECT_EQ(car1.tracking_state, +robot_status_request_t::TRACKING);
  EXPECT_EQ(decoded->robots[1].robot_id, "car2");
  EXPECT_EQ(decoded->robots[1].last_pose.translation[0], -4.0);
  // Followed by the newer sections, and damaged: truncations are refused, never misread.
  SnapshotMetadata sections;
  sections.auth_counters["client"] = 3;
  const std::string counters = encodeSnapshotMetadata(sections);
  const std::string tail = counters.substr(counters.find("\nSOCC-AUTH-COUNTERS"));
  const auto with_counters = decodeSnapshotMetadata(old_blob + tail);
  ASSERT_TRUE(with_counters);
  EXPECT_EQ(with_counters->auth_counters.at("client"), 3);
  for (std::size_t n = 1; n < old_blob.size(); n += 5)
    EXPECT_FALSE(decodeSnapshotMetadata(old_blob.substr(0, n))) << n;
}

TEST(Durability, MetadataWithoutServerVersionStillLoads) {
  // The metadata of a snapshot written before map_stats_t had server_version (encoded by the
  // types of then): car1 seq 8 at (2.5, 0, 0), LOST ("lost" at seq 8), 3 refused, journal 9.
  const std::string old_blob = fromHex(
      "aac20648c2eb2350000000000000000000000000000000000000000000000000"
      "0000000000000000000000000000000000000000000000000000000000000000"
      "0000000000000000000000000000000900000000000000000000000000000000"
      "0000000000000000000000000000000000000001000000056361723100000000"
      "000000000800000000000c350000000000000000094004000000000000000000"
      "000000000000000000000000003ff00000000000000000000000000000000000"
      "0000000000000000000000000002000000056c6f737400000000000000000800"
      "000000000c35000000000000000003");
  const auto decoded = decodeSnapshotMetadata(old_blob);
  ASSERT_TRUE(decoded);
  EXPECT_EQ(decoded->journal_sequence, 9);
  ASSERT_EQ(decoded->robots.size(), 1u);
  const robot_state_t& car1 = decoded->robots[0];
  EXPECT_EQ(car1.robot_id, "car1");
  EXPECT_EQ(car1.last_seq, 8);
  EXPECT_EQ(car1.last_pose.translation[0], 2.5);
  EXPECT_EQ(car1.tracking_state, +robot_status_request_t::LOST);
  EXPECT_EQ(car1.tracking_reason, "lost");
  EXPECT_EQ(car1.refused_integrations, 3);
  for (std::size_t n = 1; n < old_blob.size(); n += 5)
    EXPECT_FALSE(decodeSnapshotMetadata(old_blob.substr(0, n))) << n;
}

}  // namespace
}  // namespace socc::service
