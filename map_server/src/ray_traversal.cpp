// Ray traversal: forEachVoxelOnRay's list form, and RayFootprint::markRays, which walks many
// rays from one origin into a dense footprint with SIMD lanes.
#include "socc/map/ray_traversal.hpp"

#ifdef __SSE2__
#include <emmintrin.h>
#endif
#if defined(__GNUC__) && defined(__x86_64__)
#include <immintrin.h>
#endif

#include <algorithm>

#include "socc/map/ray_footprint.hpp"

namespace socc::map {

void traverseRay(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double voxel_size,
                 std::vector<VoxelIndex>& out) {
  forEachVoxelOnRay(from, to, voxel_size, [&out](const VoxelIndex& v) { out.push_back(v); });
}

namespace {

/// What the lane kernels need of a dense footprint: the walks (sorted by unchecked steps)
/// and the grid layout (bit index = (x * ny + y) * nz + z from lo).
struct DenseWalks {
  RayWalk* walks;
  const std::uint32_t* order;
  const int* unchecked;
  std::size_t n;
  std::uint64_t* grid;
  VoxelIndex lo;
  std::size_t ny, nz;

  std::size_t indexOf(int x, int y, int z) const {
    return (static_cast<std::size_t>(x - lo.x()) * ny + static_cast<std::size_t>(y - lo.y())) * nz +
           static_cast<std::size_t>(z - lo.z());
  }
  void mark(std::size_t i) const { grid[i >> 6] |= std::uint64_t{1} << (i & 63); }
  /// Rays next .. next + count - 1 of the order, their common unchecked steps and indices.
  int group(std::size_t next, std::size_t count, RayWalk** w, double* index) const {
    int common = unchecked[order[next]];
    for (std::size_t j = 0; j < count; ++j) {
      w[j] = &walks[order[next + j]];
      common = std::min(common, unchecked[order[next + j]]);
      index[j] = static_cast<double>(indexOf(w[j]->x, w[j]->y, w[j]->z));
    }
    return common;
  }
  /// After `common` steps in lanes (now at grid indices index[]), the rest of each walk.
  void finish(RayWalk* const* w, const double* index, std::size_t count, int common) const {
    for (std::size_t j = 0; j < count; ++j) {
      RayWalk& r = *w[j];
      r.steps -= common;
      if (r.steps == 0) continue;
      if (common > 0) {  // the voxel from its grid index
        const auto i = static_cast<std::size_t>(index[j]);
        const std::size_t xy = i / nz;
        r.z = lo.z() + static_cast<int>(i - xy * nz);
        r.y = lo.y() + static_cast<int>(xy % ny);
        r.x = lo.x() + static_cast<int>(xy / ny);
      }
      continueRayWalk(r, [this](const VoxelIndex& v) { mark(indexOf(v.x(), v.y(), v.z())); });
    }
  }
};

// The lane kernels walk rays during their unchecked steps (no end checks:
// RayWalk::uncheckedSteps) with forEachVoxelOnRay's axis choice as masks: x if tx < ty and
// tx < tz, else y if ty < tz, else z (written as y: ty <= tx and ty < tz, z: tz <= tx and
// tz <= ty, the same for values that are never NaN). The chosen t grows by its delta, the
// others by +0.0 as in the scalar walk, so every t is bit for bit the scalar one. The voxel
// is kept as its grid index (a double: exact below 2^53), which a step moves by the axis'
// stride. Only additions, compares and bit masks: SSE2 and AVX2 lanes give the same bits.

#ifdef __SSE2__
/// Two rays in the lanes of SSE2 registers.
class RayLanes {
 public:
  RayLanes(RayWalk* const* w, const double* index, const double* stride)
      : tx_(_mm_set_pd(w[1]->tx, w[0]->tx)),
        ty_(_mm_set_pd(w[1]->ty, w[0]->ty)),
        tz_(_mm_set_pd(w[1]->tz, w[0]->tz)),
        dx_(_mm_set_pd(w[1]->dx, w[0]->dx)),
        dy_(_mm_set_pd(w[1]->dy, w[0]->dy)),
        dz_(_mm_set_pd(w[1]->dz, w[0]->dz)),
        sx_(_mm_set_pd(w[1]->sx * stride[0], w[0]->sx * stride[0])),
        sy_(_mm_set_pd(w[1]->sy * stride[1], w[0]->sy * stride[1])),
        sz_(_mm_set_pd(w[1]->sz * stride[2], w[0]->sz * stride[2])),
        index_(_mm_loadu_pd(index)) {}

