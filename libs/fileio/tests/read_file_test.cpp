// The checked reader: a FIFO, a device and a directory are refused without blocking, a file over
// the limit without being read; the error names the file.
#include "libs/fileio/read_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include "libs/fileio/file_source.h"
#include "tests/support/test_support.h"

namespace sylva::fileio {
namespace {

TEST(ReadFile, ReadsARegularFileWhole) {
  test::TempDir dir;
  test::write_file(dir / "a.txt", std::string("abc\0def", 7));
  EXPECT_EQ(read_file(dir / "a.txt"), std::string("abc\0def", 7));
  EXPECT_EQ(disk_files().read(dir / "a.txt"), std::string("abc\0def", 7));
  EXPECT_TRUE(disk_files().exists(dir / "a.txt"));
  EXPECT_FALSE(disk_files().exists(dir / "b.txt"));
}

TEST(ReadFile, RefusesWhatIsNotARegularFileWithoutBlocking) {
  test::TempDir dir;
  ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0644), 0);
  std::string why;
  EXPECT_FALSE(read_regular_file(dir / "fifo", &why));
  EXPECT_EQ(why, "not a regular file");
  EXPECT_FALSE(read_regular_file("/dev/zero", &why));
  EXPECT_EQ(why, "not a regular file");
  EXPECT_FALSE(read_regular_file(dir.path(), &why));
  EXPECT_EQ(why, "Is a directory");
  EXPECT_FALSE(read_regular_file(dir / "missing", &why));
  EXPECT_EQ(why, "No such file or directory");
}

TEST(ReadFile, RefusesAFileOverTheLimitAndNamesTheFile) {
  test::TempDir dir;
  test::write_file(dir / "big", std::string(100, 'x'));
  std::string why;
  EXPECT_FALSE(read_regular_file(dir / "big", &why, 99));
  EXPECT_EQ(why, "larger than 99 bytes");
  EXPECT_TRUE(read_regular_file(dir / "big", &why, 100));
  try {
    read_file(dir / "big", 10);
    FAIL() << "expected FileReadError";
  } catch (const FileReadError& e) {
    EXPECT_EQ(std::string(e.what()), (dir / "big").string() + ": error: larger than 10 bytes");
  }
}

}  // namespace
}  // namespace sylva::fileio
