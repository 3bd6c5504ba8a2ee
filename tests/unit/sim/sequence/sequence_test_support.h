// Helpers of the sequence generator's tests.
#pragma once

#include "tests/support/read_all.h"

namespace uf::sim {

using uf::testing::ReadAll;

}  // namespace uf::sim
