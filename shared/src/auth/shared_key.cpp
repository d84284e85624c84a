#include "socc/auth/shared_key.hpp"

#include <openssl/crypto.h>
#include <openssl/rand.h>
#include <sys/stat.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <optional>
#include <stdexcept>
#include <string>

namespace socc::auth {
namespace fs = std::filesystem;

namespace {

[[noreturn]] void fail(const fs::path& file, const std::string& why) {
  throw std::runtime_error("key file " + file.string() + ": " + why);
}

// The whole content as hex (whitespace ignored), or nothing when it is not pure hex.
std::optional<std::vector<std::uint8_t>> decodeHex(const std::string& text) {
  std::string digits;
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isspace(u)) continue;
    if (!std::isxdigit(u)) return std::nullopt;
    digits += c;
  }
  if (digits.empty() || digits.size() % 2 != 0) return std::nullopt;
  std::vector<std::uint8_t> bytes(digits.size() / 2);
  for (std::size_t i = 0; i < bytes.size(); ++i)
    bytes[i] = static_cast<std::uint8_t>(std::stoul(digits.substr(2 * i, 2), nullptr, 16));
  return bytes;
}

}  // namespace

SharedKey::SharedKey(std::vector<std::uint8_t> bytes) : bytes_(std::move(bytes)) {}

SharedKey::~SharedKey() {
  if (!bytes_.empty()) OPENSSL_cleanse(bytes_.data(), bytes_.size());
}

SharedKey SharedKey::fromBytes(std::vector<std::uint8_t> bytes) {
  if (bytes.size() < kMinBytes || bytes.size() > kMaxBytes)
    throw std::invalid_argument("shared key must have " + std::to_string(kMinBytes) + ".." +
                                std::to_string(kMaxBytes) + " bytes, got " +
                                std::to_string(bytes.size()));
  return SharedKey(std::move(bytes));
}

SharedKey SharedKey::generate() {
  std::vector<std::uint8_t> bytes(kMinBytes);
  if (RAND_bytes(bytes.data(), static_cast<int>(bytes.size())) != 1)
    throw std::runtime_error("RAND_bytes failed: no key generated");
  return SharedKey(std::move(bytes));
}

SharedKey SharedKey::fromFile(const fs::path& file) {
  // stat() follows symlinks: the permissions that matter are those of the file read.
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0) fail(file, std::strerror(errno));
  if (!S_ISREG(st.st_mode)) fail(file, "not a regular file");
  if ((st.st_mode & (S_IRWXG | S_IRWXO)) != 0) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(st.st_mode & 07777));
    fail(file, std::string("mode ") + mode + " lets group/others access the key; run: chmod 600 " +
                   file.string());
  }
  if (st.st_size > static_cast<off_t>(2 * kMaxBytes + 64)) fail(file, "too large for a key");

  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, "cannot open for reading");
  std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::uint8_t> bytes;
  if (auto hex = decodeHex(content))
    bytes = std::move(*hex);
  else
    bytes.assign(content.begin(), content.end());
  OPENSSL_cleanse(content.data(), content.size());
  if (bytes.size() < kMinBytes)
    fail(file, "key has " + std::to_string(bytes.size()) + " bytes, at least " +
                   std::to_string(kMinBytes) + " needed (e.g. openssl rand -hex 32)");
  if (bytes.size() > kMaxBytes)
    fail(file, "key longer than " + std::to_string(kMaxBytes) + " bytes");
  return SharedKey(std::move(bytes));
}

}  // namespace socc::auth
