#include "hope/tools/cli.h"

#include <exception>
#include <iostream>
#include <stdexcept>

namespace hope {
namespace tools {

int runTool(const char* tool, int (*run)(int, char**), int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::invalid_argument& e) {
    std::cerr << tool << ": error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << tool << ": error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace tools
}  // namespace hope
