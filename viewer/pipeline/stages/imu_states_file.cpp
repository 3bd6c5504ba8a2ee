#include "viewer/pipeline/stages/imu_states_file.h"

#include <sstream>

#include "odometry/eval/series_plot.h"
#include "odometry/types/printf_text.h"
#include "viewer/pipeline/run_files.h"

namespace uf::pipeline {
namespace {

// The x, y, z of one vector of every row, as three plotted series.
std::vector<NamedSeries> Components(const std::vector<ImuStateRow>& rows,
                                    Eigen::Vector3d ImuStateRow::*member) {
  std::vector<NamedSeries> series = {{"x", {}}, {"y", {}}, {"z", {}}};
  for (const ImuStateRow& row : rows)
    for (int i = 0; i < 3; ++i) series[i].values.push_back((row.*member)(i));
  return series;
}

}  // namespace

Expected<ImuStateFiles> WriteImuStateFiles(const std::filesystem::path& folder,
                                           const std::vector<ImuStateRow>& rows) {
  if (rows.empty()) return ImuStateFiles{};
  const ImuStateFiles written = {{"imu_states.csv", "plots/imu_accel_bias.png", "plots/imu_gyro_bias.png"},
                                 "plots/imu_accel_bias.png",
                                 "plots/imu_gyro_bias.png"};
  std::ostringstream csv;
  csv << "stamp_ns,vx_mps,vy_mps,vz_mps,speed_mps,accel_bias_x,accel_bias_y,accel_bias_z,gyro_bias_x,"
         "gyro_bias_y,gyro_bias_z\n";
  std::vector<double> seconds;
  for (const ImuStateRow& row : rows) {
    if (!row.velocity.allFinite() || !row.accel_bias.allFinite() || !row.gyro_bias.allFinite())
      return Status::Error("imu_states.csv: the state at " + StampText(row.stamp) + " is not finite");
    const Eigen::Vector3d &v = row.velocity, &a = row.accel_bias, &g = row.gyro_bias;
    csv << row.stamp << PrintfText(",%.6f,%.6f,%.6f,%.6f", v.x(), v.y(), v.z(), v.norm())
        << PrintfText(",%.7f,%.7f,%.7f", a.x(), a.y(), a.z())
        << PrintfText(",%.8f,%.8f,%.8f", g.x(), g.y(), g.z()) << "\n";
    seconds.push_back(ToSeconds(row.stamp - rows.front().stamp));
  }
  if (Status s = WriteTextFileAtomically(folder / written.files[0], csv.str()); !s.ok()) return s;
  const std::string x_label = "time since the first keyframe [s]";
  if (Status s = WriteSeriesPlot((folder / written.accel_bias_plot).string(), seconds,
                                 Components(rows, &ImuStateRow::accel_bias), std::nullopt,
                                 "Accelerometer bias (imu frame)", x_label, "bias [m/s^2]");
      !s.ok())
    return s;
  if (Status s = WriteSeriesPlot((folder / written.gyro_bias_plot).string(), seconds,
                                 Components(rows, &ImuStateRow::gyro_bias), std::nullopt,
                                 "Gyroscope bias (imu frame)", x_label, "bias [rad/s]");
      !s.ok())
    return s;
  return written;
}

}  // namespace uf::pipeline
