// Test helpers shared by the file-writing unit tests: a scratch directory per test, and (from
// messages.hpp) the message of an expected std::invalid_argument.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstddef>
#include <filesystem>
#include <iterator>
#include <stdexcept>
#include <string>

#include "../common/messages.hpp"
#include "asperity/apps/common/output_files.hpp"

namespace asperity::test_support {

// A fresh, empty directory per test (named after the process and the test), removed after it.
class ScratchDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("asperity_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->test_suite_name() + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    app::ensure_directory(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // Files and folders in the directory (atomic writes must leave no temporaries behind).
  std::size_t entries() const {
    return static_cast<std::size_t>(std::distance(std::filesystem::directory_iterator(dir_), {}));
  }

  std::filesystem::path dir_;
};

}  // namespace asperity::test_support
