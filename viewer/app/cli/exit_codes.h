#pragma once

namespace uf::app {

constexpr int kExitOk = 0;
constexpr int kExitError = 1;  // runtime or data error (bad file, bad value, failed stage)
constexpr int kExitUsage = 2;  // usage error (unknown option, invalid option value)

}  // namespace uf::app
