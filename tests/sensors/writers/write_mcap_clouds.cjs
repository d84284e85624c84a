// Writes MCAP files of real scans with the MCAP project's own TypeScript writer (@mcap/core)
// and Foxglove's ROS message serializers, independent of socc's reader (test_bags reads them
// back bit for bit):
//   node write_mcap_clouds.cjs OUT_DIR SCAN.bin...
// For each chunk compression (none, zstd, lz4) OUT_DIR/clouds_<compression>.mcap holds
//   /points       sensor_msgs/msg/PointCloud2, cdr:  x y z intensity float32 (KITTI layout)
//   /points_ros1  sensor_msgs/PointCloud2, ros1:     x y z float64, intensity float32,
//                                                    time float32 = point index * 1e-6 s
//   /chatter      std_msgs/msg/String, cdr           (a topic socc does not read)
//   /imu          sensor_msgs/msg/Imu, cdr:           the samples of write_ros1_bags.py
//   /tf_static    tf2_msgs/msg/TFMessage, cdr:        the transforms of write_ros1_bags.py
// Scan i has header stamp 1700000000 + i s + 500 ns and log time 1 ms later.
"use strict";
const fs = require("node:fs");
const path = require("node:path");
const { McapWriter } = require("@mcap/core");
const { parse } = require("@foxglove/rosmsg");
const Ros2Writer = require("@foxglove/rosmsg2-serialization").MessageWriter;
const Ros1Writer = require("@foxglove/rosmsg-serialization").MessageWriter;
const zstd = require("@bokuweb/zstd-wasm");
const lz4 = require("lz4js");

const POINTCLOUD2 = `std_msgs/Header header
uint32 height
uint32 width
PointField[] fields
bool is_bigendian
uint32 point_step
uint32 row_step
uint8[] data
bool is_dense
================================================================================
MSG: std_msgs/Header
HEADER_BODY
================================================================================
MSG: sensor_msgs/PointField
uint8 INT8 = 1
uint8 UINT8 = 2
uint8 INT16 = 3
uint8 UINT16 = 4
uint8 INT32 = 5
uint8 UINT32 = 6
uint8 FLOAT32 = 7
uint8 FLOAT64 = 8
string name
uint32 offset
uint8 datatype
uint32 count`;
const ROS2_HEADER = "builtin_interfaces/Time stamp\nstring frame_id\n" +
  "================================================================================\n" +
  "MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec";
const ROS1_HEADER = "uint32 seq\ntime stamp\nstring frame_id";
const ROS2_DEF = POINTCLOUD2.replace("HEADER_BODY", ROS2_HEADER);
const ROS1_DEF = POINTCLOUD2.replace("HEADER_BODY", ROS1_HEADER);

const IMU_DEF = `std_msgs/Header header
geometry_msgs/Quaternion orientation
float64[9] orientation_covariance
geometry_msgs/Vector3 angular_velocity
float64[9] angular_velocity_covariance
geometry_msgs/Vector3 linear_acceleration
float64[9] linear_acceleration_covariance
================================================================================
MSG: std_msgs/Header
${ROS2_HEADER}
================================================================================
MSG: geometry_msgs/Quaternion
float64 x
float64 y
float64 z
float64 w
================================================================================
MSG: geometry_msgs/Vector3
float64 x
float64 y
float64 z`;

const TF_DEF = `geometry_msgs/TransformStamped[] transforms
================================================================================
MSG: geometry_msgs/TransformStamped
std_msgs/Header header
string child_frame_id
geometry_msgs/Transform transform
================================================================================
MSG: std_msgs/Header
${ROS2_HEADER}
================================================================================
MSG: geometry_msgs/Transform
geometry_msgs/Vector3 translation
geometry_msgs/Quaternion rotation
================================================================================
MSG: geometry_msgs/Vector3
float64 x
float64 y
float64 z
================================================================================
MSG: geometry_msgs/Quaternion
float64 x
float64 y
float64 z
float64 w`;