  /// One step of both rays; marks both voxels in grid.
  __attribute__((always_inline)) void step(std::uint64_t* grid) {
    const __m128d xy = _mm_cmplt_pd(tx_, ty_), xz = _mm_cmplt_pd(tx_, tz_);
    const __m128d yz = _mm_cmplt_pd(ty_, tz_);
    const __m128d mx = _mm_and_pd(xy, xz);
    const __m128d my = _mm_andnot_pd(xy, yz);
    const __m128d not_z = _mm_or_pd(xz, yz);
    tx_ = _mm_add_pd(tx_, _mm_and_pd(mx, dx_));
    ty_ = _mm_add_pd(ty_, _mm_and_pd(my, dy_));
    tz_ = _mm_add_pd(tz_, _mm_andnot_pd(not_z, dz_));
    const __m128d move =
        _mm_or_pd(_mm_or_pd(_mm_and_pd(mx, sx_), _mm_and_pd(my, sy_)), _mm_andnot_pd(not_z, sz_));
    index_ = _mm_add_pd(index_, move);
    const __m128i i = _mm_cvttpd_epi32(index_);
    const auto i0 = static_cast<std::uint32_t>(_mm_cvtsi128_si32(i));
    const auto i1 = static_cast<std::uint32_t>(_mm_cvtsi128_si32(_mm_shuffle_epi32(i, 1)));
    grid[i0 >> 6] |= std::uint64_t{1} << (i0 & 63);
    grid[i1 >> 6] |= std::uint64_t{1} << (i1 & 63);
  }

  /// The rays' t and grid indices after the steps taken.
  void store(RayWalk* const* w, double* index) const {
    double v[2];
    _mm_storeu_pd(v, tx_);
    w[0]->tx = v[0];
    w[1]->tx = v[1];
    _mm_storeu_pd(v, ty_);
    w[0]->ty = v[0];
    w[1]->ty = v[1];
    _mm_storeu_pd(v, tz_);
    w[0]->tz = v[0];
    w[1]->tz = v[1];
    _mm_storeu_pd(index, index_);
  }

 private:
  __m128d tx_, ty_, tz_, dx_, dy_, dz_, sx_, sy_, sz_, index_;
};

/// Walks groups of six rays (three pairs per iteration: their dependency chains overlap);
/// returns how many rays of the order it walked.
std::size_t walkLanesSse2(const DenseWalks& d, const double* stride) {
  constexpr std::size_t kRays = 6;
  std::size_t next = 0;
  for (; next + kRays <= d.n; next += kRays) {
    RayWalk* w[kRays];
    double index[kRays];
    const int common = d.group(next, kRays, w, index);
    if (common > 0) {
      RayLanes p(w, index, stride), q(w + 2, index + 2, stride), u(w + 4, index + 4, stride);
      for (int k = 0; k < common; ++k) {
        p.step(d.grid);
        q.step(d.grid);
        u.step(d.grid);
      }
      p.store(w, index);
      q.store(w + 2, index + 2);
      u.store(w + 4, index + 4);
    }
    d.finish(w, index, kRays, common);
  }
  return next;
}
#endif

#if defined(__GNUC__) && defined(__x86_64__)
#define SOCC_RAY_LANES_AVX2 1
#define SOCC_AVX2 __attribute__((target("avx2")))

/// Four rays in the lanes of AVX2 registers (RayLanes' arithmetic, lane for lane).
class RayLanes4 {
 public:
  SOCC_AVX2 RayLanes4(RayWalk* const* w, const double* index, const double* stride)
      : tx_(_mm256_set_pd(w[3]->tx, w[2]->tx, w[1]->tx, w[0]->tx)),
        ty_(_mm256_set_pd(w[3]->ty, w[2]->ty, w[1]->ty, w[0]->ty)),
        tz_(_mm256_set_pd(w[3]->tz, w[2]->tz, w[1]->tz, w[0]->tz)),
        dx_(_mm256_set_pd(w[3]->dx, w[2]->dx, w[1]->dx, w[0]->dx)),
        dy_(_mm256_set_pd(w[3]->dy, w[2]->dy, w[1]->dy, w[0]->dy)),
        dz_(_mm256_set_pd(w[3]->dz, w[2]->dz, w[1]->dz, w[0]->dz)),
        sx_(_mm256_set_pd(w[3]->sx * stride[0], w[2]->sx * stride[0], w[1]->sx * stride[0],
                          w[0]->sx * stride[0])),
        sy_(_mm256_set_pd(w[3]->sy * stride[1], w[2]->sy * stride[1], w[1]->sy * stride[1],
                          w[0]->sy * stride[1])),
        sz_(_mm256_set_pd(w[3]->sz * stride[2], w[2]->sz * stride[2], w[1]->sz * stride[2],
                          w[0]->sz * stride[2])),
        index_(_mm256_loadu_pd(index)) {}

