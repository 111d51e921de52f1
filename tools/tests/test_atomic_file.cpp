// Owner tags: how a run tells a dead predecessor's leftovers from those of a run still going.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <sys/stat.h>

#include <filesystem>
#include <stdexcept>
#include <string>

#include "tools/atomic_file.hpp"

namespace test_atomic_file {

using tagbench::owner_is_gone;
using tagbench::owner_prefix_is_gone;
using tagbench::owner_tag;

namespace {

// The pid of a child that has exited and been reaped: a process of this host that is gone.
pid_t dead_pid() {
  const pid_t pid = ::fork();
  if (pid == 0) ::_exit(0);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return pid;
}

}  // namespace

TEST(OwnerTag, AProcessThatIsGoneAndOneThatIsNot) {
  const std::string dead = owner_tag(dead_pid()), alive = owner_tag();
  EXPECT_TRUE(owner_is_gone(dead));
  EXPECT_FALSE(owner_is_gone(alive));
  EXPECT_FALSE(owner_is_gone(owner_tag(::getppid())));
  std::string other_host = dead;  // the same pid on another host: never ours to judge
  char& h = other_host[other_host.find('-') + 1];
  h = h == '0' ? '1' : '0';
  EXPECT_FALSE(owner_is_gone(other_host));
  EXPECT_FALSE(owner_is_gone("not-a-tag"));
  EXPECT_FALSE(owner_is_gone(""));
}

TEST(OwnerTag, NamesThatStartWithATag) {
  const std::string dead = owner_tag(dead_pid()), alive = owner_tag();
  EXPECT_TRUE(owner_prefix_is_gone(dead + "-fakepkg"));
  EXPECT_TRUE(owner_prefix_is_gone(dead + "-a-b-c"));
  EXPECT_FALSE(owner_prefix_is_gone(dead));  // no dash after the tag
  EXPECT_FALSE(owner_prefix_is_gone(alive + "-fakepkg"));
  EXPECT_FALSE(owner_prefix_is_gone("x-" + dead + "-rest"));
  EXPECT_FALSE(owner_prefix_is_gone("plain"));
}

TEST(WriteFileAtomic, WritesThroughSymlinksAndRefusesDevicesAndFifos) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("tagbench-atomic-" + owner_tag());
  fs::remove_all(dir);
  fs::create_directories(dir / "sub");
  tagbench::write_file_atomic(dir / "sub" / "real.txt", "old");
  fs::create_symlink(fs::path("sub") / "real.txt", dir / "link.txt");  // relative to the link's folder
  tagbench::write_file_atomic(dir / "link.txt", "new");
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir / "link.txt")));
  EXPECT_EQ(tagbench::read_file(dir / "sub" / "real.txt"), "new");
  fs::create_symlink(dir / "sub" / "absent.txt", dir / "dangling.txt");  // a dangling link: its file is made
  tagbench::write_file_atomic(dir / "dangling.txt", "made");
  EXPECT_EQ(tagbench::read_file(dir / "sub" / "absent.txt"), "made");
  ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0644), 0);
  EXPECT_THROW(tagbench::write_file_atomic(dir / "fifo", "x"), std::runtime_error);
  EXPECT_TRUE(fs::is_fifo(fs::status(dir / "fifo")));
  EXPECT_THROW(tagbench::write_file_atomic(dir / "sub", "x"), std::runtime_error);
  EXPECT_THROW(tagbench::write_files_atomic({{dir / "a.txt", "a"}, {"/dev/null", "b"}}), std::runtime_error);
  EXPECT_FALSE(fs::exists(dir / "a.txt"));  // nothing of the set written
  fs::remove_all(dir);
}

}  // namespace test_atomic_file
