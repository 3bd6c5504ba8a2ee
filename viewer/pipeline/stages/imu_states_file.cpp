#include "viewer/pipeline/stages/imu_states_file.h"

#include <algorithm>
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

// The same for the LiDAR translation, of the rows that have it, and their times (s since the first row).
std::vector<NamedSeries> LidarTranslationComponents(const std::vector<ImuStateRow>& rows,
                                                    std::vector<double>& seconds) {
  std::vector<NamedSeries> series = {{"x", {}}, {"y", {}}, {"z", {}}};
  for (const ImuStateRow& row : rows) {
    if (!row.lidar_translation) continue;
    seconds.push_back(ToSeconds(row.stamp - rows.front().stamp));
    for (int i = 0; i < 3; ++i) series[i].values.push_back((*row.lidar_translation)(i));
  }
  return series;
}

}  // namespace

Expected<ImuStateFiles> WriteImuStateFiles(const std::filesystem::path& folder,
                                           const std::vector<ImuStateRow>& rows) {
  if (rows.empty()) return ImuStateFiles{};
  ImuStateFiles written = {{"imu_states.csv", "plots/imu_accel_bias.png", "plots/imu_gyro_bias.png"},
                           "plots/imu_accel_bias.png",
                           "plots/imu_gyro_bias.png",
                           ""};
  const bool lever = std::any_of(rows.begin(), rows.end(),
                                 [](const ImuStateRow& row) { return row.lidar_translation.has_value(); });
  std::ostringstream csv;
  csv << "stamp_ns,vx_mps,vy_mps,vz_mps,speed_mps,accel_bias_x,accel_bias_y,accel_bias_z,gyro_bias_x,"
         "gyro_bias_y,gyro_bias_z"
      << (lever ? ",lidar_tx_m,lidar_ty_m,lidar_tz_m" : "") << "\n";
  std::vector<double> seconds;
  for (const ImuStateRow& row : rows) {
    if (!row.velocity.allFinite() || !row.accel_bias.allFinite() || !row.gyro_bias.allFinite() ||
        (row.lidar_translation && !row.lidar_translation->allFinite()))
      return Status::Error("imu_states.csv: the state at " + StampText(row.stamp) + " is not finite");
    const Eigen::Vector3d &v = row.velocity, &a = row.accel_bias, &g = row.gyro_bias;
    csv << row.stamp << PrintfText(",%.6f,%.6f,%.6f,%.6f", v.x(), v.y(), v.z(), v.norm())
        << PrintfText(",%.7f,%.7f,%.7f", a.x(), a.y(), a.z())
        << PrintfText(",%.8f,%.8f,%.8f", g.x(), g.y(), g.z());
    if (row.lidar_translation) {
      const Eigen::Vector3d& t = *row.lidar_translation;
      csv << PrintfText(",%.5f,%.5f,%.5f", t.x(), t.y(), t.z());
    } else if (lever) {
      csv << ",,,";
    }
    csv << "\n";
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
  if (!lever) return written;
  written.lidar_translation_plot = "plots/lidar_translation.png";
  written.files.push_back(written.lidar_translation_plot);
  std::vector<double> lever_seconds;
  std::vector<NamedSeries> lever_series = LidarTranslationComponents(rows, lever_seconds);
  if (Status s = WriteSeriesPlot((folder / written.lidar_translation_plot).string(), lever_seconds,
                                 std::move(lever_series), std::nullopt,
                                 "LiDAR extrinsic translation as estimated (imu frame)", x_label, "[m]");
      !s.ok())
    return s;
  return written;
}

}  // namespace uf::pipeline
