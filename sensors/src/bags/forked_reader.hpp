#pragma once
// Runs a reader that may crash on damaged input (a library that trusts the lengths in a file)
// in a child process; the child sends what it reads as frames through a pipe and can wait for
// a value from this process (what to read next) through a socket. A crash, a sanitizer abort
// or an exception in the child becomes a failure frame in this process, which goes on. Two
// ways to start the child: a helper program by posix_spawn (a fresh process image: use this
// when the caller may run other threads and the work allocates or takes library locks; the
// ROS 1 bag reader does), or a fork running a function, which then leaves with _exit. A
// forked child has only the forking thread and keeps every lock another thread held at the
// fork held for good (ASan's allocator under GCC 12 deadlocked so, docs/sensors_bags.md):
// fork only for work that needs no such lock, or in a single-threaded program.
#include <sys/types.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "bags/byte_view.hpp"

namespace socc::sensors::bags {

/// The child's ends of the pipes.
class FrameWriter {
 public:
  FrameWriter(int out, int in) : out_(out), in_(in) {}
  /// One frame: kind (>= kFirstUserFrame) and the concatenation of the parts as payload.
  void write(std::uint8_t kind, std::initializer_list<ByteView> parts);
  /// Waits for the value the parent sends (ForkedReader::send); nullopt when it sends none.
  std::optional<std::uint64_t> receive();

 private:
  void writeAll(const std::uint8_t* data, std::size_t n);
  int out_;
  int in_;
};

struct Frame {
  std::uint8_t kind = 0;
  std::vector<std::uint8_t> payload;
  std::string text() const { return std::string(payload.begin(), payload.end()); }
};

/// Runs work on writer and ends its output: a kEnd frame, or kFailed with what it threw. For a
/// child process (forked, or a helper program started by ForkedReader's spawning constructor).
void runChildWork(const std::function<void(FrameWriter&)>& work, FrameWriter& writer);

class ForkedReader {
 public:
  /// Frame kinds of the reader itself; work uses kinds from kFirstUserFrame on.
  static constexpr std::uint8_t kEnd = 0;     // work returned
  static constexpr std::uint8_t kFailed = 1;  // payload: why (exception text, or how it died)
  static constexpr std::uint8_t kFirstUserFrame = 2;

  /// A spawned program's ends of the pipe (frames to this process) and of the socket (values
  /// from it): FrameWriter(kChildFramesFd, kChildValuesFd) there.
  static constexpr int kChildFramesFd = 3;
  static constexpr int kChildValuesFd = 4;

  /// Starts work in a forked child process. Throws std::runtime_error when no process can be
  /// started.
  explicit ForkedReader(const std::function<void(FrameWriter&)>& work);
  /// Starts program (args: its arguments after its name) by posix_spawn: a fresh process image
  /// that inherits no lock of this process's threads, only stdio and the two channels (on
  /// kChildFramesFd, kChildValuesFd); it must end its output with runChildWork. Throws
  /// std::runtime_error when it cannot be started.
  ForkedReader(const std::string& program, const std::vector<std::string>& args);
  ~ForkedReader();
  ForkedReader(const ForkedReader&) = delete;
  ForkedReader& operator=(const ForkedReader&) = delete;

  /// The next frame of work; a kFailed frame when it threw or the child died (signal, exit
  /// status) or sent a broken frame; nullopt after the kEnd or kFailed frame.
  std::optional<Frame> next();
  /// Sends the child a value (what FrameWriter::receive returns there), e.g. what to read next.
  void send(std::uint64_t value);

 private:
  /// Reads n bytes; false at the end of the pipe (the child is gone).
  bool readAll(std::uint8_t* data, std::size_t n);
  /// The two channels; the child's ends are from_child[1], to_child[0].
  struct Channels {
    int from_child[2];
    int to_child[2];
  };
  static Channels openChannels();
  void keepParentEnds(const Channels& c);
  /// A kFailed frame saying how the child ended (it is reaped).
  Frame childGone(const std::string& context);
  void stopChild();

  pid_t pid_ = -1;
  int fd_ = -1;        // frames from the child
  int to_child_ = -1;  // values to the child
  bool done_ = false;
};

}  // namespace socc::sensors::bags
