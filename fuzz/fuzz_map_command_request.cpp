// MAP_COMMAND requests (save / load / export / clear with client-given paths) on a small map
// whose file_dir is $TMPDIR (scripts/fuzz.sh points it at a scratch directory).
#include "fuzz_service.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto request = socc::fuzz::decodeRequest<socc::map_command_request_t>(data, size);
  if (!request) return 0;
  socc::service::MapService service = socc::fuzz::populatedService();
  service.command(*request);
  return 0;
}
