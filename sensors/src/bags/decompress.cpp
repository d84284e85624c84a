#include "bags/decompress.hpp"

#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <memory>

namespace socc::sensors::bags {

namespace {

// Beyond this ratio (plus a floor for small chunks) an announced size is a corrupted field:
// real LiDAR chunks compress far less.
constexpr std::uint64_t kMaxRatio = 1024;
constexpr std::uint64_t kSizeFloor = 16u << 20;

void checkPlausible(ByteView compressed, std::uint64_t size) {
  if (size > kSizeFloor + kMaxRatio * compressed.size) {
    throw FormatError("chunk of " + std::to_string(compressed.size) + " bytes announces " +
                      std::to_string(size) + " uncompressed");
  }
}

void zstdInto(ByteView in, std::vector<std::uint8_t>& out) {
  const std::size_t n = ZSTD_decompress(out.data(), out.size(), in.data, in.size);
  if (ZSTD_isError(n)) throw FormatError(std::string("zstd: ") + ZSTD_getErrorName(n));
  if (n != out.size()) throw FormatError("zstd chunk shorter than announced");
}

void lz4Into(ByteView in, std::vector<std::uint8_t>& out) {
  LZ4F_dctx* raw = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION))) {
    throw FormatError("lz4: no context");
  }
  const std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> ctx(
      raw, &LZ4F_freeDecompressionContext);
  std::size_t in_pos = 0;
  std::size_t out_pos = 0;
  std::size_t hint = 1;
  while (hint != 0) {
    std::size_t in_size = in.size - in_pos;
    std::size_t out_size = out.size() - out_pos;
    hint = LZ4F_decompress(ctx.get(), out.data() + out_pos, &out_size, in.data + in_pos, &in_size,
                           nullptr);
    if (LZ4F_isError(hint)) throw FormatError(std::string("lz4: ") + LZ4F_getErrorName(hint));
    in_pos += in_size;
    out_pos += out_size;
    if (hint != 0 && in_size == 0 && out_size == 0) throw FormatError("lz4: truncated frame");
  }
  if (out_pos != out.size()) throw FormatError("lz4 chunk shorter than announced");
}

}  // namespace

std::vector<std::uint8_t> decompress(const std::string& compression, ByteView compressed,
                                     std::uint64_t uncompressed_size) {
  if (compression.empty() || compression == "none") {
    if (uncompressed_size != compressed.size) throw FormatError("chunk size mismatch");
    return std::vector<std::uint8_t>(compressed.data, compressed.data + compressed.size);
  }
  checkPlausible(compressed, uncompressed_size);
  std::vector<std::uint8_t> out(static_cast<std::size_t>(uncompressed_size));
  if (compression == "zstd") {
    zstdInto(compressed, out);
  } else if (compression == "lz4") {
    lz4Into(compressed, out);
  } else {
    throw FormatError("compression '" + compression + "' is not supported");
  }
  return out;
}

std::vector<std::uint8_t> decompressZstdFrame(ByteView frame) {
  const unsigned long long size = ZSTD_getFrameContentSize(frame.data, frame.size);
  if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN) {
    throw FormatError("zstd frame without its content size");
  }
  return decompress("zstd", frame, size);
}

bool isZstdFrame(ByteView bytes) {
  return bytes.size >= 4 && bytes.data[0] == 0x28 && bytes.data[1] == 0xB5 &&
         bytes.data[2] == 0x2F && bytes.data[3] == 0xFD;
}

std::uint32_t crc32Of(ByteView bytes) {
  uLong crc = crc32(0L, Z_NULL, 0);
  std::size_t done = 0;
  while (done < bytes.size) {  // zlib takes uInt lengths
    const auto n = static_cast<uInt>(std::min<std::size_t>(bytes.size - done, 1u << 30));
    crc = crc32(crc, bytes.data + done, n);
    done += n;
  }
  return static_cast<std::uint32_t>(crc);
}

}  // namespace socc::sensors::bags