  SOCC_AVX2 __attribute__((always_inline)) void step(std::uint64_t* grid) {
    const __m256d xy = _mm256_cmp_pd(tx_, ty_, _CMP_LT_OQ);
    const __m256d xz = _mm256_cmp_pd(tx_, tz_, _CMP_LT_OQ);
    const __m256d yz = _mm256_cmp_pd(ty_, tz_, _CMP_LT_OQ);
    const __m256d mx = _mm256_and_pd(xy, xz);
    const __m256d my = _mm256_andnot_pd(xy, yz);
    const __m256d not_z = _mm256_or_pd(xz, yz);
    tx_ = _mm256_add_pd(tx_, _mm256_and_pd(mx, dx_));
    ty_ = _mm256_add_pd(ty_, _mm256_and_pd(my, dy_));
    tz_ = _mm256_add_pd(tz_, _mm256_andnot_pd(not_z, dz_));
    const __m256d move = _mm256_or_pd(_mm256_or_pd(_mm256_and_pd(mx, sx_), _mm256_and_pd(my, sy_)),
                                      _mm256_andnot_pd(not_z, sz_));
    index_ = _mm256_add_pd(index_, move);
    const __m128i i = _mm256_cvttpd_epi32(index_);
    const auto i0 = static_cast<std::uint32_t>(_mm_cvtsi128_si32(i));
    const auto i1 = static_cast<std::uint32_t>(_mm_extract_epi32(i, 1));
    const auto i2 = static_cast<std::uint32_t>(_mm_extract_epi32(i, 2));
    const auto i3 = static_cast<std::uint32_t>(_mm_extract_epi32(i, 3));
    grid[i0 >> 6] |= std::uint64_t{1} << (i0 & 63);
    grid[i1 >> 6] |= std::uint64_t{1} << (i1 & 63);
    grid[i2 >> 6] |= std::uint64_t{1} << (i2 & 63);
    grid[i3 >> 6] |= std::uint64_t{1} << (i3 & 63);
  }

  SOCC_AVX2 void store(RayWalk* const* w, double* index) const {
    double v[4];
    _mm256_storeu_pd(v, tx_);
    for (int j = 0; j < 4; ++j) w[j]->tx = v[j];
    _mm256_storeu_pd(v, ty_);
    for (int j = 0; j < 4; ++j) w[j]->ty = v[j];
    _mm256_storeu_pd(v, tz_);
    for (int j = 0; j < 4; ++j) w[j]->tz = v[j];
    _mm256_storeu_pd(index, index_);
  }

