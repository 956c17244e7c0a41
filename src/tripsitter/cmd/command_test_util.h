// What the tests that run the built `tripsitter` share: a scratch directory per test, reading a file whole,
// and running a shell command with its output captured.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace tripsitter::cmd::test {

namespace fs = std::filesystem;

// A fresh, empty directory for the running test: `prefix`, the process id and the test's name.
inline fs::path scratch_dir(const std::string& prefix) {
  const fs::path dir = fs::temp_directory_path() / (prefix + std::to_string(::getpid()) + "_" +
                                                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Result {
  int exit_code = -1;  // -1: killed by a signal
  std::string out, err;
};

// Runs `command` (shell words, stdin redirected by the caller) with stdout and stderr in `log_dir`.
inline Result run_shell(const std::string& command, const fs::path& log_dir) {
  fs::create_directories(log_dir);
  const fs::path out = log_dir / "stdout", err = log_dir / "stderr";
  const int status = std::system((command + " >" + out.string() + " 2>" + err.string()).c_str());
  Result r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

}  // namespace tripsitter::cmd::test
