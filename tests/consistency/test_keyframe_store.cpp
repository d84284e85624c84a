// The consistency store (docs/consistency.md, "Durability"): records read back as written, a
// torn or corrupt tail is dropped with a message (never a crash), a bad header is a clear
// error, and a service started from the store holds the same keyframes and graph.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>

#include "../temp_dir.hpp"
#include "consistency_restore.hpp"
#include "consistency_service.hpp"
#include "keyframe_store.hpp"

namespace socc::consistency {
namespace {

using StoreDir = socc::testing::TempDir;

Eigen::Isometry3d poseAt(double x, double yaw) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, 0.5 * x, 0.1);
  pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return pose;
}

// A street of two walls and a road with posts, seen from the sensor at x along the street.
LabeledCloud streetScan(double x) {
  LabeledCloud cloud;
  for (int i = -200; i <= 200; ++i) {
    const float along = 0.1f * static_cast<float>(i);
    for (int h = 0; h < 8; ++h) {
      cloud.points.emplace_back(along, 6.0f, 0.4f * static_cast<float>(h) - 1.0f);
      cloud.points.emplace_back(along, -6.0f, 0.4f * static_cast<float>(h) - 1.0f);
    }
    cloud.points.emplace_back(along, 0.0f, -1.7f);
    if (std::fmod(static_cast<double>(along) + x, 7.0) < 0.1)
      for (int h = 0; h < 10; ++h) cloud.points.emplace_back(along, 4.0f, 0.2f * h - 1.5f);
  }
  cloud.labels.assign(cloud.points.size(), 1);
  return cloud;
}

StoredKeyframe sampleKeyframe(int id) {
  StoredKeyframe k;
  k.robot = "car";
  k.keyframe.id = id;
  k.keyframe.robot_kf = id;
  k.keyframe.seq = 10 * id;
  k.keyframe.utime = 1000 * id;
  k.keyframe.odom_pose = poseAt(3.0 * id, 0.1 * id);
  k.keyframe.travelled = 3.0 * id;
  k.keyframe.points = {Eigen::Vector3f(1, 2, 3), Eigen::Vector3f(-4, 5, 0.5f)};
  k.keyframe.scan = compactScan(streetScan(id), 0.1);
  k.estimate = poseAt(3.0 * id + 0.01, 0.1 * id);
  if (id > 0) k.edges.push_back({id - 1, id, poseAt(3.0, 0.1), isotropicInformation(0.05, 0.01)});
  if (id == 0) k.priors.push_back({0, poseAt(0, 0), isotropicInformation(1.0, 0.05), true});
  return k;
}

void writeSample(const std::filesystem::path& file) {
  auto store = KeyframeStore::create(file, false, true);
  for (int id = 0; id < 3; ++id)
    store->add(RecordType::kKeyframe, encodeKeyframe(sampleKeyframe(id)));
  StoredClosure closure;
  closure.closure = {0, 2, poseAt(6.0, 0.2), 0.8, 0.05, true};
  closure.edge = {0, 2, poseAt(6.0, 0.2), isotropicInformation(0.1, 0.01)};
  store->add(RecordType::kClosure, encodeClosure(closure));
  // Two records in one append (as a checkpoint writes its waiting keyframes and its mark).
  store->add({{RecordType::kRebuild,
               encodeRebuild({1, {poseAt(0, 0), poseAt(3, 0)}, {{"car", poseAt(0.2, 0.01)}}})},
              {RecordType::kCheckpoint, encodeCheckpoint({7, 42, 3, 1})}});
}

