#include "odometry/io/folders/csv_sources.h"

#include <array>
#include <fstream>
#include <iterator>

#include "odometry/io/text_table.h"

namespace uf {
namespace {

// A CSV of fixed numeric columns after the stamp; Parse() turns the current row into the record.
template <typename Record>
class NumericCsvSource : public StreamSource {
 public:
  using Parser = Status (*)(const TextTableReader&, Record&);
  NumericCsvSource(TextTableReader reader, std::size_t columns, const char* layout, Parser parse)
      : reader_(std::move(reader)), columns_(columns), layout_(layout), parse_(parse) {}

  Expected<bool> Advance() override {
    if (!reader_.Next()) {
      if (Status s = reader_.read_status(); !s.ok()) return s;
      return false;
    }
    if (Status s = reader_.ExpectColumns(columns_, layout_); !s.ok()) return s;
    auto stamp = reader_.Nanoseconds(0, "stamp");
    if (!stamp) return stamp.status();
    if (std::string order = order_.Check(*stamp); !order.empty()) return reader_.Error(order);
    record_ = Record{};
    record_.stamp = *stamp;
    if (Status s = parse_(reader_, record_); !s.ok()) return s;
    return true;
  }
  Stamp stamp() const override { return record_.stamp; }
  Expected<std::optional<MeasurementData>> Load(StreamInfo&, WarningLog&) override {
    return std::optional<MeasurementData>(record_);
  }

 private:
  TextTableReader reader_;
  std::size_t columns_;
  const char* layout_;
  Parser parse_;
  IncreasingStamps order_;
  Record record_;
};

// Reads `names.size()` numbers starting at `column` into `out`.
template <std::size_t N>
Status Numbers(const TextTableReader& in, std::size_t column, const std::array<const char*, N>& names,
               double* out) {
  for (std::size_t i = 0; i < N; ++i) {
    auto value = in.Number(column + i, names[i]);
    if (!value) return value.status();
    out[i] = *value;
  }
  return {};
}

Status ParseImu(const TextTableReader& in, ImuSample& sample) {
  if (Status s = Numbers<3>(in, 1, {"gyro x", "gyro y", "gyro z"}, sample.gyro.data()); !s.ok()) return s;
  return Numbers<3>(in, 4, {"acc x", "acc y", "acc z"}, sample.acc.data());
}

Status ParseWheel(const TextTableReader& in, WheelSample& sample) {
  if (Status s = Numbers<3>(in, 1, {"vx", "vy", "vz"}, sample.linear_velocity.data()); !s.ok()) return s;
  return Numbers<3>(in, 4, {"wx", "wy", "wz"}, sample.angular_velocity.data());
}

Status ParseGnss(const TextTableReader& in, GnssFix& fix) {
  double position[3];
  if (Status s = Numbers<3>(in, 1, {"latitude", "longitude", "altitude"}, position); !s.ok()) return s;
  if (position[0] < -90 || position[0] > 90) return in.Error("latitude out of -90..90 deg");
  if (position[1] < -180 || position[1] > 180) return in.Error("longitude out of -180..180 deg");
  fix.latitude_deg = position[0];
  fix.longitude_deg = position[1];
  fix.altitude_m = position[2];
  double covariance[9];
  const std::array<const char*, 9> names = {"c00", "c01", "c02", "c10", "c11", "c12", "c20", "c21", "c22"};
  if (Status s = Numbers<9>(in, 4, names, covariance); !s.ok()) return s;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) fix.covariance_enu(r, c) = covariance[3 * r + c];
  if (!ParseGnssFixStatus(in.field(13), fix.status))
    return in.Error("status (column 14) is not one of no_fix, fix, sbas, rtk_float, rtk_fixed: " +
                    QuotedForError(in.field(13)));
  return {};
}

class CameraCsvSource : public StreamSource {
 public:
  CameraCsvSource(TextTableReader reader, std::filesystem::path image_folder, int camera, std::string stream)
      : reader_(std::move(reader)),
        folder_(std::move(image_folder)),
        camera_(camera),
        stream_(std::move(stream)) {}

