#include "viewer/app/cli/subcommand.h"

#include <iostream>

#include "viewer/app/cli/exit_codes.h"

namespace uf::app {

int ReportError(const Status& status) {
  std::cerr << "ultrafusion: error: " << status.message() << "\n";
  return kExitError;
}

int ReportUsageError(const Status& status) {
  ReportError(status);
  return kExitUsage;
}

}  // namespace uf::app
