// Each handler of MapService, called directly (no transport).
#include <gtest/gtest.h>

#include "service/request_checks.hpp"
#include "service_test_helpers.hpp"

namespace socc::service {
namespace {

using test::scan;

TEST(MapServiceHandlers, IntegrateAppliesOnceAndAcknowledgesRetries) {
  MapService service(test::smallConfig());
  const integrate_reply_t first = service.integrate(scan("robot1", 5));
  ASSERT_EQ(first.header.status, +reply_header_t::OK) << first.header.message;
  EXPECT_FALSE(first.duplicate);
  EXPECT_EQ(first.seq, 5);
  EXPECT_GT(first.voxels_hit, 0);
  EXPECT_GT(first.voxels_touched, 0);
  const std::int64_t version = first.map_version;
  const auto before = test::content(service.getChunk(test::everything()));

  for (const std::int64_t seq : {5, 4, 0}) {  // retry of the same seq, and older ones
    const integrate_reply_t again = service.integrate(scan("robot1", seq));
    EXPECT_EQ(again.header.status, +reply_header_t::OK);
    EXPECT_TRUE(again.duplicate) << "seq " << seq;
    EXPECT_EQ(again.voxels_touched, 0);
    EXPECT_EQ(again.map_version, version);
  }
  EXPECT_EQ(test::content(service.getChunk(test::everything())), before);
  EXPECT_EQ(service.integrations(), 1);

  // Another robot has its own sequence.
  EXPECT_FALSE(service.integrate(scan("robot2", 5, 1.0)).duplicate);
  EXPECT_FALSE(service.integrate(scan("robot1", 6, 2.0)).duplicate);
  EXPECT_EQ(service.integrations(), 3);
}

// A founding scan (map_epoch FOUND_MAP) goes into an empty map only: the first of two robots
// founding at once founds it, the other is told to search it and nothing of it is applied.
TEST(MapServiceHandlers, OneRobotFoundsAnEmptyMapAndOnlyAnEmptyOne) {
  MapService service(test::smallConfig());
  const auto founding = [](const std::string& robot, std::int64_t seq, double x) {
    integrate_request_t request = scan(robot, seq, x);
    request.map_epoch = integrate_request_t::FOUND_MAP;
    return request;
  };
  const integrate_reply_t founded = service.integrate(founding("first", 1, 0.0));
  ASSERT_EQ(founded.header.status, +reply_header_t::OK) << founded.header.message;
  EXPECT_NE(founded.map_epoch, 0);
  EXPECT_TRUE(service.integrate(founding("first", 1, 0.0)).duplicate) << "a retry";
  const auto content = test::content(service.getChunk(test::everything()));

  const integrate_reply_t second = service.integrate(founding("second", 1, 3.0));
  EXPECT_EQ(second.header.status, +reply_header_t::FAILED_PRECONDITION);
  EXPECT_NE(second.header.message.find("not empty"), std::string::npos) << second.header.message;
  EXPECT_EQ(test::content(service.getChunk(test::everything())), content);
  EXPECT_EQ(service.robots().find("second"), nullptr);
  // The founder goes on as any robot; the other's scans placed in the map (after its search)
  // are taken as anyone's.
  EXPECT_EQ(service.integrate(scan("first", 2, 0.5)).header.status, +reply_header_t::OK);
  EXPECT_EQ(service.integrate(scan("second", 1, 3.0)).header.status, +reply_header_t::OK);

  // A cleared server is empty again; a robot known without voxels is not.
  map_command_request_t clear{};
  clear.command = map_command_request_t::CLEAR;
  ASSERT_EQ(service.command(clear).header.status, +reply_header_t::OK);
  EXPECT_EQ(service.integrate(founding("third", 7, 1.0)).header.status, +reply_header_t::OK);
}

TEST(MapServiceHandlers, IntegrateWithInconsistentRowsIsInvalid) {
  // Only possible in-process (decode() always yields full rows); toCloud() and the journal's
  // encode() would read past a short row.
  MapService service(test::smallConfig());
  auto request = scan("robot1", 1);
  request.xyz[2].pop_back();
  EXPECT_EQ(service.integrate(request).header.status, +reply_header_t::INVALID_ARGUMENT);
  request = scan("robot1", 1);
  request.xyz.pop_back();
  EXPECT_EQ(service.integrate(request).header.status, +reply_header_t::INVALID_ARGUMENT);
  request = scan("robot1", 1);
  request.header.mac_len = 32;  // no mac bytes behind it
  EXPECT_EQ(service.integrate(request).header.status, +reply_header_t::INVALID_ARGUMENT);
  EXPECT_EQ(service.integrations(), 0);
  EXPECT_EQ(service.integrate(scan("robot1", 1)).header.status, +reply_header_t::OK);
}

TEST(MapServiceHandlers, ChunkShapesLimitsAndTruncation) {
  ServerConfig config = test::smallConfig();
  config.limits.max_chunk_voxels = 50;
  config.limits.max_region_extent = 100.0;
  MapService service(config);
  service.integrate(scan("robot1", 1));

  chunk_request_t box = test::everything();
  box.shape = chunk_request_t::SHAPE_BOX;
  for (int i = 0; i < 3; ++i) {
    box.box_min[i] = -20.0;
    box.box_max[i] = 20.0;
  }
  box.fields = chunk_request_t::FIELD_FEATURES;
  box.limit = 10;
  chunk_reply_t reply = service.getChunk(box);
  ASSERT_EQ(reply.header.status, +reply_header_t::OK) << reply.header.message;
  EXPECT_EQ(reply.num_voxels, 10);
  EXPECT_TRUE(reply.truncated);
  EXPECT_EQ(reply.voxel_size, 0.5);

  box.limit = 0;  // server maximum applies
  reply = service.getChunk(box);
  EXPECT_EQ(reply.num_voxels, 50);
  EXPECT_TRUE(reply.truncated);

  chunk_request_t huge = test::everything();
  huge.radius = 500.0;
  EXPECT_EQ(service.getChunk(huge).header.status, +reply_header_t::RESOURCE_EXHAUSTED);

  chunk_request_t bad = test::everything();
  bad.radius = std::nan("");
  EXPECT_EQ(service.getChunk(bad).header.status, +reply_header_t::INVALID_ARGUMENT);
  bad = test::everything();
  bad.shape = 7;
  EXPECT_EQ(service.getChunk(bad).header.status, +reply_header_t::INVALID_ARGUMENT);
  bad = test::everything();
  bad.fields = 64;
  EXPECT_EQ(service.getChunk(bad).header.status, +reply_header_t::INVALID_ARGUMENT);
}

TEST(MapServiceHandlers, OversizedReplyIsResourceExhausted) {
  ServerConfig config = test::smallConfig();
  config.limits.max_reply_bytes = 1000;
  MapService service(config);
  service.integrate(scan("robot1", 1));
  const chunk_reply_t reply = service.getChunk(test::everything());
  EXPECT_EQ(reply.header.status, +reply_header_t::RESOURCE_EXHAUSTED);
  EXPECT_EQ(reply.num_voxels, 0);
}

TEST(MapServiceHandlers, StatsAndRobotPoses) {
  MapService service(test::smallConfig());
  service.integrate(scan("robot1", 3, 1.5));
  service.integrate(scan("robot2", 9, -1.0));
  RequestCounters counters;
  counters.requests = 7;
  counters.rejected = 2;
  const stats_reply_t stats = service.getStats(stats_request_t{}, counters);
  EXPECT_EQ(stats.header.status, +reply_header_t::OK);
  EXPECT_GT(stats.stats.num_voxels, 0);
  EXPECT_GT(stats.stats.memory_bytes, 0);
  EXPECT_EQ(stats.stats.integrations, 2);
  EXPECT_GT(stats.stats.integrations_per_s, 0.0);
  EXPECT_EQ(stats.stats.requests, 7);
  EXPECT_EQ(stats.stats.rejected_requests, 2);
  ASSERT_EQ(stats.stats.num_robots, 2);
  EXPECT_EQ(stats.stats.robots[0].robot_id, "robot1");
  EXPECT_EQ(stats.stats.robots[1].last_seq, 9);

  robot_pose_request_t ask{};
  ask.robot_id = "robot1";
  const robot_pose_reply_t pose = service.getRobotPose(ask);
  ASSERT_EQ(pose.header.status, +reply_header_t::OK);
  EXPECT_EQ(pose.state.last_seq, 3);
  EXPECT_EQ(pose.state.last_scan_utime, 300000);
  EXPECT_DOUBLE_EQ(pose.state.last_pose.translation[0], 1.5);
  EXPECT_EQ(pose.history.num_poses, 0) << "no history unless asked for";
  ask.robot_id = "nobody";
  EXPECT_EQ(service.getRobotPose(ask).header.status, +reply_header_t::NOT_FOUND);
}

TEST(MapServiceHandlers, PoseHistoryInSeqOrderPagedAndSaved) {
  test::TempDir dir;
  MapService service(test::smallConfig(dir.path()));
  for (const int seq : {2, 4, 5, 9}) service.integrate(scan("robot1", seq, 0.5 * seq));
  service.integrate(scan("robot1", 4, 99.0));  // a duplicate: not in the history
  service.integrate(scan("robot2", 1, -1.0));
  robot_pose_request_t ask{};
  ask.robot_id = "robot1";
  ask.max_history = 100;
  robot_pose_reply_t reply = service.getRobotPose(ask);
  ASSERT_EQ(reply.header.status, +reply_header_t::OK);
  EXPECT_EQ(reply.history.robot_id, "robot1");
  EXPECT_EQ(reply.history.seq, (std::vector<std::int64_t>{2, 4, 5, 9}));
  EXPECT_EQ(reply.history.scan_utime[3], 900000);
  EXPECT_DOUBLE_EQ(reply.history.translation[0][1], 2.0);
  EXPECT_DOUBLE_EQ(reply.history.quaternion[0][1], 1.0);
  EXPECT_FALSE(reply.history_truncated);

  ask.max_history = 2;  // a page: seq >= 3, two poses, more follow
  ask.history_from_seq = 3;
  reply = service.getRobotPose(ask);
  EXPECT_EQ(reply.history.seq, (std::vector<std::int64_t>{4, 5}));
  EXPECT_TRUE(reply.history_truncated);
  ask.max_history = -1;
  EXPECT_EQ(service.getRobotPose(ask).header.status, +reply_header_t::INVALID_ARGUMENT);

  // A snapshot keeps the histories; a cleared server has none.
  map_command_request_t command{};
  command.command = map_command_request_t::SAVE;
  command.path = "history.snap";
  ASSERT_EQ(service.command(command).header.status, +reply_header_t::OK);
  command.command = map_command_request_t::CLEAR;
  ASSERT_EQ(service.command(command).header.status, +reply_header_t::OK);
  ask.max_history = 100;
  ask.history_from_seq = 0;
  EXPECT_EQ(service.getRobotPose(ask).header.status, +reply_header_t::NOT_FOUND);
  command.command = map_command_request_t::LOAD;
  ASSERT_EQ(service.command(command).header.status, +reply_header_t::OK);
  reply = service.getRobotPose(ask);
  EXPECT_EQ(reply.history.seq, (std::vector<std::int64_t>{2, 4, 5, 9}));
  service.integrate(scan("robot1", 10, 5.0));
  EXPECT_EQ(service.getRobotPose(ask).history.num_poses, 5);
}

TEST(MapServiceHandlers, CommandsSaveLoadExportClear) {
  test::TempDir dir;
  MapService service(test::smallConfig(dir.path()));
  service.integrate(scan("robot1", 1));
  const auto before = test::content(service.getChunk(test::everything()));

  map_command_request_t command{};
  command.command = map_command_request_t::SAVE;
  command.path = "map.snap";
  map_command_reply_t reply = service.command(command);
  ASSERT_EQ(reply.header.status, +reply_header_t::OK) << reply.header.message;
  EXPECT_GT(reply.num_bytes, 0);
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "map.snap"));

