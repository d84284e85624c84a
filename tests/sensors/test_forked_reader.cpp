// ForkedReader: the child's frames arrive in order, a value sent reaches it; an exception or a
// crash in the child becomes a kFailed frame here, and this process goes on.
#include <gtest/gtest.h>
#include <unistd.h>

#include <csignal>
#include <cstring>

#include "bags/forked_reader.hpp"

namespace socc::sensors::bags {
namespace {

constexpr std::uint8_t kData = ForkedReader::kFirstUserFrame;

std::vector<Frame> readAll(ForkedReader& reader) {
  std::vector<Frame> frames;
  while (std::optional<Frame> f = reader.next()) frames.push_back(std::move(*f));
  EXPECT_FALSE(reader.next()) << "nothing after the end";
  return frames;
}

TEST(ForkedReader, FramesArriveInOrderAndWhole) {
  const std::vector<std::uint8_t> big(3 << 20, 0xAB);  // larger than the pipe
  ForkedReader reader([&](FrameWriter& out) {
    const std::string a = "first";
    out.write(kData, {textBytes(a)});
    out.write(kData, {ByteView(big), textBytes(a)});
    out.write(kData, {});
  });
  const std::vector<Frame> frames = readAll(reader);
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(frames[0].text(), "first");
  ASSERT_EQ(frames[1].payload.size(), big.size() + 5);
  EXPECT_TRUE(std::equal(big.begin(), big.end(), frames[1].payload.begin()));
  EXPECT_TRUE(frames[2].payload.empty());
}

TEST(ForkedReader, AnExceptionInTheChildIsAFailedFrame) {
  ForkedReader reader([](FrameWriter& out) {
    out.write(kData, {});
    throw std::runtime_error("bad record at 42");
  });
  const std::vector<Frame> frames = readAll(reader);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[1].kind, ForkedReader::kFailed);
  EXPECT_EQ(frames[1].text(), "bad record at 42");
}

TEST(ForkedReader, AChildThatDiesIsAFailedFrame) {
  ForkedReader reader([](FrameWriter& out) {
    out.write(kData, {});
    ::kill(::getpid(), SIGKILL);  // as a read past a buffer would end it, without a sanitizer
  });
  const std::vector<Frame> frames = readAll(reader);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[1].kind, ForkedReader::kFailed);
  EXPECT_NE(frames[1].text().find("killed by signal 9"), std::string::npos) << frames[1].text();
}

TEST(ForkedReader, TheChildWaitsForAValueFromTheParent) {
  ForkedReader reader([](FrameWriter& out) {
    out.write(kData, {});
    const std::optional<std::uint64_t> v = out.receive();
    const std::uint64_t echo = v ? *v + 1 : 0;
    out.write(kData, {ByteView(reinterpret_cast<const std::uint8_t*>(&echo), sizeof(echo))});
  });
  ASSERT_TRUE(reader.next());
  reader.send(41);
  const std::optional<Frame> f = reader.next();
  ASSERT_TRUE(f);
  ASSERT_EQ(f->payload.size(), 8u);
  std::uint64_t echo = 0;
  std::memcpy(&echo, f->payload.data(), 8);
  EXPECT_EQ(echo, 42u);
  EXPECT_FALSE(reader.next());
}

TEST(ForkedReader, SendingToAChildThatIsGoneIsHarmless) {
  ForkedReader reader([](FrameWriter&) {});
  EXPECT_FALSE(reader.next());  // the child ended
  reader.send(1);               // no SIGPIPE: this process goes on
  ForkedReader waiting([](FrameWriter& out) { out.receive(); });
  // Destroyed while its child waits for a value: the child is killed and reaped.
}

TEST(ForkedReader, StoppingEarlyEndsTheChild) {
  // The child would write for ever; destroying the reader kills and reaps it.
  ForkedReader reader([](FrameWriter& out) {
    const std::vector<std::uint8_t> block(1 << 16);
    while (true) out.write(kData, {ByteView(block)});
  });
  EXPECT_TRUE(reader.next());
}

// A spawned program (posix_spawn, as the ROS 1 reader's helper) writes its frames to
// descriptor 3 and has the value socket on 4; its exit status or a missing program is an error.
TEST(ForkedReader, SpawnedProgramWritesFramesOnDescriptorThree) {
  ForkedReader reader("/bin/sh",
                      {"-c",
                       "printf '\\002\\005\\000\\000\\000\\000\\000\\000\\000hello' >&3; "
                       "test -S /dev/fd/4 || exit 9; "
                       "printf '\\000\\000\\000\\000\\000\\000\\000\\000\\000' >&3"});
  const std::optional<Frame> f = reader.next();
  ASSERT_TRUE(f);
  EXPECT_EQ(f->kind, kData);
  EXPECT_EQ(f->text(), "hello");
  EXPECT_FALSE(reader.next());  // its kEnd frame: descriptor 4 was the value socket
  ForkedReader failing("/bin/sh", {"-c", "exit 3"});
  const std::optional<Frame> gone = failing.next();
  ASSERT_TRUE(gone);
  EXPECT_EQ(gone->kind, ForkedReader::kFailed);
  EXPECT_NE(gone->text().find("exited with status 3"), std::string::npos) << gone->text();
  EXPECT_THROW(ForkedReader("/nonexistent/reader", {}), std::runtime_error);
}

}  // namespace
}  // namespace socc::sensors::bags
