// Issue 37: SIGINT and SIGTERM during a write left 100-195 MB temporaries beside the output
// (and slice a folder of layers). The handler the command line installs removes what the
// writers registered, then ends the process as the signal would have.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>

#include "io/interrupt_cleanup.hpp"
#include "test_util.hpp"

namespace tpmsfill {
namespace {

namespace fs = std::filesystem;
using detail::RemovedOnInterrupt;

TEST(InterruptCleanup, ASignalRemovesTheRegisteredFilesAndFoldersAndEndsTheProcess) {
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
    const fs::path dir = test::scratch_dir();
    const fs::path staged = dir / ".out.stl.staged-1-0", layers = dir / "layers.tmp-1",
                   kept = dir / "out.stl";
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      // A shell's background jobs start with SIGINT ignored, and an ignored signal stays so
      // (the test below): each signal starts at its default here, as in a terminal.
      for (const int s : {SIGINT, SIGTERM, SIGHUP}) std::signal(s, SIG_DFL);
      detail::remove_registered_paths_on_signals();
      test::write_file(staged, "partial");
      fs::create_directory(layers);
      for (int k = 0; k < 300; ++k) test::write_file(layers / ("layer-" + std::to_string(k)), "x");
      const RemovedOnInterrupt a(staged, RemovedOnInterrupt::Kind::File);
      const RemovedOnInterrupt b(layers, RemovedOnInterrupt::Kind::Folder);
      test::write_file(kept, "finished");
      RemovedOnInterrupt c(kept, RemovedOnInterrupt::Kind::File);
      c.release();  // renamed into place: no longer the process's to remove
      raise(signal);
      _exit(0);  // not reached: the signal ends the process
    }
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFSIGNALED(status)) << status;
    EXPECT_EQ(WTERMSIG(status), signal);
    EXPECT_FALSE(fs::exists(staged)) << signal;
    EXPECT_FALSE(fs::exists(layers)) << signal;
    EXPECT_TRUE(fs::exists(kept)) << signal;
  }
}

TEST(InterruptCleanup, ASignalIgnoredAtStartStaysIgnored) {
  // `nohup tpmsfill fill ...`: SIGHUP is ignored and must stay so, the job running on.
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    signal(SIGHUP, SIG_IGN);
    detail::remove_registered_paths_on_signals();
    raise(SIGHUP);
    _exit(7);
  }
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << status;
  EXPECT_EQ(WEXITSTATUS(status), 7);
}

}  // namespace
}  // namespace tpmsfill
