// Large messages in parts (docs/fleet.md "Large messages"): PartAssembler's bookkeeping and
// PartTransport end to end over memq:// with a lossy forwarder between sender and receiver.
#include <gtest/gtest.h>

#include <algorithm>
#include <lcm/lcm-cpp.hpp>
#include <optional>
#include <random>
#include <thread>
#include <vector>

#include "socc/rpc/part_assembler.hpp"
#include "socc/rpc/part_transport.hpp"

namespace socc::rpc {
namespace {

using Clock = std::chrono::steady_clock;

std::vector<std::uint8_t> testMessage(std::size_t size, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<std::uint8_t> bytes(size);
  for (auto& b : bytes) b = static_cast<std::uint8_t>(rng());
  return bytes;
}

// The parts PartTransport would send for message, 100 bytes each.
std::vector<part_t> partsOf(const std::vector<std::uint8_t>& message, std::int64_t transfer) {
  std::vector<part_t> parts;
  const int count = static_cast<int>((message.size() + 99) / 100);
  for (int i = 0; i < count; ++i) {
    part_t p{};
    p.sender = "sender.1";
    p.transfer_id = transfer;
    p.index = i;
    p.count = count;
    p.total_size = static_cast<std::int32_t>(message.size());
    p.offset = i * 100;
    p.data.assign(message.begin() + p.offset,
                  message.begin() + std::min<std::size_t>(message.size(), p.offset + 100));
    p.size = static_cast<std::int32_t>(p.data.size());
    parts.push_back(p);
  }
  return parts;
}

TEST(PartAssembler, AnyOrderWithDuplicatesCompletesOnce) {
  const auto message = testMessage(1050, 1);
  auto parts = partsOf(message, 7);
  parts.push_back(parts[3]);
  std::shuffle(parts.begin(), parts.end(), std::mt19937(2));
  PartAssembler assembler;
  int completed = 0;
  for (const auto& p : parts)
    if (const auto whole = assembler.add(p, Clock::now())) {
      ++completed;
      EXPECT_EQ(*whole, message);
    }
  EXPECT_EQ(completed, 1);
  EXPECT_FALSE(assembler.add(parts[0], Clock::now())) << "a late part of a completed transfer";
  EXPECT_EQ(assembler.incompleteTransfers(), 0u);
}

TEST(PartAssembler, StalledTransferListsItsMissingParts) {
  const auto message = testMessage(1000, 3);
  const auto parts = partsOf(message, 9);
  PartAssemblerLimits limits;
  limits.max_nacks = 2;
  PartAssembler assembler(limits);
  const auto t0 = Clock::now();
  for (const auto& p : parts)
    if (p.index != 2 && p.index != 7) assembler.add(p, t0);
  EXPECT_TRUE(assembler.stalled(t0 + std::chrono::milliseconds(5)).empty()) << "not yet stalled";
  const auto nacks = assembler.stalled(t0 + limits.stall);
  ASSERT_EQ(nacks.size(), 1u);
  EXPECT_EQ(nacks[0].sender, "sender.1");
  EXPECT_EQ(nacks[0].nack.transfer_id, 9);
  EXPECT_EQ(nacks[0].nack.missing, (std::vector<std::int32_t>{2, 7}));
  EXPECT_EQ(assembler.stalled(t0 + 2 * limits.stall).size(), 1u);
  EXPECT_TRUE(assembler.stalled(t0 + 3 * limits.stall).empty()) << "gave up after max_nacks";
  EXPECT_EQ(assembler.incompleteTransfers(), 0u);
}

TEST(PartAssembler, InconsistentPartsAreIgnored) {
  auto parts = partsOf(testMessage(300, 4), 1);
  PartAssembler assembler;
  part_t bad = parts[0];
  bad.offset = 250;  // 100 bytes at 250 overrun the 300-byte message
  EXPECT_FALSE(assembler.add(bad, Clock::now()));
  EXPECT_EQ(assembler.incompleteTransfers(), 0u);
  assembler.add(parts[0], Clock::now());
  part_t other_size = parts[1];
  other_size.total_size = 400;  // disagrees with the transfer's first part
  EXPECT_FALSE(assembler.add(other_size, Clock::now()));
  bad = parts[1];
  bad.size = 5;  // size field and data disagree
  EXPECT_FALSE(assembler.add(bad, Clock::now()));
}

// Sender and receiver transports on one memq:// LCM; the test forwards the sender's parts from
// OUT/PART to IN/PART, dropping each with probability loss, so only NACKs can complete them.
class LossyLink {
 public:
  explicit LossyLink(double loss) : loss_(loss) {
    PartOptions options;
    options.split = true;
    options.part_bytes = 1000;
    sender.emplace(lcm, "sender", options);
    receiver.emplace(lcm, "receiver", options);
    receiver->subscribe("IN", [this](const std::uint8_t* data, std::size_t size) {
      delivered.emplace_back(data, data + size);
    });
    lcm_subscribe(lcm.getUnderlyingLCM(), "OUT/PART", &LossyLink::forward, this);
  }

