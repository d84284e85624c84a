#pragma once
// The secret shared by the map server and its clients for HMAC-SHA256 request signing.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace socc::auth {

class SharedKey {
 public:
  static constexpr std::size_t kMinBytes = 32;  // = SHA-256 output: shorter keys weaken HMAC
  static constexpr std::size_t kMaxBytes = 4096;

  /// Reads a key file: hex digits (whitespace ignored) or raw bytes, at least kMinBytes after
  /// decoding. Refuses (std::runtime_error) files that group or others may read or write
  /// (mode must be 0600 or 0400), missing/unreadable files and too short keys.
  static SharedKey fromFile(const std::filesystem::path& file);
  /// A key from bytes (at least kMinBytes), e.g. generated in tests.
  static SharedKey fromBytes(std::vector<std::uint8_t> bytes);
  /// kMinBytes fresh bytes from OpenSSL's CSPRNG.
  static SharedKey generate();

  SharedKey(const SharedKey&) = default;
  SharedKey& operator=(const SharedKey&) = default;
  SharedKey(SharedKey&&) noexcept = default;
  SharedKey& operator=(SharedKey&&) noexcept = default;
  ~SharedKey();  // wipes the key bytes

  const std::uint8_t* data() const { return bytes_.data(); }
  std::size_t size() const { return bytes_.size(); }

 private:
  explicit SharedKey(std::vector<std::uint8_t> bytes);
  std::vector<std::uint8_t> bytes_;
};

}  // namespace socc::auth
