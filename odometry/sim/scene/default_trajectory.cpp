#include "odometry/sim/scene/default_trajectory.h"

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "odometry/sim/scene/scene_builder.h"
#include "odometry/sim/scene/scene_placement.h"

namespace uf::sim {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kStandStill = 1.0;  // s
constexpr double kDt = 0.01;         // output period, s

// A curvature event over arc length [s0, s0 + length], x = (s - s0) / length in [0, 1]:
//   turn:        kappa = k sin^2(pi x)                      (C1; heading change k length / 2)
//   lane change: kappa = k sin(2 pi x) sin^2(pi x)
//              = k (sin(2 pi x) / 2 - sin(4 pi x) / 4)     (C1; zero net heading change; lateral shift
//                k length^2 int_0^1 (1 - x) f(x) dx = k length^2 * 3 / (16 pi))
struct CurvatureEvent {
  double s0, length, k;
  bool lane_change;
};

struct Wave {
  double amplitude, frequency, phase;  // amplitude * sin(2 pi frequency * arg + phase)
  double operator()(double arg) const { return amplitude * std::sin(2.0 * kPi * frequency * arg + phase); }
  double Derivative(double arg) const {
    return amplitude * 2.0 * kPi * frequency * std::cos(2.0 * kPi * frequency * arg + phase);
  }
};

struct MotionProfile {
  double cruise = 1.0, ramp_s = 5.0;          // m/s, s
  double wobble = 0.0, wobble_period = 20.0;  // relative speed variation after the ramp
  std::vector<CurvatureEvent> events;
  std::vector<Wave> z_waves;                  // height over arc length (frequency in 1/m)
  std::vector<Wave> roll_waves, pitch_waves;  // rad over time (frequency in Hz)
  double lean = 0.0, squat = 0.0;             // rad per m/s^2 of lateral / longitudinal acceleration
};

double Smoothstep5(double u) {
  if (u <= 0.0) return 0.0;
  if (u >= 1.0) return 1.0;
  return u * u * u * (u * (u * 6.0 - 15.0) + 10.0);
}
double Smoothstep5Derivative(double u) {
  return (u <= 0.0 || u >= 1.0) ? 0.0 : 30.0 * u * u * (u - 1.0) * (u - 1.0);
}

double Curvature(const MotionProfile& m, double s) {
  double kappa = 0.0;
  for (const CurvatureEvent& e : m.events) {
    const double x = (s - e.s0) / e.length;
    if (x <= 0.0 || x >= 1.0) continue;
    const double bump = std::sin(kPi * x) * std::sin(kPi * x);
    kappa += e.k * (e.lane_change ? std::sin(2.0 * kPi * x) * bump : bump);
  }
  return kappa;
}

// v(t) = cruise S(u) (1 + wobble sin(2 pi (t - 1) / period)), u = (t - 1) / ramp: C2, zero while standing.
double Speed(const MotionProfile& m, double t, double* accel = nullptr) {
  const double u = (t - kStandStill) / m.ramp_s;
  const double w = 2.0 * kPi / m.wobble_period, tau = t - kStandStill;
  const double mod = 1.0 + m.wobble * std::sin(w * tau);
  if (accel != nullptr) {
    *accel = m.cruise *
             (Smoothstep5Derivative(u) / m.ramp_s * mod + Smoothstep5(u) * m.wobble * w * std::cos(w * tau));
  }
  return m.cruise * Smoothstep5(u) * mod;
}

// The height over arc length: zero at arg = 0, so the track starts at the world origin.
double Sum(const std::vector<Wave>& waves, double arg) {
  double sum = 0.0;
  for (const Wave& w : waves) sum += w(arg) - w(0.0);  // zero at arg = 0
  return sum;
}

// The suspension's oscillation about its equilibrium: zero-mean (not shifted to zero at arg = 0, which
// would add a constant offset of up to the amplitudes' sum, a tilt of the body against the road that only
// appears while moving: a mounting error no real suspension has). The callers scale it by v / v_cruise,
// which keeps the standing second exactly still and the attitude C2 where the motion starts.
double Oscillation(const std::vector<Wave>& waves, double arg) {
  double sum = 0.0;
  for (const Wave& w : waves) sum += w(arg);
  return sum;
}

std::vector<Wave> RandomWaves(std::mt19937_64& rng, std::initializer_list<std::pair<double, double>> spec) {
  std::vector<Wave> out;
  for (const auto& [amplitude, frequency] : spec) {
    out.push_back({amplitude, frequency * Uniform(rng, 0.85, 1.15), Uniform(rng, 0.0, 2.0 * kPi)});
  }
  return out;
}

// Turns (heading change in rad) and lane changes (lateral shift in m) along the whole distance.
void AddTurn(MotionProfile& m, double s0, double length, double heading_change) {
  m.events.push_back({s0, length, 2.0 * heading_change / length, false});
}
void AddLaneChange(MotionProfile& m, double s0, double length, double shift) {
  m.events.push_back({s0, length, shift / (length * length * 3.0 / (16.0 * kPi)), true});
}

MotionProfile MakeProfile(std::string_view scene, double distance, std::mt19937_64& rng) {
  MotionProfile m;
  const double deg = kPi / 180.0;
  auto sign = [&]() { return Chance(rng, 0.5) ? 1.0 : -1.0; };
  if (scene == "urban") {
    m.cruise = 8.0, m.ramp_s = 6.0, m.wobble = 0.08, m.wobble_period = 18.0;
    for (double s = Uniform(rng, 25.0, 50.0); s < distance; s += Uniform(rng, 20.0, 50.0)) {
      const double length = Uniform(rng, 50.0, 80.0);
      if (Chance(rng, 0.6)) {
        AddTurn(m, s, length, sign() * Uniform(rng, 15.0, 45.0) * deg);
      } else {
        AddLaneChange(m, s, length, sign() * 3.5);
      }
      s += length;
    }
    m.z_waves = RandomWaves(rng, {{2.0, 1.0 / 400.0}, {0.5, 1.0 / 150.0}});
    m.roll_waves = RandomWaves(rng, {{0.012, 1.1}, {0.006, 1.8}});
    m.pitch_waves = RandomWaves(rng, {{0.010, 0.9}, {0.005, 1.6}});
    m.lean = 0.01, m.squat = 0.008;
  } else if (scene == "wild") {
    m.cruise = 3.0, m.ramp_s = 4.0, m.wobble = 0.15, m.wobble_period = 12.0;
    for (double s = Uniform(rng, 5.0, 15.0); s < distance; s += Uniform(rng, 5.0, 20.0)) {
      const double length = Uniform(rng, 15.0, 35.0);
      AddTurn(m, s, length, sign() * Uniform(rng, 20.0, 80.0) * deg);
      s += length;
    }
    m.z_waves = RandomWaves(rng, {{1.2, 1.0 / 90.0}, {0.25, 1.0 / 30.0}});  // grade up to ~14 %
    m.roll_waves = RandomWaves(rng, {{0.05, 0.6}, {0.03, 1.1}, {0.012, 1.8}});
    m.pitch_waves = RandomWaves(rng, {{0.04, 0.5}, {0.025, 1.0}, {0.01, 1.7}});
    m.lean = 0.02, m.squat = 0.01;
  } else if (scene == "warehouse") {
    // Serpentine: an aisle, two 90-degree turns the same way around a short cross aisle, the next aisle
    // back, then two turns the other way.
    m.cruise = 1.5, m.ramp_s = 3.0;
    double turn = sign();
    for (double s = Uniform(rng, 18.0, 28.0); s < distance; s += Uniform(rng, 18.0, 28.0)) {
      AddTurn(m, s, 7.0, turn * kPi / 2.0);
      AddTurn(m, s + 8.0, 7.0, turn * kPi / 2.0);
      s += 15.0;
      turn = -turn;
    }
    m.roll_waves = RandomWaves(rng, {{0.004, 1.5}});
    m.pitch_waves = RandomWaves(rng, {{0.004, 1.2}});
    m.lean = 0.005, m.squat = 0.005;
  } else if (scene == "corridor") {
    m.cruise = 1.2, m.ramp_s = 3.0;
    double turn = sign();
    for (double s = Uniform(rng, 3.0, 8.0); s < distance; s += Uniform(rng, 3.0, 10.0)) {
      const double length = Uniform(rng, 8.0, 15.0);
      AddTurn(m, s, length, turn * Uniform(rng, 2.0, 6.0) * deg);
      turn = -turn;  // alternate, so the heading stays within a few degrees
      s += length;
    }
    m.roll_waves = RandomWaves(rng, {{0.008, 1.0}});
    m.pitch_waves = RandomWaves(rng, {{0.006, 1.8}});
    m.lean = 0.005, m.squat = 0.005;
  } else {  // tunnel
    m.cruise = 12.0, m.ramp_s = 8.0, m.wobble = 0.05, m.wobble_period = 25.0;
    for (double s = Uniform(rng, 40.0, 80.0); s < distance; s += Uniform(rng, 40.0, 120.0)) {
      const double length = Uniform(rng, 120.0, 250.0);
      if (Chance(rng, 0.6)) {
        AddTurn(m, s, length, sign() * Uniform(rng, 3.0, 10.0) * deg);
      } else {
        AddLaneChange(m, s, length, sign() * 3.5);
      }
      s += length;
    }
    m.z_waves = RandomWaves(rng, {{3.0, 1.0 / 800.0}});
    m.roll_waves = RandomWaves(rng, {{0.008, 1.2}});
    m.pitch_waves = RandomWaves(rng, {{0.008, 0.9}});
    m.lean = 0.01, m.squat = 0.008;
  }
  return m;
}

// The scene's path: its profile (drawn from the seed exactly as for the vehicle, so that every motion
// follows the same curvature and heights over arc length) and the checks of the inputs.
Expected<MotionProfile> ScenePathProfile(std::string_view scene, double duration_s, std::uint64_t seed) {
  if (DefaultCruiseSpeed(scene) == 0.0) {
    std::string names;
    for (const std::string_view name : SceneNames()) names += (names.empty() ? "" : ", ") + std::string(name);
    return Status::Error("trajectory.scene: unknown scene '" + std::string(scene) +
                         "', expected one of: " + names);
  }
  if (!(duration_s >= 2.0 && duration_s <= 7200.0)) {
    return Status::Error("trajectory.duration_s: must be in [2, 7200], got " + std::to_string(duration_s));
  }
  std::mt19937_64 rng(SubSeed(seed, std::string("trajectory/") + std::string(scene)));
  return MakeProfile(scene, DefaultCruiseSpeed(scene) * 1.3 * duration_s + 100.0, rng);
}

// Integrates the track over duration_s and calls visit(i, t, q) at each output sample i (t = i * kDt s from
// the start) with q = (s, heading, x, y): RK4, two 5 ms steps per output, of ds/dt = v(t),
// dheading/dt = v kappa(s), dx/dt = v cos(heading), dy/dt = v sin(heading).
using TrackState = Eigen::Vector4d;
template <typename Visit>
void IntegrateTrack(const MotionProfile& m, double duration_s, Visit visit) {
  auto derivative = [&](double t, const TrackState& q) {
    const double v = Speed(m, t);
    return TrackState(v, v * Curvature(m, q[0]), v * std::cos(q[1]), v * std::sin(q[1]));
  };
  const auto count = static_cast<std::int64_t>(std::llround(duration_s / kDt));
  TrackState q = TrackState::Zero();
  for (std::int64_t i = 0; i <= count; ++i) {
    const double t = static_cast<double>(i) * kDt;
    if (i > 0) {
      for (int sub = 0; sub < 2; ++sub) {
        const double h = 0.5 * kDt, t0 = t - kDt + sub * h;
        const TrackState k1 = derivative(t0, q), k2 = derivative(t0 + 0.5 * h, q + 0.5 * h * k1);
        const TrackState k3 = derivative(t0 + 0.5 * h, q + 0.5 * h * k2), k4 = derivative(t0 + h, q + h * k3);
        q += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
      }
    }
    visit(i, t, q);
  }
}

Stamp SampleStamp(Stamp start_stamp, std::int64_t i) {
  return start_stamp + i * (kNanosecondsPerSecond / 100);
}

}  // namespace

