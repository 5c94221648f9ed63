#pragma once
#include <CLI/CLI.hpp>
#include <chrono>
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

// When the process began: main()'s first instant less the CPU time spent
// before it (the dynamic loader's and the static initialisers', on one
// thread: its wall time but for waits on the disk). Commands that report
// their whole time (report.json's total_seconds) count from here.
std::chrono::steady_clock::time_point ProcessStarted();

}  // namespace cogmap::app
