// The acceleration grid must return exactly what a brute-force search over all primitives does.
#include <gtest/gtest.h>

#include "socc/sim/primitive_grid.hpp"
#include "socc/sim/random.hpp"

namespace socc::sim {
namespace {

TEST(PrimitiveGrid, MatchesBruteForce) {
  Random rng(7);
  std::vector<Primitive> prims;
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d c(rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(-2, 5));
    const auto label = static_cast<std::uint16_t>(i);
    switch (i % 3) {
      case 0:
        prims.push_back({makeBox(c, {rng.uniform(0.2, 8), rng.uniform(0.2, 8), rng.uniform(0.2, 8)},
                                 rng.uniform(-3, 3)),
                         label});
        break;
      case 1:
        prims.push_back({Cylinder{c.head<2>(), c.z() - 2, c.z() + 2, rng.uniform(0.1, 1)}, label});
        break;
      default:
        prims.push_back({Sphere{c, rng.uniform(0.2, 3)}, label});
    }
  }
  const PrimitiveGrid grid(prims, 4.0);
  int hits = 0;
  for (int i = 0; i < 3000; ++i) {
    const Eigen::Vector3d o(rng.uniform(-60, 60), rng.uniform(-60, 60), rng.uniform(-1, 3));
    Eigen::Vector3d d(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-0.3, 0.3));
    if (i % 50 == 0) d = Eigen::Vector3d(0, 0, -1);  // vertical rays
    const Ray ray{o, d.normalized()};
    std::optional<Hit> brute;
    for (const auto& p : prims) {
      const auto t = intersect(ray, p.shape);
      if (t && *t < 80.0 && (!brute || *t < brute->range)) brute = Hit{*t, p.label};
    }
    const auto fast = grid.cast(ray, 80.0);
    ASSERT_EQ(fast.has_value(), brute.has_value()) << "ray " << i;
    if (brute) {
      ++hits;
      EXPECT_DOUBLE_EQ(fast->range, brute->range);
      EXPECT_EQ(fast->label, brute->label);
    }
  }
  EXPECT_GT(hits, 300);
}

TEST(PrimitiveGrid, EmptyGridHitsNothing) {
  const PrimitiveGrid grid({}, 2.0);
  EXPECT_FALSE(grid.cast({Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX()}, 100.0));
}

}  // namespace
}  // namespace socc::sim
