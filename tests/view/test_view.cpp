// socc-view's parts without processes: the map server's view stream (changed blocks, budget,
// refresh), the bridge's model fed by it, the page and Foxglove encodings, the LAN token.
#include <gtest/gtest.h>

#include <cstring>
#include <nlohmann/json.hpp>

#include "access_token.hpp"
#include "foxglove_protocol.hpp"
#include "page_protocol.hpp"
#include "service/view_stream.hpp"
#include "socc/map/semantic_occupancy_map.hpp"
#include "view_model.hpp"

namespace socc {
namespace {

// Hits in three blocks (4 m blocks of 0.5 m voxels): 2 voxels near the origin, one at 10 m, one
// at 20 m.
map::SemanticOccupancyMap mapWithThreeBlocks() {
  map::SemanticOccupancyMap map{map::MapConfig{}};
  LabeledCloud c;
  c.points = {Eigen::Vector3f(1.1f, 0.1f, 0.1f), Eigen::Vector3f(1.6f, 0.1f, 0.1f),
              Eigen::Vector3f(10.1f, 0.1f, 0.1f), Eigen::Vector3f(20.1f, 0.1f, 0.1f)};
  c.labels = {13, 13, 15, 9};
  map.integrate(Eigen::Isometry3d::Identity(), c);
  return map;
}

std::int64_t changedVoxels(const std::vector<map_delta_t>& messages) {
  std::int64_t n = 0;
  for (const map_delta_t& m : messages)
    if (m.kind == map_delta_t::CHANGED) n += m.num_voxels;
  return n;
}

TEST(ViewStream, SendsChangedBlocksOnceThenOnlyTheRefresh) {
  const map::SemanticOccupancyMap map = mapWithThreeBlocks();
  service::ViewStream stream;
  const std::vector<map_delta_t> first = stream.next(map, 1);
  EXPECT_EQ(changedVoxels(first), map.stats().num_occupied);
  ASSERT_FALSE(first.empty());
  EXPECT_EQ(first[0].epoch, map.epoch());
  EXPECT_EQ(first[0].block_dim, 8);
  const std::vector<map_delta_t> second = stream.next(map, 2);
  EXPECT_EQ(changedVoxels(second), 0);  // nothing changed: only refresh messages
  for (const map_delta_t& m : second) EXPECT_EQ(m.kind, +map_delta_t::REFRESH);
}

TEST(ViewStream, BudgetLeavesTheRestPendingAndCoalesces) {
  const map::SemanticOccupancyMap map = mapWithThreeBlocks();
  service::ViewStreamBudget budget;
  budget.changed_voxels = 1;  // one block per period
  budget.refresh_voxels = 0;
  service::ViewStream stream(budget);
  // Rays made blocks of free voxels too: listed (no voxels) but free of the budget.
  std::int64_t sent = 0;
  int periods = 0;
  for (; periods < 20; ++periods) {
    const auto messages = stream.next(map, periods);
    if (messages.empty()) break;
    ASSERT_EQ(messages.size(), 1u);
    int with_voxels = 0;
    for (const std::int16_t n : messages[0].block_voxels) with_voxels += n > 0 ? 1 : 0;
    EXPECT_LE(with_voxels, 1);
    sent += messages[0].num_voxels;
  }
  EXPECT_EQ(periods, 3);  // one period per block with voxels
  EXPECT_EQ(stream.pendingBlocks(), 0u);
  EXPECT_EQ(sent, map.stats().num_occupied);
  EXPECT_TRUE(stream.next(map, 99).empty());
}

TEST(ViewModel, HoldsWhatTheStreamSentAndRefusesInconsistentDeltas) {
  const map::SemanticOccupancyMap map = mapWithThreeBlocks();
  service::ViewStream stream;
  view::ViewModel model;
  for (const map_delta_t& m : stream.next(map, 1)) EXPECT_EQ(model.applyDelta(m), "");
  EXPECT_EQ(model.read([](const view::ViewModel& m) { return m.voxelCount(); }),
            map.stats().num_occupied);
  EXPECT_EQ(model.read([](const view::ViewModel& m) { return m.blocks().size(); }), 3u);

  map_delta_t bad = stream.next(map, 2).at(0);
  ASSERT_GT(bad.num_voxels, 0);
  bad.block_voxels[0] = static_cast<std::int16_t>(bad.block_voxels[0] + 1);
  EXPECT_NE(model.applyDelta(bad), "");
  bad.block_voxels[0] = static_cast<std::int16_t>(bad.block_voxels[0] - 1);
  bad.local[0] = 512;  // outside its 8^3 block
  EXPECT_NE(model.applyDelta(bad), "");

  // A block listed without voxels is emptied; a new epoch drops everything.
  map_delta_t empty = stream.next(map, 3).at(0);
  empty.num_blocks = 1;
  for (auto& row : empty.block_key) row.resize(1);
  empty.block_voxels = {0};
  empty.num_voxels = 0;
  empty.local.clear();
  empty.occupancy.clear();
  empty.label.clear();
  EXPECT_EQ(model.applyDelta(empty), "");
  EXPECT_EQ(model.read([](const view::ViewModel& m) { return m.blocks().size(); }), 2u);
  empty.epoch += 1;
  empty.num_blocks = 0;
  for (auto& row : empty.block_key) row.clear();
  empty.block_voxels.clear();
  EXPECT_EQ(model.applyDelta(empty), "");
  EXPECT_EQ(model.read([](const view::ViewModel& m) { return m.voxelCount(); }), 0);
}

TEST(PageProtocol, BlocksMessageLayout) {
  const map::SemanticOccupancyMap map = mapWithThreeBlocks();
  service::ViewStream stream;
  view::ViewModel model;
  for (const map_delta_t& m : stream.next(map, 1)) model.applyDelta(m);
  std::vector<view::BlockKey> keys;
  model.read([&](const view::ViewModel& m) {
    for (const auto& entry : m.blocks()) keys.push_back(entry.first);
    return 0;
  });
  std::vector<std::uint8_t> out;
  const std::size_t taken = model.read(
      [&](const view::ViewModel& m) { return view::page::blocks(m, keys, 0, 1 << 20, out); });
  EXPECT_EQ(taken, keys.size());
  std::uint32_t n = 0;
  std::memcpy(&n, out.data() + 4, 4);
  EXPECT_EQ(out[0], view::page::kBlocks);
  EXPECT_EQ(n, keys.size());
  // 8 header bytes, 14 per block, 4 per voxel.
  EXPECT_EQ(out.size(),
            8 + 14 * keys.size() + 4 * static_cast<std::size_t>(map.stats().num_occupied));
}

TEST(FoxgloveProtocol, MessageDataFrameAndPointCloud) {
  const auto frame = view::foxglove::messageData(7, 123456789u, "{}");
  ASSERT_EQ(frame.size(), 1u + 4 + 8 + 2);
  EXPECT_EQ(frame[0], 0x01);
  std::uint32_t id = 0;
  std::uint64_t ns = 0;
  std::memcpy(&id, frame.data() + 1, 4);
  std::memcpy(&ns, frame.data() + 5, 8);
  EXPECT_EQ(id, 7u);
  EXPECT_EQ(ns, 123456789u);

  const map::SemanticOccupancyMap map = mapWithThreeBlocks();
  service::ViewStream stream;
  view::ViewModel model;
  for (const map_delta_t& m : stream.next(map, 1)) model.applyDelta(m);
  const auto cloud = nlohmann::json::parse(
      model.read([](const view::ViewModel& m) { return view::foxglove::voxels(m, 1, 0); }));
  EXPECT_EQ(cloud["frame_id"], "map");
  EXPECT_EQ(cloud["point_stride"], 16);
  // base64 of 16 bytes per occupied voxel
  EXPECT_EQ(cloud["data"].get<std::string>().size(),
            4 * ((16 * static_cast<std::size_t>(map.stats().num_occupied) + 2) / 3));
  const auto advertise = nlohmann::json::parse(view::foxglove::advertise());
  EXPECT_EQ(advertise["op"], "advertise");
  EXPECT_EQ(advertise["channels"].size(), view::foxglove::kNumChannels);
}

TEST(AccessToken, DerivedFromTheKeyAndComparedWhole) {
  const auth::SharedKey a = auth::SharedKey::generate();
  const auth::SharedKey b = auth::SharedKey::generate();
  const std::string token = view::accessToken(a);
  EXPECT_EQ(token.size(), 64u);
  EXPECT_EQ(token, view::accessToken(a));
  EXPECT_NE(token, view::accessToken(b));
  EXPECT_TRUE(view::tokenMatches(token, token));
  EXPECT_FALSE(view::tokenMatches(token, token.substr(0, 63)));
  EXPECT_FALSE(view::tokenMatches(token, ""));
}

}  // namespace
}  // namespace socc
