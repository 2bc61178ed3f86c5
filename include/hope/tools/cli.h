// The command-line tools' shared entry point: one error convention for all of them.
#pragma once

namespace hope {
namespace tools {

// Runs `run(argc, argv)` and returns its exit code. An exception ends the tool with
// "<tool>: error: <what>" on stderr and exit code 2 for std::invalid_argument (bad arguments
// or values) or 1 for anything else (unreadable or unwritable files, …).
int runTool(const char* tool, int (*run)(int, char**), int argc, char** argv);

}  // namespace tools
}  // namespace hope
