#pragma once
// Tests that read the real measurements in ../shared/data (beside the repository, not in it) skip
// with a message when that folder is absent, instead of failing on a missing file.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#define TRUEAXIS_SKIP_WITHOUT_SHARED_FILE(path)                                                            \
  do {                                                                                                     \
    if (!std::filesystem::exists(path))                                                                    \
      GTEST_SKIP() << (path) << " is absent: this test reads ../shared/data (real measurements kept beside " \
                                "the repository); check it out there to run it";                           \
  } while (0)