  Expected<bool> Advance() override {
    if (!reader_.Next()) {
      if (Status s = reader_.read_status(); !s.ok()) return s;
      return false;
    }
    if (Status s = reader_.ExpectColumns(2, "stamp_ns, filename"); !s.ok()) return s;
    auto stamp = reader_.Nanoseconds(0, "stamp");
    if (!stamp) return stamp.status();
    if (std::string order = order_.Check(*stamp); !order.empty()) return reader_.Error(order);
    const std::filesystem::path file(reader_.field(1));
    if (file.empty() || file.is_absolute() || file.lexically_normal().string().starts_with(".."))
      return reader_.Error("filename (column 2) must be a file inside " + folder_.string() + ": " +
                           QuotedForError(reader_.field(1)));
    stamp_ = *stamp;
    file_ = folder_ / file;
    return true;
  }
  Stamp stamp() const override { return stamp_; }

  Expected<std::optional<MeasurementData>> Load(StreamInfo&, WarningLog& warnings) override {
    std::ifstream in(file_, std::ios::binary);
    if (!in) {
      warnings.Add(stream_, "image file missing or unreadable (frame skipped), e.g. " + file_.string());
      return std::optional<MeasurementData>();
    }
    CameraFrame frame;
    frame.stamp = stamp_;
    frame.camera = camera_;
    frame.encoded.bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    frame.encoded.format = ImageFormatOf(frame.encoded.bytes);
    if (in.bad() || frame.encoded.format.empty()) {
      warnings.Add(stream_, "image file is not a PNG or JPEG (frame skipped), e.g. " + file_.string());
      return std::optional<MeasurementData>();
    }
    return std::optional<MeasurementData>(std::move(frame));
  }

 private:
  TextTableReader reader_;
  std::filesystem::path folder_;
  int camera_;
  std::string stream_;
  IncreasingStamps order_;
  Stamp stamp_ = 0;
  std::filesystem::path file_;
};

template <typename Record>
Expected<std::unique_ptr<StreamSource>> OpenNumeric(const std::filesystem::path& path, std::size_t columns,
                                                    const char* layout,
                                                    typename NumericCsvSource<Record>::Parser parse) {
  auto reader = TextTableReader::Open(path.string());
  if (!reader) return reader.status();
  return std::unique_ptr<StreamSource>(
      std::make_unique<NumericCsvSource<Record>>(std::move(*reader), columns, layout, parse));
}

constexpr std::array<std::string_view, 5> kFixStatusNames = {"no_fix", "fix", "sbas", "rtk_float",
                                                             "rtk_fixed"};

}  // namespace

Expected<std::unique_ptr<StreamSource>> OpenImuCsv(const std::filesystem::path& path) {
  return OpenNumeric<ImuSample>(path, 7, "stamp_ns, gx, gy, gz, ax, ay, az", ParseImu);
}

Expected<std::unique_ptr<StreamSource>> OpenWheelCsv(const std::filesystem::path& path) {
  return OpenNumeric<WheelSample>(path, 7, "stamp_ns, vx, vy, vz, wx, wy, wz", ParseWheel);
}

Expected<std::unique_ptr<StreamSource>> OpenGnssCsv(const std::filesystem::path& path) {
  return OpenNumeric<GnssFix>(path, 14, "stamp_ns, lat, lon, alt, 9 covariance entries, status", ParseGnss);
}

Expected<std::unique_ptr<StreamSource>> OpenCameraCsv(const std::filesystem::path& path,
                                                      const std::filesystem::path& image_folder, int camera,
                                                      const std::string& stream_name) {
  auto reader = TextTableReader::Open(path.string());
  if (!reader) return reader.status();
  return std::unique_ptr<StreamSource>(
      std::make_unique<CameraCsvSource>(std::move(*reader), image_folder, camera, stream_name));
}

std::string_view GnssFixStatusName(GnssFixStatus status) { return kFixStatusNames[static_cast<int>(status)]; }

bool ParseGnssFixStatus(std::string_view name, GnssFixStatus& status) {
  for (std::size_t i = 0; i < kFixStatusNames.size(); ++i) {
    if (kFixStatusNames[i] == name) {
      status = static_cast<GnssFixStatus>(i);
      return true;
    }
  }
  return false;
}

std::string ImageFormatOf(const std::vector<std::uint8_t>& bytes) {
  static constexpr std::uint8_t kPng[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (bytes.size() >= sizeof(kPng) && std::equal(std::begin(kPng), std::end(kPng), bytes.begin()))
    return "png";
  if (bytes.size() >= 3 && bytes[0] == 0xff && bytes[1] == 0xd8 && bytes[2] == 0xff) return "jpeg";
  return {};
}

}  // namespace uf