// /tf_static as write_ros1_bags.py's static_transforms() (frame names without a leading '/').
function staticTransforms() {
  const header = (frame) => ({ stamp: { sec: 1699999999, nanosec: 0 }, frame_id: frame });
  return { transforms: [
    { header: header("base_link"), child_frame_id: "velodyne",
      transform: { translation: { x: 0, y: 0, z: 1.7 }, rotation: { x: 0, y: 0, z: 0, w: 1 } } },
    { header: header("base_link"), child_frame_id: "imu",
      transform: { translation: { x: 0.1, y: 0, z: 0.5 },
                   rotation: { x: 0, y: 0, z: Math.sin(Math.PI / 4), w: Math.cos(Math.PI / 4) } } },
  ] };
}

// Sample k of /imu, as write_ros1_bags.py's imu_sample(k) writes it.
function imuSample(k) {
  const covariance = [1e-4, 0, 0, 0, 4e-4, 0, 0, 0, 1e-2];
  if (k === 5) covariance[0] = -1;
  return {
    header: { stamp: { sec: 1699999999 + Math.floor((5 + k) / 10), nanosec: ((5 + k) % 10) * 100000000 },
              frame_id: "imu" },
    orientation: { x: Math.sin(0.005 * k), y: 0, z: 0, w: Math.cos(0.005 * k) },
    orientation_covariance: covariance,
    angular_velocity: { x: 0.1, y: 0.2, z: 0.3 + k },
    angular_velocity_covariance: new Array(9).fill(0),
    linear_acceleration: { x: 0.5, y: -0.25, z: 9.81 },
    linear_acceleration_covariance: new Array(9).fill(0),
  };
}

class FileWritable {
  constructor(file) { this.fd = fs.openSync(file, "w"); this.pos = 0n; }
  async write(buffer) { fs.writeSync(this.fd, buffer); this.pos += BigInt(buffer.length); }
  position() { return this.pos; }
  close() { fs.closeSync(this.fd); }
}

function field(name, offset, datatype) { return { name, offset, datatype, count: 1 }; }

// KITTI .bin (float32 x y z intensity) as the ROS 2 cloud, as is.
function kittiCloud(bytes) {
  return {
    height: 1, width: bytes.length / 16,
    fields: [field("x", 0, 7), field("y", 4, 7), field("z", 8, 7), field("intensity", 12, 7)],
    is_bigendian: false, point_step: 16, row_step: bytes.length, data: bytes, is_dense: true,
  };
}

// The same points with float64 x y z, float32 intensity and a float32 time field (32 B).
function float64Cloud(bytes) {
  const n = bytes.length / 16;
  const input = new DataView(bytes.buffer, bytes.byteOffset, bytes.length);
  const out = new Uint8Array(n * 32);
  const view = new DataView(out.buffer);
  for (let i = 0; i < n; i++) {
    for (let k = 0; k < 3; k++) view.setFloat64(i * 32 + 8 * k, input.getFloat32(i * 16 + 4 * k, true), true);
    view.setFloat32(i * 32 + 24, input.getFloat32(i * 16 + 12, true), true);
    view.setFloat32(i * 32 + 28, Math.fround(i * 1e-6), true);
  }
  return {
    height: 1, width: n,
    fields: [field("x", 0, 8), field("y", 8, 8), field("z", 16, 8), field("intensity", 24, 7),
             field("time", 28, 7)],
    is_bigendian: false, point_step: 32, row_step: n * 32, data: out, is_dense: true,
  };
}

const compressors = {
  none: undefined,
  zstd: (data) => ({ compression: "zstd", compressedData: zstd.compress(data, 3) }),
  lz4: (data) => ({ compression: "lz4", compressedData: Uint8Array.from(lz4.compress(data)) }),
};

