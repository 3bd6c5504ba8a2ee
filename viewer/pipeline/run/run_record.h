// run.json: what a run folder says about the run that made it, read back by `ultrafusion splat RUN_DIR` (and
// by run --from splat) to read the dataset again and place its images without working out the frames anew:
//
//   {"dataset": "/abs/path", "mode": "lo" | "lio", "output_frame": "lidar" | "imu",
//    "map_from": "odometry" | "trajectory",
//    "frames": {"T_imu_lidar": 4x4 | null, "T_estimator_body": 4x4, "T_output_body": 4x4,
//               "T_map_world": 4x4}}
//
// Matrices are row-major arrays of 4 rows; numbers are written with enough digits to read back exactly
// (nlohmann::json's shortest round-trip form). The frames are those of run_frames.h.
#pragma once

#include <filesystem>
#include <string>

#include "odometry/types/status.h"
#include "viewer/pipeline/run/run_frames.h"

namespace uf::pipeline {

inline constexpr const char* kRunJsonFile = "run.json";

struct RunRecord {
  std::string dataset;  // absolute path
  RunFrames frames;
};

// Writes folder/run.json atomically.
Status WriteRunRecord(const std::filesystem::path& folder, const RunRecord& record);

// Reads folder/run.json. A folder without one, or with one from before the frames were recorded, gets an
// error that says to re-run `ultrafusion run`; other errors name the field and the value.
Expected<RunRecord> ReadRunRecord(const std::filesystem::path& folder);

}  // namespace uf::pipeline