  /// Handles messages and polls for stalls until n messages arrived or timeout.
  void runUntil(std::size_t n, std::chrono::milliseconds timeout) {
    const auto end = Clock::now() + timeout;
    while (delivered.size() < n && Clock::now() < end) {
      while (lcm.handleTimeout(1) > 0) {
      }
      receiver->poll();
    }
  }

  lcm::LCM lcm{"memq://"};
  std::optional<PartTransport> sender;
  std::optional<PartTransport> receiver;
  std::vector<std::vector<std::uint8_t>> delivered;
  int dropped = 0;

 private:
  static void forward(const lcm_recv_buf_t* rbuf, const char*, void* self) {
    auto* link = static_cast<LossyLink*>(self);
    if (std::bernoulli_distribution(link->loss_)(link->rng_)) {
      ++link->dropped;
      return;
    }
    link->lcm.publish("IN/PART", rbuf->data, rbuf->data_size);
  }
  double loss_;
  std::mt19937 rng_{5};
};

TEST(PartTransport, LargeMessagesSurviveTenPercentLoss) {
  LossyLink link(0.10);
  const std::vector<std::vector<std::uint8_t>> sent{testMessage(200000, 6), testMessage(1, 7),
                                                    testMessage(50000, 8)};
  for (const auto& m : sent) link.sender->publish("OUT", m.data(), m.size());
  link.runUntil(2, std::chrono::seconds(10));  // the 1-byte message is not sent in parts
  ASSERT_EQ(link.delivered.size(), 2u);
  // In completion order: the smaller one may be repaired first.
  std::sort(link.delivered.begin(), link.delivered.end(),
            [](const auto& a, const auto& b) { return a.size() > b.size(); });
  EXPECT_EQ(link.delivered[0], sent[0]);
  EXPECT_EQ(link.delivered[1], sent[2]);
  EXPECT_GT(link.dropped, 0);
  EXPECT_GE(link.sender->resentParts(), link.dropped) << "every dropped part was sent again";
}

TEST(PartTransport, WithoutSplittingMessagesGoWhole) {
  lcm::LCM lcm{"memq://"};
  PartTransport transport(lcm, "plain", PartOptions{});
  int whole = 0;
  lcm_subscribe(
      lcm.getUnderlyingLCM(), "PLAIN",
      [](const lcm_recv_buf_t*, const char*, void* n) { ++*static_cast<int*>(n); }, &whole);
  const auto message = testMessage(100000, 9);
  EXPECT_EQ(transport.publish("PLAIN", message.data(), message.size()), 0);
  while (lcm.handleTimeout(0) > 0) {
  }
  EXPECT_EQ(whole, 1);
}

}  // namespace
}  // namespace socc::rpc
