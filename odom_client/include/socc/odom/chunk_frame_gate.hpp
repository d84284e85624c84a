#pragma once
// Whether a chunk is in the robot's frame (docs/consistency.md "Map correction"). The server
// swaps in a grid rebuilt at corrected poses while it handles some robot's Integrate, and tells
// each robot its correction with that robot's next Integrate reply. A robot whose chunk is
// fetched after its own Integrate but after another robot's swap gets the new grid while its
// pose is still in the old frame: registered against it, its next pose would already be in the
// new frame, and the server would move that Integrate by the correction a second time. Such a
// chunk is held until the robot's next Integrate reply (which tells the correction, if any)
// and only then registered against.
#include <cstdint>
#include <optional>

namespace socc::odom {

class ChunkFrameGate {
 public:
  /// A chunk of map instance `epoch` (chunk_reply_t::map_epoch) at map `version`, fetched right
  /// after an Integrate whose reply was at `integrate_version`. True: it is in the robot's frame
  /// (the map instance the robot registers in, or nothing changed on the server between that
  /// reply and the chunk, so no swap happened that the robot has not been told of); false: hold
  /// it until the robot's next Integrate reply, then adopt() it.
  bool admit(std::int64_t epoch, std::int64_t version, std::int64_t integrate_version);
  /// The robot registers against a chunk of `epoch` from now on.
  void adopt(std::int64_t epoch) { epoch_ = epoch; }

 private:
  std::optional<std::int64_t> epoch_;  // of the chunk the robot registers against
};

}  // namespace socc::odom
