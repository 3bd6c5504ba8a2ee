// The IMU's reliability score (schedule/imu_score.h) read off the window: its factor over one node interval
// at the blocks' current values.
#pragma once

#include <optional>

#include "odometry/estimator/window/factor_graph.h"
#include "odometry/types/keyframe.h"

namespace uf::estimator {

// The score of the IMU factor tagged `tag` (the interval ending at node `tag`); none when the graph holds no
// such factor.
std::optional<ImuReliability> ScoreImuFactor(const FactorGraph& graph, long tag);

}  // namespace uf::estimator
