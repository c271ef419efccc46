// core/text_file.hpp's atomic write: a regular file is replaced through a temporary file; a symlink
// stays a link and its target gets the content; a device or FIFO is written through, never
// replaced (renaming a file over /dev/null replaced the device when run as root).
#include "trueaxis/core/text_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis {
namespace {
namespace fs = std::filesystem;

class AtomicWrite : public ::testing::Test {
 protected:
  fs::path dir = fs::temp_directory_path() / ("trueaxis_text_file_" + std::to_string(::getpid()));
  void SetUp() override { fs::create_directories(dir); }
  void TearDown() override { fs::remove_all(dir); }
  static std::string Read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
};

TEST_F(AtomicWrite, ReplacesARegularFileAndLeavesNoTemporary) {
  const fs::path f = dir / "out.csv";
  WriteTextFile(f.string(), "old");
  WriteTextFile(f.string(), "new");
  EXPECT_EQ(Read(f), "new");
  EXPECT_FALSE(fs::exists(dir / "out.csv.tmp"));
}

TEST_F(AtomicWrite, ASymlinkStaysALinkAndItsTargetGetsTheContent) {
  const fs::path target = dir / "real.csv", link = dir / "link.csv";
  WriteTextFile(target.string(), "old");
  fs::create_symlink(target, link);
  WriteTextFile(link.string(), "new");
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link)));
  EXPECT_EQ(Read(target), "new");
}

TEST_F(AtomicWrite, AFifoIsWrittenThroughNotReplaced) {
  const fs::path fifo = dir / "pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] { received = Read(fifo); });  // opens, reads to EOF
  WriteTextFile(fifo.string(), "through the pipe");
  reader.join();
  EXPECT_EQ(received, "through the pipe");
  struct stat st {};
  ASSERT_EQ(::lstat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode)) << "the FIFO was replaced by a file";
  EXPECT_FALSE(fs::exists(dir / "pipe.tmp"));
}

TEST_F(AtomicWrite, ADirectoryIsAnInputErrorNamingIt) {
  try {
    WriteTextFile(dir.string(), "x");
    FAIL() << "wrote over a directory";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), dir.string());
    EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_directory(dir));
}

}  // namespace
}  // namespace trueaxis
