#include "odometry/io/recalibrated_reader.h"

#include "odometry/io/calibration_file.h"

namespace uf {
namespace {

class RecalibratedReader : public DatasetReader {
 public:
  RecalibratedReader(std::unique_ptr<DatasetReader> inner, Calibration calibration)
      : inner_(std::move(inner)), calibration_(std::move(calibration)) {}

  // The inner reader's description (which may learn fields from the data) with the file's calibration.
  const DatasetDescription& description() const override {
    description_ = inner_->description();
    for (StreamInfo& stream : description_.streams) {
      if (const SensorCalibration* sensor = calibration_.Find(stream.name)) {
        stream.T_body_sensor = sensor->T_body_sensor;
        stream.time_offset = sensor->time_offset;
      }
    }
    return description_;
  }
  Expected<std::optional<Measurement>> Next() override { return inner_->Next(); }
  const std::vector<ReadWarning>& warnings() const override { return inner_->warnings(); }

 private:
  std::unique_ptr<DatasetReader> inner_;
  Calibration calibration_;
  mutable DatasetDescription description_;
};

}  // namespace

Expected<std::unique_ptr<DatasetReader>> WithCalibrationFile(std::unique_ptr<DatasetReader> reader,
                                                             const std::filesystem::path& calibration_file) {
  Expected<Calibration> calibration = ReadCalibrationFile(calibration_file);
  if (!calibration) return calibration.status();
  const DatasetDescription& description = reader->description();
  for (const SensorCalibration& sensor : calibration->sensors) {
    const StreamInfo* match = nullptr;
    for (const StreamInfo& stream : description.streams)
      if (stream.name == sensor.name) match = &stream;
    if (!match)
      return Status::Error(calibration_file.string() + ": sensor '" + sensor.name + "' names no stream of " +
                           description.path.string() + " (streams: " + StreamNames(description) + ")");
    if (match->kind != sensor.kind)
      return Status::Error(calibration_file.string() + ": sensor '" + sensor.name + "' is a " +
                           std::string(SensorKindName(sensor.kind)) + " in the file and a " +
                           std::string(SensorKindName(match->kind)) + " stream in the dataset");
  }
  return std::unique_ptr<DatasetReader>(
      std::make_unique<RecalibratedReader>(std::move(reader), std::move(*calibration)));
}

}  // namespace uf
