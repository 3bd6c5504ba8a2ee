// What every subcommand file gives main(): its CLI11 sub-app and the function that runs it.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

#include "odometry/types/status.h"

namespace uf::app {

struct Subcommand {
  CLI::App* command;
  std::function<int()> run;  // returns the process exit code
};

// Prints "ultrafusion: error: ..." to stderr and returns the data-error exit code.
int ReportError(const Status& status);
// The same message, returning the usage-error exit code (bad options or configuration).
int ReportUsageError(const Status& status);

}  // namespace uf::app
