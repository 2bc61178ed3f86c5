// Running the command-line tools from tests: exit code and output, a scratch folder.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace hope {
namespace test {

struct CliRun {
  int exit_code;
  std::string output;  // stdout and stderr
};

// Runs `binary args`, stdout and stderr together.
inline CliRun runTool(const std::string& binary, const std::string& args) {
  const std::string cmd = binary + " " + args + " 2>&1";
  CliRun r{-1, ""};
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  char buffer[4096];
  while (std::fgets(buffer, sizeof(buffer), pipe)) r.output += buffer;
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

inline std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/hope_cli_XXXXXX";
    dir_ = mkdtemp(tmpl);
  }
  void TearDown() override { std::system(("rm -rf " + dir_).c_str()); }
  std::string dir_;
};

// hope_extract with `args`.
inline CliRun run(const std::string& args) { return runTool(HOPE_EXTRACT_BIN, args); }

// One of the command-line tools (hope_eval, hope_track_eval, …): they are all built beside
// hope_extract.
inline std::string toolBinary(const std::string& tool) {
  const std::string extract = HOPE_EXTRACT_BIN;
  return extract.substr(0, extract.rfind('/') + 1) + tool;
}

}  // namespace test
}  // namespace hope