TEST(KeyframeStore, RecordsReadBackAsWritten) {
  StoreDir dir;
  const auto file = dir.path() / "map.snap.consistency";
  writeSample(file);
  const StoreContents c = KeyframeStore::read(file);
  EXPECT_TRUE(c.problem.empty()) << c.problem;
  EXPECT_FALSE(c.foreign_base);
  EXPECT_EQ(c.valid_bytes, std::filesystem::file_size(file));
  ASSERT_EQ(c.keyframes.size(), 3u);
  const StoredKeyframe want = sampleKeyframe(2);
  const StoredKeyframe& got = c.keyframes[2];
  EXPECT_EQ(got.robot, "car");
  EXPECT_EQ(got.keyframe.seq, 20);
  EXPECT_EQ(got.keyframe.utime, 2000);
  EXPECT_TRUE(got.keyframe.odom_pose.isApprox(want.keyframe.odom_pose, 1e-12));
  EXPECT_TRUE(got.estimate.isApprox(want.estimate, 1e-12));
  EXPECT_EQ(got.keyframe.points, want.keyframe.points);
  EXPECT_EQ(got.keyframe.scan.xyz, want.keyframe.scan.xyz);
  EXPECT_EQ(got.keyframe.scan.labels, want.keyframe.scan.labels);
  EXPECT_EQ(got.keyframe.scan.resolution, want.keyframe.scan.resolution);
  ASSERT_EQ(got.edges.size(), 1u);
  EXPECT_EQ(got.edges[0].from, 1);
  EXPECT_TRUE(got.edges[0].information.isApprox(want.edges[0].information));
  ASSERT_EQ(c.keyframes[0].priors.size(), 1u);
  EXPECT_TRUE(c.keyframes[0].priors[0].fixed);
  ASSERT_EQ(c.closures.size(), 1u);
  EXPECT_EQ(c.closures[0].closure.to, 2);
  EXPECT_TRUE(c.closures[0].closure.by_descriptor);
  EXPECT_DOUBLE_EQ(c.closures[0].closure.fitness, 0.8);
  ASSERT_EQ(c.rebuilds.size(), 1u);
  EXPECT_EQ(c.rebuilds[0].poses.size(), 2u);
  EXPECT_TRUE(c.rebuilds[0].corrections.at("car").isApprox(poseAt(0.2, 0.01)));
  ASSERT_EQ(c.checkpoints.size(), 1u);
  EXPECT_EQ(c.checkpoints[0].map_version, 42);
  EXPECT_EQ(c.checkpoints[0].grid_serial, 1);
}

TEST(KeyframeStore, AWaitingRecordKeepsItsFormAndTheOldFormsReadAsBefore) {
  StoredWaiting cloud;
  cloud.robot = "car";
  cloud.keyframe = sampleKeyframe(1).keyframe;
  cloud.keyframe.points.clear();
  cloud.keyframe.scan = KeyframeScan();
  StoredWaiting pose_only = cloud;
  cloud.form = WaitingForm::kCloud;
  cloud.cloud = streetScan(1);
  StoredWaiting reduced = cloud;
  reduced.form = WaitingForm::kReduced;
  reduced.cloud = LabeledCloud();
  reduced.keyframe = sampleKeyframe(1).keyframe;
  // The form byte follows the keyframe's fields; then the cloud (count, 12 B a point, count,
  // 1 B a label). 0 and 1 are what stores before reduction on arrival wrote (has_cloud).
  const auto formByte = [](const std::string& payload, std::size_t points) {
    return static_cast<int>(payload[payload.size() - 17 - 13 * points]);
  };
  EXPECT_EQ(formByte(encodeWaiting(pose_only), 0), 0);
  EXPECT_EQ(formByte(encodeWaiting(cloud), cloud.cloud.size()), 1);
  EXPECT_EQ(formByte(encodeWaiting(reduced), 0), 2);
  EXPECT_EQ(decodeWaiting(encodeWaiting(pose_only)).form, WaitingForm::kPoseOnly);
  const StoredWaiting cloud_back = decodeWaiting(encodeWaiting(cloud));
  EXPECT_EQ(cloud_back.form, WaitingForm::kCloud);
  EXPECT_EQ(cloud_back.cloud.points, cloud.cloud.points);
  const StoredWaiting reduced_back = decodeWaiting(encodeWaiting(reduced));
  EXPECT_EQ(reduced_back.form, WaitingForm::kReduced);
  EXPECT_EQ(reduced_back.keyframe.points, reduced.keyframe.points);
  EXPECT_EQ(reduced_back.keyframe.scan.xyz, reduced.keyframe.scan.xyz);
  EXPECT_EQ(reduced_back.keyframe.scan.labels, reduced.keyframe.scan.labels);
  // An unknown form, or a cloud in a reduced record: a clear error.
  std::string bad = encodeWaiting(pose_only);
  bad[bad.size() - 17] = 3;
  EXPECT_THROW(decodeWaiting(bad), std::runtime_error);
  std::string mixed = encodeWaiting(cloud);
  mixed[mixed.size() - 17 - 13 * cloud.cloud.size()] = 2;
  EXPECT_THROW(decodeWaiting(mixed), std::runtime_error);
}

