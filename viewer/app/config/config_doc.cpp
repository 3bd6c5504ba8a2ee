#include "viewer/app/config/config_doc.h"

#include "viewer/app/config/section_schemas.h"

namespace uf::app {
namespace {

using config::DocRows;
using config::MarkdownTable;

constexpr const char* kHeader = R"(# Configuration reference

<!-- Generated from the schemas in viewer/app/config/ (*_config.cpp): do not edit by hand. After changing a
key, regenerate with `cmake --build build --target config-doc`; test_app_config fails while this file
differs from what the schemas give. -->

A configuration file is YAML with top-level sections; one file may hold several, and each command reads the
sections it needs: `ultrafusion run --config` reads `dataset:`, `lo:`, `lio:`, `wio:` and `splat:`, `ultrafusion
info --config` `dataset:`, `ultrafusion splat --config` `splat:`, `ultrafusion sim --config` `sim:`. The
file is read once (`LoadConfigFile`, `viewer/app/config/config_file.h`) and every section is checked,
whichever command reads it. Every key is optional: a key that is not given keeps the default below. A list
that is given replaces the default list.

Errors name the file, the key path, its line and the value, e.g. `run.yaml: lo.map.voxel_m (line 3):
expected a number, got 'fast'`: unknown keys (listing the known ones), values of the wrong type, unknown
top-level sections. Value ranges are checked by the option structs' `Validate()` (the message names the
key: `run.yaml: lo.window_size: must be >= 2, got 1`). Numbers are read exactly (`std::from_chars`),
booleans are `true` or `false`, seconds of stamps and windows exactly to the nanosecond.

`ultrafusion run` saves the resolved `dataset:`, `lo:` (for LIO also `lio:`; for WIO `wio:` instead) and `splat:` sections as
`config.yaml` in its run folder, and `ultrafusion sim` the resolved `sim:` section as `sim_config.yaml`:
both read back to the same values. Profiles per sensor setup are in `configs/`; `configs/sim.yaml` and
`configs/splat.yaml` state every key of their section at its default.
)";

constexpr const char* kDataset = R"(
## `dataset:` (how to open and merge a dataset)

Read by `run`, `info` and `splat` (from the run's `config.yaml`); maps onto `DatasetOptions`
(`odometry/io/dataset_options.h`) and `MeasurementStreamOptions` (`odometry/io/measurement_stream.h`).

)";

constexpr const char* kLo = R"(
## `lo:` (LiDAR odometry)

Read by `run`; maps onto `estimator::LidarOdometryConfig` (`odometry/estimator/config/`). The method and
the paper's values of these parameters are in `docs/METHOD.md`. `T_body_lidar` and `use_imu` are not keys:
`run` sets them from the dataset and `--mode`.

)";

constexpr const char* kLio = R"(
## `lio:` (what LiDAR-inertial odometry adds)

Read by `run` in LIO mode (`--mode lio`, or auto with an IMU); the same struct as `lo:`. The IMU noise
densities are 10x the simulated IMU's datasheet values (EuRoC's ADIS16448) on purpose: see
`odometry/estimator/config/lidar_odometry_config.h`.

)";

constexpr const char* kWio = R"(
## `wio:` (wheel-inertial odometry)

Read by `run` in the modes without a LiDAR (`--mode wio` or `wgio`, or auto on a dataset with an IMU and a
wheel stream but no LiDAR); maps onto `estimator::InertialOdometryConfig`
(`odometry/estimator/config/inertial_odometry_config.h`). Nodes on a grid of IMU time linked by IMU and wheel
factors; the `imu`, `init`, `wheel` and `gnss` parts mean what they mean under `lio:`. `T_body_wheel`,
`T_body_gnss` and `use_gnss` are not keys: `run` sets them from the dataset and `--mode`.

)";

constexpr const char* kSplat = R"(
## `splat:` (Gaussian splat training)

Read by `splat` and by `run`'s splat stage; maps onto `SplatConfig` (`viewer/app/config/splat_config.h`),
which holds `splat::TrainingOptions` (`splat/training/training_options.h`; 3DGS' defaults, Kerbl et al.
2023). `splat`'s options (`--iterations`, `--resolution`, `--sh-degree`, `--time-budget`) override the file.

)";

constexpr const char* kSim = R"(
## `sim:` (the simulator)

Read by `sim`; maps onto `sim::SimulationConfig` (`odometry/sim/sequence/simulation_config.h`). Units are
SI; angles in degrees where the key says `_deg`. Ranges are checked by `sim::ValidateSimulationConfig`
after `sim`'s options are applied.

- Frames: the body frame is the IMU frame (x forward, y left, z up); the world is east-north-up at
  `origin`. Each sensor but the imu has the placement keys `extrinsic`, `stamp_delay_s` and
  `extrinsic_error`. `extrinsic` is written back as the exact 4x4 matrix `{matrix: [...]}` with its
  translation and roll-pitch-yaw in a comment; the table shows the default as translation and rpy.
- Event windows `[begin_s, end_s]` are seconds from the sequence start (`start_time_s`, read first wherever
  it stands), begin inclusive, end exclusive, end > begin.

)";

constexpr const char* kFooter = R"(
## `calibration:` (sensor calibration files)

Not a settings section: the calibration files the simulator writes (`calibration.yaml`,
`calibration_true.yaml`) and `colorize` reads, one entry per sensor with `name`, `kind`, `T_body_sensor`,
`time_offset_s` and, for cameras, `intrinsics` (below). The format is described in
`odometry/io/calibration_file.h`. A configuration file may carry the section; the other readers skip it.

## Camera intrinsics (`render --camera`, calibration files, dataset files)

One dialect (EuRoC / Kalibr) wherever camera intrinsics are written: the camera file of `ultrafusion
render` holds these keys at its top level (as `configs/render-camera.yaml` and a run's `views/camera.yaml`),
a calibration file's camera under `intrinsics:`, the project's `dataset.yaml` under `calibration:`, EuRoC
in each `sensor.yaml`. One parser reads them all (`odometry/io/camera_calibration.h`).

| key | value | meaning |
|---|---|---|
| `camera_model` | `pinhole` | optional; the only model |
| `distortion_model` | `radial-tangential` \| `equidistant` | `render` draws radial-tangential cameras only |
| `intrinsics` | `[fx, fy, cx, cy]` | px; pixel (0, 0) is the centre of the top-left pixel |
| `distortion_coefficients` | `[k1, k2, p1, p2]` or `[k1, k2, p1, p2, k3]`; equidistant `[k1, k2, k3, k4]` | all 0: no distortion |
| `resolution` | `[width, height]` | px |

Camera axes as OpenCV: x right, y down, z forward.
)";

}  // namespace

std::string ConfigReferenceMarkdown() {
  const estimator::LidarOdometryConfig odometry;
  return std::string(kHeader) + kDataset + MarkdownTable(DocRows(config::DatasetSchema(), DatasetConfig{})) +
         kLo + MarkdownTable(DocRows(config::LoSchema(), odometry)) + kLio +
         MarkdownTable(DocRows(config::LioSchema(), odometry)) + kWio +
         MarkdownTable(DocRows(config::WioSchema(), estimator::InertialOdometryConfig{})) + kSplat +
         MarkdownTable(DocRows(config::SplatSchema(), SplatConfig{})) + kSim +
         MarkdownTable(DocRows(config::SimSchema(), sim::SimulationConfig{})) + kFooter;
}

}  // namespace uf::app
