#pragma once
// A map_server child process owned by socc-loadtest --start-server: started in the
// constructor, stopped (SIGTERM, then SIGKILL after a grace period) in the destructor, so the
// server never outlives the load test, also when the test throws.
#include <sys/types.h>

#include <string>

namespace socc::tools {

class ServerProcess {
 public:
  /// Runs `binary --lcm-url url --quiet`; throws std::runtime_error when it cannot be spawned.
  ServerProcess(const std::string& binary, const std::string& url);
  ~ServerProcess();
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  /// False once the child has exited (e.g. a bad option or a port in use).
  bool running();

 private:
  pid_t pid_ = -1;
};

}  // namespace socc::tools
