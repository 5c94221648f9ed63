#include <CLI/CLI.hpp>
#include <iostream>

int main(int argc, char** argv) {
  CLI::App app{"cogmap: cognitive maps (rooms, walls, exits) from range readings and odometry"};
  app.require_subcommand(1);
  CLI11_PARSE(app, argc, argv);
  return 0;
}