 private:
  __m256d tx_, ty_, tz_, dx_, dy_, dz_, sx_, sy_, sz_, index_;
};

/// walkLanesSse2 with groups of eight rays in two AVX2 quadruples. The grouping loop is
/// repeated, not shared: a shared template would be compiled for the default target, and GCC
/// neither inlines AVX2 code into it nor lets it carry the target per instantiation, so every
/// group would pay a call (and a lambda would not inherit the attribute at all).
SOCC_AVX2 std::size_t walkLanesAvx2(const DenseWalks& d, const double* stride) {
  constexpr std::size_t kRays = 8;
  std::size_t next = 0;
  for (; next + kRays <= d.n; next += kRays) {
    RayWalk* w[kRays];
    double index[kRays];
    const int common = d.group(next, kRays, w, index);
    if (common > 0) {
      RayLanes4 p(w, index, stride), q(w + 4, index + 4, stride);
      for (int k = 0; k < common; ++k) {
        p.step(d.grid);
        q.step(d.grid);
      }
      p.store(w, index);
      q.store(w + 4, index + 4);
    }
    d.finish(w, index, kRays, common);
  }
  return next;
}

bool haveAvx2() {
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2;
}
#endif

}  // namespace

void RayFootprint::markRays(const Eigen::Vector3d& origin, const Eigen::Vector3d* ends,
                            std::size_t n, double voxel_size) {
  if (!dense_) {
    Marker mark(*this);
    for (std::size_t i = 0; i < n; ++i) forEachVoxelOnRay(origin, ends[i], voxel_size, mark);
    return;
  }
  if (n == 0) return;
  useGrid();
  const auto markVoxel = [this](const VoxelIndex& v) { markDense(denseIndex(v)); };

  // Walks in order of their unchecked steps (counting sort, capped), so the rays that
  // share the lanes take about as many steps.
  constexpr std::size_t kBuckets = 4096;
  walks_.resize(n);
  order_.resize(n);
  bucket_.assign(kBuckets + 1, 0);
  std::vector<int>& unchecked = unchecked_;
  unchecked.resize(n);
  const double inv = 1.0 / voxel_size;  // startRayWalk's arithmetic, the origin's part once
  const Eigen::Vector3d a = origin * inv;
  const VoxelIndex start(floorToInt(a.x()), floorToInt(a.y()), floorToInt(a.z()));
  for (std::size_t i = 0; i < n; ++i) {
    walks_[i] = startRayWalk(a, start, ends[i], inv);
    unchecked[i] = walks_[i].uncheckedSteps();
    markVoxel(VoxelIndex(walks_[i].x, walks_[i].y, walks_[i].z));
    ++bucket_[std::min(static_cast<std::size_t>(unchecked[i]), kBuckets - 1) + 1];
  }
  for (std::size_t b = 1; b <= kBuckets; ++b) bucket_[b] += bucket_[b - 1];
  for (std::size_t i = 0; i < n; ++i)
    order_[bucket_[std::min(static_cast<std::size_t>(unchecked[i]), kBuckets - 1)]++] =
        static_cast<std::uint32_t>(i);

  const DenseWalks walks{walks_.data(),
                         order_.data(),
                         unchecked.data(),
                         n,
                         grid_.data(),
                         grid_lo_,
                         static_cast<std::size_t>(ny_),
                         static_cast<std::size_t>(nz_)};
  const double stride[3] = {static_cast<double>(ny_) * nz_, static_cast<double>(nz_), 1.0};
  std::size_t next = 0;
#ifdef SOCC_RAY_LANES_AVX2
  if (haveAvx2()) next = walkLanesAvx2(walks, stride);
#endif
#ifdef __SSE2__
  if (next == 0) next = walkLanesSse2(walks, stride);
#endif
  for (; next < n; ++next) continueRayWalk(walks_[order_[next]], markVoxel);
}

void RayFootprint::absorb(RayFootprint& other) {
  if (!dense_) {  // hash mode: the block lists are complete while marking
    merge(other);
    other.slot_of_.clear();
    other.keys_.clear();
    other.masks_.clear();
    other.cache_.fill(CacheEntry{});
    return;
  }
  if (!other.dirty_) return;  // other marked nothing
  useGrid();
  // The same box, so the same grid layout; only words that other marked are non-zero.
  const std::size_t words = static_cast<std::size_t>(nx_) * ny_ * nz_ / 64;
  std::uint64_t* mine = grid_.data();
  std::uint64_t* theirs = other.grid_.data();
  for (std::size_t i = 0; i < words; ++i)
    if (theirs[i] != 0) {
      mine[i] |= theirs[i];
      theirs[i] = 0;
    }
  other.dirty_ = false;
}

}  // namespace socc::map