  for (const auto& [code, file] : std::vector<std::pair<std::int8_t, std::string>>{
           {+map_command_request_t::EXPORT_OCTOMAP_BT, "m.bt"},
           {+map_command_request_t::EXPORT_OCTOMAP_OT, "m.ot"},
           {+map_command_request_t::EXPORT_PCD, "m.pcd"}}) {
    command.command = code;
    command.path = file;
    reply = service.command(command);
    EXPECT_EQ(reply.header.status, +reply_header_t::OK) << file << ": " << reply.header.message;
    EXPECT_GT(reply.num_voxels, 0) << file;
    EXPECT_TRUE(std::filesystem::exists(dir.path() / file)) << file;
  }
  command.command = map_command_request_t::EXPORT_PCD;
  command.path = "m.bt";  // wrong extension
  EXPECT_EQ(service.command(command).header.status, +reply_header_t::INVALID_ARGUMENT);

  command.command = map_command_request_t::CLEAR;
  ASSERT_EQ(service.command(command).header.status, +reply_header_t::OK);
  EXPECT_EQ(service.map().stats().num_voxels, 0);
  EXPECT_EQ(service.robots().size(), 0u);

  command.command = map_command_request_t::LOAD;
  command.path = "map.snap";
  reply = service.command(command);
  ASSERT_EQ(reply.header.status, +reply_header_t::OK) << reply.header.message;
  EXPECT_EQ(test::content(service.getChunk(test::everything())), before);
  EXPECT_TRUE(service.integrate(scan("robot1", 1)).duplicate) << "robot state restored";

