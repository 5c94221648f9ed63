// The `cogmap` command: one subcommand per stage of the pipeline. Only app/
// parses argv or prints.
#include <CLI/CLI.hpp>
#include <malloc.h>
#include <time.h>

#include <algorithm>
#include <exception>
#include <iostream>
#include <vector>

#include "app/command.h"
#include "cogmap/core/error.h"

namespace cogmap::app {

static std::vector<Command>& Registry() {
  static std::vector<Command> commands;
  return commands;
}

bool RegisterCommand(Command command) {
  Registry().push_back(std::move(command));
  return true;
}

static std::chrono::steady_clock::time_point process_started;

std::chrono::steady_clock::time_point ProcessStarted() { return process_started; }

}  // namespace cogmap::app

int main(int argc, char** argv) {
  using cogmap::app::Registry;
  {
    timespec cpu{};
    const auto now = std::chrono::steady_clock::now();
    cogmap::app::process_started =
        clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &cpu) == 0
            ? now - std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                        std::chrono::seconds(cpu.tv_sec) + std::chrono::nanoseconds(cpu.tv_nsec))
            : now;
  }
  // One malloc arena for every thread: what the mapper's threads free (the
  // pose graph, the rooms' grids) is then reused by what follows on this
  // thread (the floor plan) instead of held in arenas of their own (a
  // 1000-room run's peak 61 -> 80 MiB with an arena per thread). The threads
  // hand over whole rooms, so they rarely contend for it.
  mallopt(M_ARENA_MAX, 1);
  CLI::App app{
      "cogmap: cognitive maps from range readings and odometry.\n"
      "Each room becomes a small occupancy grid, then a few wall polylines (an\n"
      "Absolute Space Representation), linked to its neighbours by doorways and\n"
      "corrected for heading drift."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "cogmap 0.1.0");
  auto commands = Registry();
  std::sort(commands.begin(), commands.end(),
            [](const auto& a, const auto& b) { return a.order < b.order || (a.order == b.order && a.name < b.name); });
  std::vector<std::function<int()>> runs(commands.size());
  std::vector<CLI::App*> subs;
  for (size_t i = 0; i < commands.size(); ++i) {
    CLI::App* sub = app.add_subcommand(commands[i].name, commands[i].description);
    runs[i] = commands[i].setup(*sub);
    subs.push_back(sub);
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    for (size_t i = 0; i < subs.size(); ++i)
      if (subs[i]->parsed()) return runs[i]();
  } catch (const cogmap::InputError& e) {
    std::cerr << "cogmap: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "cogmap: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
