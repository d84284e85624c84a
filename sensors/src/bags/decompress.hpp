#pragma once
// Decompression of MCAP chunks and rosbag2 messages into a buffer of the size the container
// announces. Throws FormatError when the bytes do not decompress to exactly that size, and before
// allocating when the size is implausible for the compressed length (a corrupted size field).
#include <cstdint>
#include <string>
#include <vector>

#include "bags/byte_view.hpp"

namespace socc::sensors::bags {

/// compression: "" / "none", "zstd", "lz4" (LZ4 frame format); anything else throws
/// FormatError.
std::vector<std::uint8_t> decompress(const std::string& compression, ByteView compressed,
                                     std::uint64_t uncompressed_size);

/// A whole zstd frame that records its content size (rosbag2's per-message compression).
std::vector<std::uint8_t> decompressZstdFrame(ByteView frame);

/// True when bytes start with the zstd frame magic (28 B5 2F FD); CDR starts with 00.
bool isZstdFrame(ByteView bytes);

/// CRC-32 (ISO-HDLC, as zlib and MCAP compute it).
std::uint32_t crc32Of(ByteView bytes);

}  // namespace socc::sensors::bags
