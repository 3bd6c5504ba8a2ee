// `ultrafusion eval REFERENCE ESTIMATE`: evo-compatible trajectory accuracy (APE, RPE, KITTI drift), printed
// as a table and optionally written as JSON and PNG plots.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace uf::app {

struct Subcommand {
  CLI::App* command;
  std::function<int()> run;  // returns the process exit code
};

Subcommand AddEvalCommand(CLI::App& app);

}  // namespace uf::app
