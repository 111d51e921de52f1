// Owner tags: how a run tells a dead predecessor's leftovers from those of a run still going.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

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

}  // namespace test_atomic_file
