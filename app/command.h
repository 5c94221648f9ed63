#pragma once
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

namespace cogmap::app {

// One `cogmap` subcommand. Each cmd_*.cc registers itself with
//   static const bool kRegistered = RegisterCommand({...});
// 'setup' adds the options to 'sub' and returns the function that runs the
// command after parsing (returning the exit status). Library InputErrors
// thrown by 'run' are printed on one line by main() with exit status 2.
struct Command {
  std::string name;
  std::string description;
  int order = 100;  // position in --help
  std::function<std::function<int()>(CLI::App& sub)> setup;
};

bool RegisterCommand(Command command);

}  // namespace cogmap::app