TEST(KeyframeStore, AnOldStoresPoseOnlyWaitingKeyframeIsRestoredAsAPose) {
  // Written before reduction on arrival: a keyframe that waited without its scan (form 0).
  StoreDir dir;
  const auto file = dir.path() / "store";
  {
    auto store = KeyframeStore::create(file, false, true);
    StoredWaiting old;
    old.robot = "car";
    old.keyframe.seq = 4;
    old.keyframe.odom_pose = poseAt(1.0, 0.0);
    store->add(RecordType::kWaiting, encodeWaiting(old));
    store->add(RecordType::kCheckpoint, encodeCheckpoint({5, 2, 1, 0}));
  }
  const StoreContents contents = KeyframeStore::read(file);
  ASSERT_EQ(contents.waiting.size(), 1u);
  EXPECT_EQ(contents.waiting[0].form, WaitingForm::kPoseOnly);
  std::string why;
  ASSERT_NE(coveringMark(contents, 5, 2, why), nullptr) << why;
  ConsistencyService restored(ConsistencyParams{}, map::MapConfig{}, {}, nullptr, &contents, 0);
  restored.flush();
  ASSERT_EQ(restored.keyframePoses().size(), 1u);
  EXPECT_EQ(restored.keyframePoses()[0].seq, 4);
  EXPECT_EQ(restored.stats().scan_bytes, sizeof(KeyframeScan));  // no scan
}

TEST(KeyframeStore, ATornOrCorruptTailIsDroppedWithAMessageAndCutOnResume) {
  StoreDir dir;
  const auto file = dir.path() / "store";
  writeSample(file);
  const std::uint64_t whole = std::filesystem::file_size(file);
  const std::uint64_t last = whole - KeyframeStore::read(file).checkpoints.size() * (13 + 28 + 4);
  // kill -9 in the middle of the last record.
  std::filesystem::resize_file(file, whole - 10);
  StoreContents c = KeyframeStore::read(file);
  EXPECT_NE(c.problem.find("dropped a torn or corrupt record at byte " + std::to_string(last)),
            std::string::npos)
      << c.problem;
  EXPECT_EQ(c.keyframes.size(), 3u);
  EXPECT_EQ(c.checkpoints.size(), 0u);
  EXPECT_EQ(c.valid_bytes, last);
  // The next writer cuts the torn bytes off and appends behind the last whole record.
  KeyframeStore::resume(file, c, false)
      ->add(RecordType::kCheckpoint, encodeCheckpoint({9, 1, 3, 0}));
  c = KeyframeStore::read(file);
  EXPECT_TRUE(c.problem.empty()) << c.problem;
  ASSERT_EQ(c.checkpoints.size(), 1u);
  EXPECT_EQ(c.checkpoints[0].journal_sequence, 9);
  // A flipped byte inside a keyframe's scan: its checksum fails; it and what follows are dropped.
  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(whole / 2));
    f.put('\x5a');
  }
  c = KeyframeStore::read(file);
  EXPECT_NE(c.problem.find("checksum mismatch"), std::string::npos) << c.problem;
  EXPECT_LT(c.keyframes.size(), 3u);
  EXPECT_TRUE(c.checkpoints.empty());
}

