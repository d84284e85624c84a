#include "socc/tools/server_process.hpp"

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <thread>
#include <vector>

extern char** environ;

namespace socc::tools {

ServerProcess::ServerProcess(const std::string& binary, const std::string& url) {
  std::vector<std::string> args{binary, "--lcm-url", url, "--quiet"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  // posix_spawn instead of fork: the caller may already run threads (LCM), and a forked
  // child of a multi-threaded process may only call async-signal-safe functions.
  if (const int err = posix_spawn(&pid_, binary.c_str(), nullptr, nullptr, argv.data(), environ))
    throw std::runtime_error("cannot start " + binary + ": " + std::strerror(err));
}

ServerProcess::~ServerProcess() {
  if (!running()) return;
  ::kill(pid_, SIGTERM);  // lets map_server finish its reply and exit cleanly
  for (int i = 0; i < 50; ++i) {
    if (!running()) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ::kill(pid_, SIGKILL);
  ::waitpid(pid_, nullptr, 0);
}

bool ServerProcess::running() {
  if (pid_ <= 0) return false;
  int status = 0;
  const pid_t r = ::waitpid(pid_, &status, WNOHANG);
  if (r == 0) return true;
  if (r == pid_ || (r < 0 && errno == ECHILD)) pid_ = -1;
  return pid_ > 0;
}

}  // namespace socc::tools
