// A dataset read with the calibration of a calibration file (calibration_file.h; DatasetOptions::
// calibration_file) instead of the one that came with the data: each sensor of the file replaces the
// T_body_sensor of the stream of the same name and sets its StreamInfo::time_offset (which
// MeasurementStream adds to the stamps). What `ultrafusion calibrate` writes is such a file. Streams the file
// does not name keep their calibration, so the file's body must be the dataset's body unless it names every
// stream that has an extrinsic.
#pragma once

#include <filesystem>
#include <memory>

#include "odometry/io/dataset_reader.h"

namespace uf {

// Wraps `reader`. Errors (naming the file and the sensor): the file's own, a sensor that names no stream of
// the dataset, a sensor whose kind is not its stream's.
Expected<std::unique_ptr<DatasetReader>> WithCalibrationFile(std::unique_ptr<DatasetReader> reader,
                                                             const std::filesystem::path& calibration_file);

}  // namespace uf
