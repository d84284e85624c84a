#include "bags/forked_reader.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <stdexcept>

namespace socc::sensors::bags {

namespace {

constexpr std::size_t kFrameHeaderBytes = 9;  // kind, uint64 payload length
// A ROS 1 message holds at most 4 GiB (uint32 length) plus the frame's own fields.
constexpr std::uint64_t kMaxFramePayload = (std::uint64_t{1} << 32) + 64;
constexpr int kPipeBytes = 1 << 20;  // fewer wake-ups for messages of megabytes

/// Closes every descriptor from 3 on but keep_low <= keep_high.
void closeAllBut(int keep_low, int keep_high) {
  unsigned from = 3;
  for (const int keep : {keep_low, keep_high}) {
    const auto k = static_cast<unsigned>(keep);
    if (keep < 0 || k < from) continue;
    if (k > from) ::close_range(from, k - 1, 0);
    from = k + 1;
  }
  ::close_range(from, ~0U, 0);
}

std::string describeEnd(int status) {
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    const char* name = ::strsignal(sig);
    return "the reader process was killed by signal " + std::to_string(sig) + " (" +
           (name != nullptr ? name : "?") + ")";
  }
  if (WIFEXITED(status))
    return "the reader process exited with status " + std::to_string(WEXITSTATUS(status));
  return "the reader process ended";
}

}  // namespace

void FrameWriter::writeAll(const std::uint8_t* data, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(out_, data, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) ::_exit(1);  // the reading side is gone: nothing left to do here
    data += w;
    n -= static_cast<std::size_t>(w);
  }
}

std::optional<std::uint64_t> FrameWriter::receive() {
  std::uint64_t value = 0;
  auto* p = reinterpret_cast<std::uint8_t*>(&value);
  std::size_t n = sizeof(value);
  while (n > 0) {
    const ssize_t r = ::read(in_, p, n);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return std::nullopt;
    p += r;
    n -= static_cast<std::size_t>(r);
  }
  return value;
}

void FrameWriter::write(std::uint8_t kind, std::initializer_list<ByteView> parts) {
  std::uint64_t length = 0;
  for (const ByteView& p : parts) length += p.size;
  std::uint8_t head[kFrameHeaderBytes];
  head[0] = kind;
  std::memcpy(head + 1, &length, sizeof(length));
  writeAll(head, sizeof(head));
  for (const ByteView& p : parts) writeAll(p.data, p.size);
}

void runChildWork(const std::function<void(FrameWriter&)>& work, FrameWriter& writer) {
  try {
    work(writer);
    writer.write(ForkedReader::kEnd, {});
  } catch (const std::exception& e) {
    const std::string what = e.what();
    writer.write(ForkedReader::kFailed, {textBytes(what)});
  } catch (...) {
    const std::string what = "unknown exception";
    writer.write(ForkedReader::kFailed, {textBytes(what)});
  }
}

ForkedReader::Channels ForkedReader::openChannels() {
  Channels c{};
  if (::pipe2(c.from_child, O_CLOEXEC) != 0)
    throw std::runtime_error(std::string("cannot create a pipe: ") + std::strerror(errno));
  // A socket, not a pipe, so that send() to a child that is gone cannot raise SIGPIPE here.
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, c.to_child) != 0) {
    const int err = errno;
    ::close(c.from_child[0]);
    ::close(c.from_child[1]);
    throw std::runtime_error(std::string("cannot create a socket pair: ") + std::strerror(err));
  }
  ::fcntl(c.from_child[1], F_SETPIPE_SZ, kPipeBytes);  // best effort: a smaller pipe costs time
  return c;
}

void ForkedReader::keepParentEnds(const Channels& c) {
  ::close(c.from_child[1]);
  ::close(c.to_child[0]);
  fd_ = c.from_child[0];
  to_child_ = c.to_child[1];
}

ForkedReader::ForkedReader(const std::function<void(FrameWriter&)>& work) {
  const Channels c = openChannels();
  pid_ = ::fork();
  if (pid_ < 0) {
    const int err = errno;
    for (const int fd : {c.from_child[0], c.from_child[1], c.to_child[0], c.to_child[1]})
      ::close(fd);
    throw std::runtime_error(std::string("cannot start a reader process: ") + std::strerror(err));
  }
  if (pid_ == 0) {
    // Only stdio and the child's ends of the pipe and the socket stay open: it keeps no
    // socket or pipe of the program alive.
    const int out = c.from_child[1];
    const int in = c.to_child[0];
    closeAllBut(std::min(out, in), std::max(out, in));
    FrameWriter writer(out, in);
    runChildWork(work, writer);
    ::_exit(0);
  }
  keepParentEnds(c);
}

