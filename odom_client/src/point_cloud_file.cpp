#include "socc/odom/point_cloud_file.hpp"

#include <pcl/PCLPointCloud2.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "socc/labels.hpp"
#include "socc/pcd_header.hpp"

namespace socc::odom {
namespace {

std::string lowerExtension(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

const pcl::PCLPointField* findField(const pcl::PCLPointCloud2& blob, const std::string& name) {
  for (const auto& f : blob.fields)
    if (f.name == name) return &f;
  return nullptr;
}

// Reads field f of point i as double, whatever its stored numeric type.
double readValue(const pcl::PCLPointCloud2& blob, const pcl::PCLPointField& f, std::size_t i) {
  const std::uint8_t* p = blob.data.data() + i * blob.point_step + f.offset;
  const auto get = [p](auto v) {
    std::memcpy(&v, p, sizeof(v));
    return static_cast<double>(v);
  };
  switch (f.datatype) {
    case pcl::PCLPointField::INT8:
      return get(std::int8_t{});
    case pcl::PCLPointField::UINT8:
      return get(std::uint8_t{});
    case pcl::PCLPointField::INT16:
      return get(std::int16_t{});
    case pcl::PCLPointField::UINT16:
      return get(std::uint16_t{});
    case pcl::PCLPointField::INT32:
      return get(std::int32_t{});
    case pcl::PCLPointField::UINT32:
      return get(std::uint32_t{});
    case pcl::PCLPointField::FLOAT32:
      return get(float{});
    case pcl::PCLPointField::FLOAT64:
      return get(double{});
    default:
      throw std::runtime_error("unsupported field type of '" + f.name + "'");
  }
}

// PCL crashes on some malformed headers, so they are checked first: PCD files by
// checkPcdHeader, PLY files here ("ply" ... "element vertex" ... "end_header").
std::string plyHeaderProblem(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return "cannot open";
  std::string line;
  bool ply = false, vertices = false;
  for (int i = 0; i < 200 && std::getline(in, line); ++i) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (i == 0) ply = line == "ply";
    if (line.rfind("element vertex", 0) == 0) vertices = true;
    if (line.rfind("end_header", 0) == 0)
      return ply && vertices ? "" : "PLY header without vertices";
  }
  return "not a PLY file (no 'ply' ... 'end_header' header)";
}

}  // namespace

bool isPointCloudFile(const std::filesystem::path& file) {
  const std::string ext = lowerExtension(file);
  return ext == ".pcd" || ext == ".ply";
}

LabeledCloud loadPointCloudFile(const std::filesystem::path& file) {
  const std::string where = file.string() + ": ";
  if (!std::filesystem::is_regular_file(file)) throw std::runtime_error(where + "no such file");
  const std::string ext = lowerExtension(file);
  if (ext != ".pcd" && ext != ".ply") throw std::runtime_error(where + "not a .pcd or .ply file");
  if (ext == ".pcd")
    checkPcdHeader(file);
  else if (const std::string problem = plyHeaderProblem(file); !problem.empty())
    throw std::runtime_error(where + problem);
  pcl::PCLPointCloud2 blob;
  int rc = -1;
  if (ext == ".pcd")
    rc = pcl::io::loadPCDFile(file.string(), blob);
  else if (ext == ".ply")
    rc = pcl::io::loadPLYFile(file.string(), blob);
  else
    throw std::runtime_error(where + "not a .pcd or .ply file");
  if (rc < 0) throw std::runtime_error(where + "PCL could not read the file");

  const pcl::PCLPointField* fx = findField(blob, "x");
  const pcl::PCLPointField* fy = findField(blob, "y");
  const pcl::PCLPointField* fz = findField(blob, "z");
  if (!fx || !fy || !fz) throw std::runtime_error(where + "no x, y, z fields");
  const pcl::PCLPointField* flabel = findField(blob, "label");
  const pcl::PCLPointField* ftime = findField(blob, "time");
  if (!ftime) ftime = findField(blob, "t");

  const std::size_t n = static_cast<std::size_t>(blob.width) * blob.height;
  if (blob.data.size() < n * blob.point_step) throw std::runtime_error(where + "truncated data");
  LabeledCloud cloud;
  cloud.points.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    cloud.points.emplace_back(static_cast<float>(readValue(blob, *fx, i)),
                              static_cast<float>(readValue(blob, *fy, i)),
                              static_cast<float>(readValue(blob, *fz, i)));
    if (flabel) {
      const auto raw = static_cast<std::uint32_t>(readValue(blob, *flabel, i));
      cloud.labels.push_back(mapSemanticKittiLabel(raw & 0xFFFFu));
    }
    if (ftime) cloud.times.push_back(static_cast<float>(readValue(blob, *ftime, i)));
  }
  return cloud;
}

}  // namespace socc::odom