async function writeFile(file, compression, scans) {
  const writable = new FileWritable(file);
  const writer = new McapWriter({
    writable, useChunks: true, chunkSize: 512 * 1024, compressChunk: compressors[compression],
  });
  await writer.start({ profile: "ros2", library: "socc test (@mcap/core)" });
  const enc = new TextEncoder();
  const ros2Schema = await writer.registerSchema(
    { name: "sensor_msgs/msg/PointCloud2", encoding: "ros2msg", data: enc.encode(ROS2_DEF) });
  const ros1Schema = await writer.registerSchema(
    { name: "sensor_msgs/PointCloud2", encoding: "ros1msg", data: enc.encode(ROS1_DEF) });
  const stringSchema = await writer.registerSchema(
    { name: "std_msgs/msg/String", encoding: "ros2msg", data: enc.encode("string data") });
  const points = await writer.registerChannel(
    { schemaId: ros2Schema, topic: "/points", messageEncoding: "cdr", metadata: new Map() });
  const pointsRos1 = await writer.registerChannel(
    { schemaId: ros1Schema, topic: "/points_ros1", messageEncoding: "ros1", metadata: new Map() });
  const chatter = await writer.registerChannel(
    { schemaId: stringSchema, topic: "/chatter", messageEncoding: "cdr", metadata: new Map() });
  const imuSchema = await writer.registerSchema(
    { name: "sensor_msgs/msg/Imu", encoding: "ros2msg", data: enc.encode(IMU_DEF) });
  const imu = await writer.registerChannel(
    { schemaId: imuSchema, topic: "/imu", messageEncoding: "cdr", metadata: new Map() });
  const imus = new Ros2Writer(parse(IMU_DEF, { ros2: true }));
  const tfSchema = await writer.registerSchema(
    { name: "tf2_msgs/msg/TFMessage", encoding: "ros2msg", data: enc.encode(TF_DEF) });
  const tf = await writer.registerChannel(
    { schemaId: tfSchema, topic: "/tf_static", messageEncoding: "cdr", metadata: new Map() });
  const tfs = new Ros2Writer(parse(TF_DEF, { ros2: true }));
  const tfTime = 1699999999n * 1000000000n;
  await writer.addMessage({ channelId: tf, sequence: 0, logTime: tfTime, publishTime: tfTime,
                            data: tfs.writeMessage(staticTransforms()) });
  const ros2 = new Ros2Writer(parse(ROS2_DEF, { ros2: true }));
  const ros1 = new Ros1Writer(parse(ROS1_DEF));
  const strings = new Ros2Writer(parse("string data", { ros2: true }));
  for (let i = 0; i < scans.length; i++) {
    const logTime = BigInt(1700000000 + i) * 1000000000n + 500n + 1000000n;
    const stamp = { sec: 1700000000 + i, nanosec: 500 };
    const ros2Msg = { header: { stamp, frame_id: "velodyne" }, ...kittiCloud(scans[i]) };
    const ros1Msg = { header: { seq: i, stamp: { sec: 1700000000 + i, nsec: 500 }, frame_id: "velodyne" },
                      ...float64Cloud(scans[i]) };
    await writer.addMessage({ channelId: points, sequence: i, logTime, publishTime: logTime,
                              data: ros2.writeMessage(ros2Msg) });
    await writer.addMessage({ channelId: pointsRos1, sequence: i, logTime, publishTime: logTime,
                              data: ros1.writeMessage(ros1Msg) });
    await writer.addMessage({ channelId: chatter, sequence: i, logTime, publishTime: logTime,
                              data: strings.writeMessage({ data: "scan " + i }) });
  }
  for (let k = 0; k < 21; k++) {
    const m = imuSample(k);
    const logTime = BigInt(m.header.stamp.sec) * 1000000000n + BigInt(m.header.stamp.nanosec) + 1000000n;
    await writer.addMessage({ channelId: imu, sequence: k, logTime, publishTime: logTime,
                              data: imus.writeMessage(m) });
  }
  await writer.end();
  writable.close();
}

async function main() {
  const [outDir, ...bins] = process.argv.slice(2);
  if (!outDir || bins.length === 0) {
    console.error("usage: node write_mcap_clouds.cjs OUT_DIR SCAN.bin...");
    process.exit(2);
  }
  await zstd.init();
  const scans = bins.map((b) => new Uint8Array(fs.readFileSync(b)));
  fs.mkdirSync(outDir, { recursive: true });
  for (const compression of Object.keys(compressors)) {
    await writeFile(path.join(outDir, `clouds_${compression}.mcap`), compression, scans);
  }
}

main().catch((e) => { console.error(e); process.exit(1); });
