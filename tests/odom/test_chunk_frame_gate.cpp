// ChunkFrameGate (docs/consistency.md "Map correction", several robots): a chunk of a grid that
// another robot's Integrate swapped in after this robot's own Integrate waits for this robot's
// next Integrate reply, which tells it the correction into that grid.
#include <gtest/gtest.h>

#include "socc/odom/chunk_frame_gate.hpp"

namespace socc::odom {
namespace {

TEST(ChunkFrameGate, TheFirstChunkAndChunksOfTheSameGridAreInTheRobotsFrame) {
  ChunkFrameGate gate;
  EXPECT_TRUE(gate.admit(7, 10, 10));
  EXPECT_TRUE(gate.admit(7, 25, 20));  // other robots integrated meanwhile: the same grid
}

TEST(ChunkFrameGate, ANewGridRightAfterTheRobotsOwnIntegrateIsInItsFrame) {
  // Nothing changed between the reply and the chunk: the swap came before (or with) this
  // robot's Integrate, whose reply told the correction; or the server restarted (same frame).
  ChunkFrameGate gate;
  EXPECT_TRUE(gate.admit(7, 10, 10));
  EXPECT_TRUE(gate.admit(8, 31, 31));
  EXPECT_TRUE(gate.admit(8, 40, 35));
}

TEST(ChunkFrameGate, ANewGridSwappedInAfterTheRobotsIntegrateWaitsForItsNextReply) {
  ChunkFrameGate gate;
  EXPECT_TRUE(gate.admit(7, 10, 10));
  // Robot B's Integrate (reply at version 20), then robot A's Integrate swaps in grid 8
  // (versions 21, 22), then B's chunk: of grid 8, B not told yet.
  EXPECT_FALSE(gate.admit(8, 22, 20));
  // B's next Integrate reply told the correction: the held chunk becomes the target.
  gate.adopt(8);
  EXPECT_TRUE(gate.admit(8, 30, 26));
  // A chunk fetched on its own (no Integrate before it) is taken and sets the grid.
  gate.adopt(9);
  EXPECT_TRUE(gate.admit(9, 41, 40));
  EXPECT_FALSE(gate.admit(10, 45, 40));
}

}  // namespace
}  // namespace socc::odom
