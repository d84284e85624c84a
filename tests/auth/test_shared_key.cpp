#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "socc/auth/shared_key.hpp"

namespace socc::auth {
namespace {
namespace fs = std::filesystem;

class SharedKeyFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("socc_test_auth_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& content, mode_t mode) {
    const fs::path p = dir_ / "key";
    std::ofstream(p, std::ios::binary | std::ios::trunc) << content;
    ::chmod(p.c_str(), mode);
    return p;
  }

  fs::path dir_;
};

std::string expectThrow(const fs::path& p) {
  try {
    SharedKey::fromFile(p);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no exception for " << p;
  return {};
}

const std::string kHex64 = "000102030405060708090a0b0c0d0e0f101112131415161718191a1b1c1d1e1f";

TEST_F(SharedKeyFile, ReadsHexWithTrailingNewline) {
  const SharedKey k = SharedKey::fromFile(write(kHex64 + "\n", 0600));
  ASSERT_EQ(k.size(), 32u);
  EXPECT_EQ(k.data()[0], 0x00);
  EXPECT_EQ(k.data()[31], 0x1f);
}

TEST_F(SharedKeyFile, ReadsRawBytesAndReadOnlyMode) {
  const std::string raw(40, '\xfe');
  const SharedKey k = SharedKey::fromFile(write(raw, 0400));
  EXPECT_EQ(k.size(), 40u);
  EXPECT_EQ(k.data()[0], 0xfe);
}

TEST_F(SharedKeyFile, RefusesGroupOrWorldAccess) {
  for (const mode_t mode : {0644, 0640, 0604, 0660, 0602}) {
    const std::string what = expectThrow(write(kHex64, mode));
    EXPECT_NE(what.find("chmod 600"), std::string::npos) << what;
  }
  EXPECT_NE(expectThrow(write(kHex64, 0644)).find("0644"), std::string::npos);
}

TEST_F(SharedKeyFile, RefusesShortMissingAndDirectories) {
  EXPECT_NE(expectThrow(write("abcdef", 0600)).find("at least 32"), std::string::npos);
  EXPECT_NE(expectThrow(write(kHex64.substr(0, 62), 0600)).find("at least 32"), std::string::npos);
  EXPECT_FALSE(expectThrow(dir_ / "missing").empty());
  ::chmod(dir_.c_str(), 0700);
  EXPECT_NE(expectThrow(dir_).find("not a regular file"), std::string::npos);
}

TEST(SharedKey, FromBytesChecksLengthAndGenerateIsRandom) {
  EXPECT_THROW(SharedKey::fromBytes(std::vector<std::uint8_t>(31, 1)), std::invalid_argument);
  const SharedKey a = SharedKey::generate();
  const SharedKey b = SharedKey::generate();
  ASSERT_EQ(a.size(), SharedKey::kMinBytes);
  EXPECT_NE(std::vector<std::uint8_t>(a.data(), a.data() + a.size()),
            std::vector<std::uint8_t>(b.data(), b.data() + b.size()));
}

}  // namespace
}  // namespace socc::auth