  command.path = "missing.snap";
  EXPECT_EQ(service.command(command).header.status, +reply_header_t::NOT_FOUND);
  command.command = 42;
  EXPECT_EQ(service.command(command).header.status, +reply_header_t::INVALID_ARGUMENT);
}

TEST(MapServiceHandlers, CommandPathsStayInsideFileDir) {
  std::filesystem::path out;
  const std::filesystem::path root = "/tmp/socc_root";
  EXPECT_TRUE(resolveCommandPath("a/b.snap", root, out).ok());
  EXPECT_EQ(out, root / "a/b.snap");
  EXPECT_TRUE(resolveCommandPath("/tmp/socc_root/x.bt", root, out).ok());
  EXPECT_FALSE(resolveCommandPath("../x.snap", root, out).ok());
  EXPECT_FALSE(resolveCommandPath("a/../../x.snap", root, out).ok());
  EXPECT_FALSE(resolveCommandPath("/etc/passwd", root, out).ok());
  EXPECT_FALSE(resolveCommandPath("", root, out).ok());
  EXPECT_FALSE(resolveCommandPath("/tmp/socc_root", root, out).ok());
}

TEST(MapServiceHandlers, RenderReturnsPng) {
  MapService service(test::smallConfig());
  service.integrate(scan("robot1", 1));
  render_request_t request{};
  for (int i = 0; i < 3; ++i) {
    request.box_min[i] = -10.0;
    request.box_max[i] = 10.0;
  }
  request.pixel_size = 0.5;
  request.occupancy_threshold = 0.5f;
  const render_reply_t reply = service.render(request);
  ASSERT_EQ(reply.header.status, +reply_header_t::OK) << reply.header.message;
  EXPECT_EQ(reply.width, 40);
  EXPECT_EQ(reply.height, 40);
  ASSERT_GT(reply.num_bytes, 8);
  EXPECT_EQ(reply.png[1], 'P');
  EXPECT_EQ(reply.png[2], 'N');
  EXPECT_EQ(reply.png[3], 'G');

  request.pixel_size = 1e-4;  // 200000 x 200000 pixels
  EXPECT_EQ(service.render(request).header.status, +reply_header_t::RESOURCE_EXHAUSTED);
  request.pixel_size = 0.5;
  request.mode = 9;
  EXPECT_EQ(service.render(request).header.status, +reply_header_t::INVALID_ARGUMENT);
}

TEST(MapServiceHandlers, TooManyRobotsIsResourceExhausted) {
  ServerConfig config = test::smallConfig();
  config.limits.max_robots = 2;
  MapService service(config);
  EXPECT_EQ(service.integrate(scan("a", 1)).header.status, +reply_header_t::OK);
  EXPECT_EQ(service.integrate(scan("b", 1)).header.status, +reply_header_t::OK);
  EXPECT_EQ(service.integrate(scan("c", 1)).header.status, +reply_header_t::RESOURCE_EXHAUSTED);
  EXPECT_EQ(service.integrate(scan("a", 2)).header.status, +reply_header_t::OK);
}

}  // namespace
}  // namespace socc::service
