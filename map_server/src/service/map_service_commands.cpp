// MAP_COMMAND: save / load snapshots, exports, clear.
#include <system_error>

#include "map_service.hpp"
#include "request_checks.hpp"

namespace socc::service {
namespace {

std::int64_t fileSize(const std::filesystem::path& file) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  return ec ? 0 : static_cast<std::int64_t>(size);
}

}  // namespace

map_command_reply_t MapService::command(const map_command_request_t& request) {
  map_command_reply_t reply{};
  try {
    setStatus(reply, runCommand(request, reply));
  } catch (const std::exception& e) {
    // I/O errors of the map (disk full, unreadable snapshot): the map is left unchanged.
    setStatus(reply, Status::internal(e.what()));
  }
  return reply;
}

Status MapService::runCommand(const map_command_request_t& request, map_command_reply_t& reply) {
  if (request.command == map_command_request_t::CLEAR) {
    reply.num_voxels = map_.stats().num_voxels;
    map_.clear();
    robots_.clear();
    corrections_.clear();
    corrections_.serving(map_.epoch());
    restartConsistency();
    if (journal_) checkpoint();  // the journal must not replay pre-clear scans
    reply.detail = "map cleared";
    return {};
  }
  if (request.command < map_command_request_t::SAVE ||
      request.command > map_command_request_t::EXPORT_PCD)
    return Status::invalid("unknown command " + std::to_string(request.command));

  std::filesystem::path file;
  if (Status s = resolveCommandPath(request.path, config_.file_dir, file); !s.ok()) return s;
  const double threshold = request.occupancy_threshold > 0.0f ? request.occupancy_threshold : 0.5;
  if (!(threshold <= 1.0)) return Status::invalid("occupancy_threshold must be in [0, 1]");

  const auto extension = file.extension();
  if (request.command == map_command_request_t::EXPORT_OCTOMAP_BT && extension != ".bt")
    return Status::invalid("EXPORT_OCTOMAP_BT needs a .bt path");
  if (request.command == map_command_request_t::EXPORT_OCTOMAP_OT && extension != ".ot")
    return Status::invalid("EXPORT_OCTOMAP_OT needs a .ot path");
  if (request.command == map_command_request_t::EXPORT_PCD && extension != ".pcd")
    return Status::invalid("EXPORT_PCD needs a .pcd path");

  switch (request.command) {
    case map_command_request_t::SAVE:
      saveSnapshot(file);
      reply.num_voxels = map_.stats().num_voxels;
      break;
    case map_command_request_t::LOAD:
      if (!std::filesystem::exists(file)) return Status::notFound("no snapshot " + file.string());
      try {
        loadSnapshot(file);
      } catch (const std::runtime_error& e) {
        return Status::invalid(std::string("snapshot not loaded: ") + e.what());
      }
      if (journal_) checkpoint();  // the journal now continues the loaded map
      reply.num_voxels = map_.stats().num_voxels;
      break;
    case map_command_request_t::EXPORT_OCTOMAP_BT:
    case map_command_request_t::EXPORT_OCTOMAP_OT:
      reply.num_voxels = map_.exportOctomap(file, threshold);
      break;
    case map_command_request_t::EXPORT_PCD:
      reply.num_voxels = map_.exportPcd(file, threshold);
      break;
    default:
      break;
  }
  reply.detail = file.string();
  reply.num_bytes = fileSize(file);
  return {};
}

}  // namespace socc::service
