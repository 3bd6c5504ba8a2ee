// A test suite over one small simulated sequence: 4 s of the urban scene with a 16-beam LiDAR, an IMU and
// GNSS (tests/integration/sim_small.yaml), made once per suite with `ultrafusion sim`.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "tests/support/cli_runner.h"
#include "tests/support/temp_dir.h"

namespace uf::testing {

class SimulatedSequenceTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<TempDir>();
    const auto sim = test::Ultrafusion(
        "sim --scene urban --duration 4 --no-camera --lidar spinning16 --config " +
        std::string(UF_SOURCE_DIR) + "/tests/integration/sim_small.yaml --out " + Sequence());
    ASSERT_EQ(sim.code, 0) << sim.output;
  }
  static void TearDownTestSuite() { dir_.reset(); }
  static std::string Sequence() { return dir_->File("seq"); }
  static inline std::unique_ptr<TempDir> dir_;
};

}  // namespace uf::testing