const std::vector<std::string_view>& MotionNames() {
  static const std::vector<std::string_view> names = {"vehicle", "handheld"};
  return names;
}

std::string_view MotionName(Motion motion) { return MotionNames()[motion == Motion::kVehicle ? 0 : 1]; }

Expected<Motion> ParseMotion(std::string_view name) {
  for (Motion motion : {Motion::kVehicle, Motion::kHandheld})
    if (MotionName(motion) == name) return motion;
  return Status::Error("unknown motion '" + std::string(name) + "' (vehicle, handheld)");
}

double DefaultCruiseSpeed(std::string_view scene) {
  if (scene == "urban") return 8.0;
  if (scene == "wild") return 3.0;
  if (scene == "warehouse") return 1.5;
  if (scene == "corridor") return 1.2;
  if (scene == "tunnel") return 12.0;
  return 0.0;
}

Expected<Trajectory> DefaultSceneTrajectory(std::string_view scene, double duration_s, std::uint64_t seed,
                                            Stamp start_stamp) {
  Expected<MotionProfile> profile = ScenePathProfile(scene, duration_s, seed);
  if (!profile) return profile.status();
  const MotionProfile& m = *profile;
  Trajectory out;
  IntegrateTrack(m, duration_s, [&](std::int64_t i, double t, const TrackState& q) {
    double a_long = 0.0;
    const double v = Speed(m, t, &a_long);
    const double a_lat = v * v * Curvature(m, q[0]);
    const double motion = v / m.cruise;  // 0 while standing still
    double grade = 0.0;
    for (const Wave& w : m.z_waves) grade += w.Derivative(q[0]);
    const double z = Sum(m.z_waves, q[0]);
    const double roll = m.lean * a_lat + motion * Oscillation(m.roll_waves, t);
    const double pitch = -std::atan(grade) - m.squat * a_long + motion * Oscillation(m.pitch_waves, t);
    // R_world_body = Rz(heading) Ry(pitch) Rx(roll): x forward, y left, z up.
    const Eigen::Matrix3d R = SO3::Exp(Eigen::Vector3d(0, 0, q[1])).matrix() *
                              SO3::Exp(Eigen::Vector3d(0, pitch, 0)).matrix() *
                              SO3::Exp(Eigen::Vector3d(roll, 0, 0)).matrix();
    out.stamps.push_back(SampleStamp(start_stamp, i));
    out.poses.emplace_back(SO3(R), Eigen::Vector3d(q[2], q[3], z));
  });
  return out;
}

Expected<Trajectory> DefaultScenePath(std::string_view scene, double duration_s, std::uint64_t seed,
                                      Stamp start_stamp, const PathSpeed& speed) {
  Expected<MotionProfile> profile = ScenePathProfile(scene, duration_s, seed);
  if (!profile) return profile.status();
  MotionProfile& m = *profile;
  m.cruise = speed.cruise_m_s, m.ramp_s = speed.ramp_s;
  m.wobble = speed.wobble, m.wobble_period = speed.wobble_period_s;
  Trajectory out;
  IntegrateTrack(m, duration_s, [&](std::int64_t i, double, const TrackState& q) {
    out.stamps.push_back(SampleStamp(start_stamp, i));
    out.poses.emplace_back(SO3::Exp(Eigen::Vector3d(0, 0, q[1])),
                           Eigen::Vector3d(q[2], q[3], Sum(m.z_waves, q[0])));
  });
  return out;
}

}  // namespace uf::sim