TEST(KeyframeStore, ABadHeaderIsAClearError) {
  StoreDir dir;
  const auto file = dir.path() / "store";
  std::ofstream(file) << "not a store at all";
  try {
    KeyframeStore::read(file);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("is not a socc consistency store"), std::string::npos);
  }
  KeyframeStore::create(file, true, false);
  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(23);  // the format version after the magic line
    f.put('\x07');
  }
  try {
    KeyframeStore::read(file);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("format version 7, this map_server reads 1"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(KeyframeStore::read(dir.path() / "missing"), std::runtime_error);
}

TEST(KeyframeStore, ARestoredServiceHoldsTheSameKeyframesAndGraph) {
  StoreDir dir;
  const auto file = dir.path() / "store";
  ConsistencyParams store_params;
  store_params.keyframe_distance = 3.0;
  std::vector<ConsistencyService::KeyframePose> before;
  {
    ConsistencyService live(store_params, map::MapConfig{}, {},
                            KeyframeStore::create(file, false, true));
    for (int seq = 0; seq < 8; ++seq)
      live.observe(seq < 5 ? "a" : "b", seq, seq, poseAt(2.0 * seq, 0.02 * seq), streetScan(seq));
    live.flush();
    live.checkpoint(8, 3);
    before = live.keyframePoses();
  }
  const StoreContents contents = KeyframeStore::read(file);
  std::string why;
  const StoredCheckpoint* mark = coveringMark(contents, 8, 3, why);
  ASSERT_NE(mark, nullptr) << why;
  EXPECT_EQ(mark->observed, static_cast<std::int64_t>(before.size()));
  EXPECT_EQ(coveringMark(contents, 8, 4, why), nullptr);  // another grid
  EXPECT_NE(why.find("no mark"), std::string::npos);
  StoreContents short_of_one = contents;  // killed before the worker stored the last keyframe
  short_of_one.keyframes.pop_back();
  EXPECT_EQ(coveringMark(short_of_one, 8, 3, why), nullptr);
  EXPECT_NE(why.find("holds 4 of the 5 keyframes"), std::string::npos) << why;
  ConsistencyService restored(store_params, map::MapConfig{}, {},
                              KeyframeStore::resume(file, contents, true), &contents,
                              mark->grid_serial);
  restored.flush();
  const auto after = restored.keyframePoses();
  ASSERT_EQ(after.size(), before.size());
  for (std::size_t i = 0; i < before.size(); ++i) {
    EXPECT_EQ(after[i].robot, before[i].robot);
    EXPECT_EQ(after[i].seq, before[i].seq);
    EXPECT_TRUE(after[i].odom_pose.isApprox(before[i].odom_pose, 1e-12));
    // 1e-7: robot b meets no keyframe of a, so only its gauge prior holds it and the solver's
    // stopping tolerance shows (1e-8 m).
    EXPECT_TRUE(after[i].optimized.isApprox(before[i].optimized, 1e-7))
        << (after[i].optimized.matrix() - before[i].optimized.matrix()).norm();
  }
  // A journal replay shows the stored integrations again: no second keyframe of them.
  for (int seq = 5; seq < 8; ++seq)
    restored.observe("b", seq, seq, poseAt(2.0 * seq, 0.02 * seq), streetScan(seq));
  // The robot goes on: its next keyframe continues its chain.
  restored.observe("b", 9, 9, poseAt(20.0, 0.2), streetScan(9));
  restored.flush();
  EXPECT_EQ(restored.stats().keyframes, static_cast<int>(before.size()) + 1);
  EXPECT_EQ(restored.keyframePoses().back().seq, 9);
  const StoreContents grown = KeyframeStore::read(file);
  EXPECT_EQ(grown.keyframes.size(), before.size() + 1);
  ASSERT_EQ(grown.keyframes.back().edges.size(), 1u);
  EXPECT_EQ(grown.keyframes.back().edges[0].from, static_cast<int>(before.size()) - 1);
}

// Integrations from..to-1 of robots a (seq < 3) and b: keyframes a0, a2, b3, b5, b7.
void observeAll(ConsistencyService& service, int from, int to) {
  for (int seq = from; seq < to; ++seq)
    service.observe(seq < 3 ? "a" : "b", seq, seq, poseAt(2.0 * seq, 0.02 * seq), streetScan(seq));
}

TEST(KeyframeStore, KeyframesWaitingForTheWorkerAtACheckpointSurviveAKill) {
  // Three keyframes wait for a held worker when the map checkpoints (its snapshot cuts the
  // journal that holds their integrations); the process dies before the worker stored them.
  StoreDir dir;
  const auto file = dir.path() / "store";
  ConsistencyParams store_params;
  store_params.keyframe_distance = 3.0;
  ConsistencyService never_killed(store_params, map::MapConfig{});
  observeAll(never_killed, 0, 8);
  never_killed.flush();
  const auto expected = never_killed.keyframePoses();
  {
    ConsistencyService killed(store_params, map::MapConfig{}, {},
                              KeyframeStore::create(file, false, true));
    observeAll(killed, 0, 3);  // keyframes a0, a2: stored by the worker
    killed.flush();
    killed.hold(true);
    observeAll(killed, 3, 8);  // b3, b5, b7: waiting
    const std::uint64_t bytes = std::filesystem::file_size(file);
    const auto start = std::chrono::steady_clock::now();
    killed.checkpoint(8, 3);
    std::cerr << "checkpoint with 3 waiting keyframes: " << std::filesystem::file_size(file) - bytes
              << " B in "
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
              << " s\n";
    killed.checkpoint(8, 4);  // a second mark writes none of them again
    EXPECT_EQ(killed.stats().pending, 3);
  }  // "kill -9": destroyed without processing what waits
  const StoreContents contents = KeyframeStore::read(file);
  ASSERT_EQ(contents.keyframes.size(), 2u);
  ASSERT_EQ(contents.waiting.size(), 3u);
  EXPECT_EQ(waitingKeyframes(contents).size(), 3u);
  std::string why;
  const StoredCheckpoint* mark = coveringMark(contents, 8, 4, why);
  ASSERT_NE(mark, nullptr) << why;
  EXPECT_EQ(mark->observed, 5);
  ConsistencyService restored(store_params, map::MapConfig{}, {},
                              KeyframeStore::resume(file, contents, true), &contents,
                              mark->grid_serial);
  observeAll(restored, 3, 8);  // the journal replay after the snapshot: nothing new
  restored.flush();
  const auto after = restored.keyframePoses();
  ASSERT_EQ(after.size(), expected.size());
  for (std::size_t i = 0; i < after.size(); ++i) {
    EXPECT_EQ(after[i].robot, expected[i].robot);
    EXPECT_EQ(after[i].seq, expected[i].seq);
    EXPECT_TRUE(after[i].optimized.isApprox(expected[i].optimized, 1e-9)) << i;
  }
  // Processed now, they are keyframe records; a second restart has each once.
  const StoreContents again = KeyframeStore::read(file);
  EXPECT_EQ(again.keyframes.size(), expected.size());
  EXPECT_TRUE(waitingKeyframes(again).empty());
  ASSERT_EQ(again.keyframes.back().edges.size(), 1u);
  EXPECT_EQ(again.keyframes.back().edges[0].from, static_cast<int>(expected.size()) - 2);
}

TEST(KeyframeStore, KeyframesReducedOnArrivalSurviveACheckpointAndAKill) {
  // As above with room for one queued cloud: b3 waits with its cloud, b5 and b7 were reduced on
  // arrival. After the kill and restart the store holds the same keyframes, points and scans
  // included, as one written by a worker that never fell behind.
  StoreDir dir;
  const auto file = dir.path() / "store";
  ConsistencyParams store_params;
  store_params.keyframe_distance = 3.0;
  {
    ConsistencyService kept_up(store_params, map::MapConfig{}, {},
                               KeyframeStore::create(dir.path() / "kept_up", false, true));
    observeAll(kept_up, 0, 8);
    kept_up.flush();
  }
  const StoreContents expected = KeyframeStore::read(dir.path() / "kept_up");
  ASSERT_EQ(expected.keyframes.size(), 5u);
  store_params.max_pending_scans = 1;
  {
    ConsistencyService killed(store_params, map::MapConfig{}, {},
                              KeyframeStore::create(file, false, true));
    observeAll(killed, 0, 3);
    killed.flush();
    const int reduced_before = killed.stats().scans_reduced_on_arrival;  // a2: maybe (timing)
    killed.hold(true);
    observeAll(killed, 3, 8);
    EXPECT_EQ(killed.stats().pending_clouds, 1);
    EXPECT_EQ(killed.stats().scans_reduced_on_arrival - reduced_before, 2);
    const std::uint64_t bytes = std::filesystem::file_size(file);
    killed.checkpoint(8, 3);
    std::cerr << "checkpoint with 1 waiting cloud and 2 reduced keyframes: "
              << std::filesystem::file_size(file) - bytes << " B\n";
  }  // "kill -9"
  const StoreContents contents = KeyframeStore::read(file);
  ASSERT_EQ(contents.waiting.size(), 3u);
  EXPECT_EQ(contents.waiting[0].form, WaitingForm::kCloud);
  EXPECT_EQ(contents.waiting[1].form, WaitingForm::kReduced);
  EXPECT_EQ(contents.waiting[2].form, WaitingForm::kReduced);
  std::string why;
  const StoredCheckpoint* mark = coveringMark(contents, 8, 3, why);
  ASSERT_NE(mark, nullptr) << why;
  {
    ConsistencyService restored(store_params, map::MapConfig{}, {},
                                KeyframeStore::resume(file, contents, true), &contents,
                                mark->grid_serial);
    observeAll(restored, 3, 8);  // the journal replay: nothing new
    restored.flush();
    EXPECT_EQ(restored.stats().keyframes, 5);
  }
  const StoreContents again = KeyframeStore::read(file);
  ASSERT_EQ(again.keyframes.size(), expected.keyframes.size());
  for (std::size_t i = 0; i < again.keyframes.size(); ++i) {
    const Keyframe& got = again.keyframes[i].keyframe;
    const Keyframe& want = expected.keyframes[i].keyframe;
    EXPECT_EQ(got.seq, want.seq);
    EXPECT_FALSE(got.points.empty()) << i;
    EXPECT_EQ(got.points, want.points) << i;
    EXPECT_EQ(got.scan.xyz, want.scan.xyz) << i;
    EXPECT_EQ(got.scan.labels, want.scan.labels) << i;
    EXPECT_TRUE(again.keyframes[i].estimate.isApprox(expected.keyframes[i].estimate, 1e-9)) << i;
  }
}

}  // namespace
}  // namespace socc::consistency
