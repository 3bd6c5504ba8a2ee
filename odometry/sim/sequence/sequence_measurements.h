// The measurements of a simulated sequence: the simulators built on its trajectory and scene, the order in
// which their measurements are stamped, and the measurement of each event. Internal to the generator.
#pragma once

#include <optional>
#include <vector>

#include "odometry/io/measurement.h"
#include "odometry/sim/sensors/ray_caster.h"
#include "odometry/sim/sequence/sequence_streams.h"
#include "odometry/sim/sequence/sim_trajectory.h"

namespace uf::sim {

// Every simulator of the sequence, built on its trajectory and scene (which must outlive it). The small
// streams are generated up front; sweeps and frames when their turn comes.
struct Simulators {
  std::optional<SimulatedImu> imu;
  std::optional<LidarSimulator> lidar;
  std::optional<CameraRenderer> camera;
  std::optional<CameraRenderer> right_camera;  // the stereo rig's (cam1)
  std::vector<WheelSample> wheel;
  std::vector<GnssFix> gnss;
};

// Each sensor gets its own seed, derived from config.seed.
Expected<Simulators> MakeSimulators(const SimulationConfig& config, const SimulationTrajectory& motion,
                                    const RayCaster& caster);

// One measurement to produce: its stream, its true time and, for streams generated up front, its index.
struct Event {
  Stamp stamp = 0;  // as stamped by the sensor (true time + stamp delay)
  int stream = 0;
  Stamp true_time = 0;
  std::size_t index = 0;
};

// The start of every LiDAR sweep that is written: whole sweeps of `period` inside [begin, end], sweep j
// starting at begin + j * period; with keyframe_rate_hz > 0 only j = round(k * rate_hz / keyframe_rate_hz),
// k = 0, 1, ... (the others are never cast).
std::vector<Stamp> WrittenSweepStarts(Stamp begin, Stamp end, Stamp period, double rate_hz,
                                      double keyframe_rate_hz);

// Every event of the sequence in stamp order (ties in stream order). LiDAR: WrittenSweepStarts.
std::vector<Event> Schedule(const std::vector<SequenceStream>& streams, const Simulators& simulators,
                            const SimulationTrajectory& motion);

// The measurement of an event, stamped by its sensor; camera frames carry PNG bytes, not pixels.
Expected<MeasurementData> Produce(const Event& event, const SequenceStream& stream,
                                  const Simulators& simulators);

}  // namespace uf::sim