ForkedReader::ForkedReader(const std::string& program, const std::vector<std::string>& args) {
  const Channels c = openChannels();
  posix_spawn_file_actions_t actions;
  ::posix_spawn_file_actions_init(&actions);
  // dup2 onto the agreed numbers clears close-on-exec there (also when a number is already
  // right); every other descriptor of this program is closed in the child.
  ::posix_spawn_file_actions_adddup2(&actions, c.from_child[1], kChildFramesFd);
  ::posix_spawn_file_actions_adddup2(&actions, c.to_child[0], kChildValuesFd);
  ::posix_spawn_file_actions_addclosefrom_np(&actions, kChildValuesFd + 1);
  std::vector<std::string> argv_strings{program};
  argv_strings.insert(argv_strings.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_strings) argv.push_back(a.data());
  argv.push_back(nullptr);
  const int err = ::posix_spawn(&pid_, program.c_str(), &actions, nullptr, argv.data(), environ);
  ::posix_spawn_file_actions_destroy(&actions);
  if (err != 0) {
    pid_ = -1;
    for (const int fd : {c.from_child[0], c.from_child[1], c.to_child[0], c.to_child[1]})
      ::close(fd);
    throw std::runtime_error("cannot start " + program + ": " + std::strerror(err));
  }
  keepParentEnds(c);
}

void ForkedReader::send(std::uint64_t value) {
  if (to_child_ < 0) return;
  // A child that is gone tells so through next() (MSG_NOSIGNAL: EPIPE, not SIGPIPE).
  const auto* p = reinterpret_cast<const std::uint8_t*>(&value);
  std::size_t n = sizeof(value);
  while (n > 0) {
    const ssize_t w = ::send(to_child_, p, n, MSG_NOSIGNAL);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) break;
    p += w;
    n -= static_cast<std::size_t>(w);
  }
}

ForkedReader::~ForkedReader() {
  stopChild();
}

void ForkedReader::stopChild() {
  if (pid_ > 0) {
    ::kill(pid_, SIGKILL);
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    pid_ = -1;
  }
  for (int* fd : {&fd_, &to_child_}) {
    if (*fd >= 0) ::close(*fd);
    *fd = -1;
  }
}

bool ForkedReader::readAll(std::uint8_t* data, std::size_t n) {
  while (n > 0) {
    const ssize_t r = ::read(fd_, data, n);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return false;
    data += r;
    n -= static_cast<std::size_t>(r);
  }
  return true;
}

Frame ForkedReader::childGone(const std::string& context) {
  Frame f;
  f.kind = kFailed;
  int status = 0;
  pid_t reaped = -1;
  while ((reaped = ::waitpid(pid_, &status, 0)) < 0 && errno == EINTR) {
  }
  const std::string how = reaped == pid_ ? describeEnd(status) : "the reader process is gone";
  pid_ = -1;
  stopChild();
  const std::string text = how + " " + context;
  f.payload.assign(text.begin(), text.end());
  return f;
}

std::optional<Frame> ForkedReader::next() {
  if (done_) return std::nullopt;
  std::uint8_t head[kFrameHeaderBytes];
  if (!readAll(head, sizeof(head))) {
    done_ = true;
    return childGone("before the end of its output");
  }
  Frame f;
  f.kind = head[0];
  std::uint64_t length = 0;
  std::memcpy(&length, head + 1, sizeof(length));
  if (length > kMaxFramePayload) {
    done_ = true;
    stopChild();
    const std::string text = "the reader process sent a broken frame";
    return Frame{kFailed, std::vector<std::uint8_t>(text.begin(), text.end())};
  }
  f.payload.resize(static_cast<std::size_t>(length));
  if (!readAll(f.payload.data(), f.payload.size())) {
    done_ = true;
    return childGone("in the middle of a frame");
  }
  if (f.kind == kEnd || f.kind == kFailed) {
    done_ = true;
    // The child leaves right after its last frame: reap it.
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    pid_ = -1;
    stopChild();
    if (f.kind == kEnd) return std::nullopt;
  }
  return f;
}

}  // namespace socc::sensors::bags
