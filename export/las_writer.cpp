#include "export/las_writer.h"

#include <cassert>
#include <cmath>
#include <limits>

#include "export/byte_buffer.h"
#include "export/output_frame.h"
#include "odometry/io/atomic_file.h"
#include "odometry/types/stamp.h"

namespace uf::exporting {
namespace {

constexpr std::uint16_t kHeaderSize = 375;   // LAS 1.4 public header block, bytes
constexpr std::uint16_t kRecordLength = 36;  // point data record format 7, bytes
constexpr std::uint8_t kPointFormat = 7;
constexpr std::uint16_t kVlrHeaderSize = 54;
constexpr std::uint16_t kWktRecordId = 2112;  // OGC coordinate system WKT
constexpr std::uint16_t kGlobalEncodingWkt = 1u << 4;

// What the public header block says besides constants (LAS 1.4 R15, Table 3).
struct LasHeader {
  std::uint16_t file_source_id = 0, global_encoding = 0;
  std::uint32_t offset_to_points = kHeaderSize, vlr_count = 0;
  std::uint64_t point_count = 0;
  Eigen::Vector3d scale, offset;
  Eigen::AlignedBox3d bounds;  // of the coordinates as stored (integer * scale + offset)
};

void PutHeader(const LasHeader& h, ByteBuffer& out) {
  out.PutFixedString("LASF", 4);
  out.Put<std::uint16_t>(h.file_source_id);
  out.Put<std::uint16_t>(h.global_encoding);
  out.PutFixedString("", 16);  // project GUID: unset
  out.Put<std::uint8_t>(1);    // version 1.4
  out.Put<std::uint8_t>(4);
  out.PutFixedString("OTHER", 32);        // system identifier: not a single sensor's flight line
  out.PutFixedString("ultrafusion", 32);  // generating software
  out.Put<std::uint16_t>(0);              // creation day of year / year: unset, so output is reproducible
  out.Put<std::uint16_t>(0);
  out.Put<std::uint16_t>(kHeaderSize);
  out.Put<std::uint32_t>(h.offset_to_points);
  out.Put<std::uint32_t>(h.vlr_count);
  out.Put<std::uint8_t>(kPointFormat);
  out.Put<std::uint16_t>(kRecordLength);
  out.Put<std::uint32_t>(0);  // legacy point count: must be 0 without legacy compatibility (formats 6-10)
  for (int r = 0; r < 5; ++r) out.Put<std::uint32_t>(0);  // legacy points by return
  for (int i = 0; i < 3; ++i) out.Put<double>(h.scale[i]);
  for (int i = 0; i < 3; ++i) out.Put<double>(h.offset[i]);
  for (int i = 0; i < 3; ++i) {  // max x, min x, max y, min y, max z, min z
    out.Put<double>(h.bounds.max()[i]);
    out.Put<double>(h.bounds.min()[i]);
  }
  out.Put<std::uint64_t>(0);  // start of waveform data packet record: none
  out.Put<std::uint64_t>(0);  // start of first EVLR: none
  out.Put<std::uint32_t>(0);  // number of EVLRs
  out.Put<std::uint64_t>(h.point_count);
  out.Put<std::uint64_t>(h.point_count);  // points by return: every point is return 1 of 1
  for (int r = 1; r < 15; ++r) out.Put<std::uint64_t>(0);
  assert(out.size() == kHeaderSize);
}

void PutWktVlr(const std::string& wkt, ByteBuffer& out) {
  out.Put<std::uint16_t>(0);  // reserved
  out.PutFixedString("LASF_Projection", 16);
  out.Put<std::uint16_t>(kWktRecordId);
  out.Put<std::uint16_t>(static_cast<std::uint16_t>(wkt.size() + 1));  // the WKT with its terminating NUL
  out.PutFixedString("OGC WKT coordinate system", 32);
  out.PutFixedString(wkt, wkt.size() + 1);
}

std::uint16_t LasIntensity(float intensity, float scale) {
  const float v = intensity * scale;
  if (!(v > 0.0f)) return 0;  // also NaN
  if (v >= 65535.0f) return 65535;
  return static_cast<std::uint16_t>(std::lround(v));
}

void PutPoint(const mapping::MapPoint& p, const Eigen::Vector3i& xyz, const LasOptions& options,
              ByteBuffer& out) {
  for (int i = 0; i < 3; ++i) out.Put<std::int32_t>(xyz[i]);
  out.Put<std::uint16_t>(LasIntensity(p.intensity, options.intensity_scale));
  out.Put<std::uint8_t>(0x11);  // return number 1 (bits 0-3), number of returns 1 (bits 4-7)
  out.Put<std::uint8_t>(0);     // classification flags, scanner channel, scan direction, edge of flight line
  out.Put<std::uint8_t>(0);     // classification: created, never classified
  out.Put<std::uint8_t>(static_cast<std::uint8_t>(std::min<std::uint32_t>(p.count, 255)));  // user data
  out.Put<std::int16_t>(0);                                                                 // scan angle
  out.Put<std::uint16_t>(options.point_source_id);
  out.Put<double>(ToSeconds(p.last_stamp));
  const std::array<std::uint8_t, 3>& rgb = p.has_color ? p.rgb : options.uncolored_rgb;
  for (std::uint8_t c : rgb) out.Put<std::uint16_t>(static_cast<std::uint16_t>(c * 257));  // 8 -> 16 bit
}

// Scale: the requested one, times 10 until the extent from the offset fits an int32 with a margin.
double ChooseScale(double requested, double extent) {
  double scale = requested;
  while (extent / scale > 2e9) scale *= 10;
  return scale;
}

}  // namespace

Status ValidateLasOptions(const LasOptions& options) {
  if (!(options.scale_m > 0 && options.scale_m <= 1))
    return Status::Error("las.scale_m: must be in (0, 1], got " + std::to_string(options.scale_m));
  if (!(options.offset_step_m > 0 && std::isfinite(options.offset_step_m)))
    return Status::Error("las.offset_step_m: must be finite and > 0, got " +
                         std::to_string(options.offset_step_m));
  if (!(options.intensity_scale >= 0 && std::isfinite(options.intensity_scale)))
    return Status::Error("las.intensity_scale: must be finite and >= 0, got " +
                         std::to_string(options.intensity_scale));
  return {};
}

Status WriteLas(const std::filesystem::path& path, const mapping::PointSource& points,
                const LasOptions& options, ExportStats* stats) {
  const std::string name = path.string();
  if (Status s = ValidateLasOptions(options); !s.ok()) return Status::Error(name + ": " + s.message());
  Expected<OutputFrame> frame = OutputFrame::Create(options.crs, options.georef, name);
  if (!frame.ok()) return frame.status();

  // Pass 1: finite points and a box around their output coordinates, for the scale and offset.
  Expected<FinitePoints> scanned = ScanWritablePoints(points, name);
  if (!scanned) return scanned.status();
  const FinitePoints& finite = *scanned;
  const Eigen::AlignedBox3d box = frame->ApplyToBox(finite.bounds);
  LasHeader header;
  header.file_source_id = options.file_source_id;
  header.offset = (box.min() / options.offset_step_m).array().floor() * options.offset_step_m;
  header.scale.setConstant(ChooseScale(options.scale_m, (box.max() - header.offset).maxCoeff()));
  std::string wkt;
  if (options.crs == OutputCrs::kUtm) {
    wkt = options.georef->UtmWkt();
    header.global_encoding |= kGlobalEncodingWkt;
    header.vlr_count = 1;
    header.offset_to_points += kVlrHeaderSize + static_cast<std::uint32_t>(wkt.size() + 1);
  }

  AtomicFileWriter file(name);
  if (Status s = file.status(); !s.ok()) return s;
  std::ofstream& stream = file.stream();
  // Header with placeholder counts and bounds (rewritten at the end), then the CRS record.
  ByteBuffer buffer;
  PutHeader(header, buffer);
  if (!wkt.empty()) PutWktVlr(wkt, buffer);
  assert(buffer.size() == header.offset_to_points);
  stream.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));

  // Pass 2: stream the points, tracking the integer extent of what is written.
  Eigen::Vector3i int_min = Eigen::Vector3i::Constant(std::numeric_limits<int>::max());
  Eigen::Vector3i int_max = Eigen::Vector3i::Constant(std::numeric_limits<int>::min());
  std::uint64_t written = 0;
  points.ForEachChunk([&](std::span<const mapping::MapPoint> chunk) {
    buffer.Clear();
    for (const mapping::MapPoint& p : chunk) {
      if (!p.position.allFinite()) continue;
      const Eigen::Vector3d q = (frame->Apply(p.position) - header.offset).cwiseQuotient(header.scale);
      Eigen::Vector3i xyz;
      for (int i = 0; i < 3; ++i) {
        assert(std::abs(q[i]) < 2.1e9);  // ChooseScale and ApplyToBox keep every point in range
        xyz[i] = static_cast<std::int32_t>(std::lround(q[i]));
      }
      int_min = int_min.cwiseMin(xyz);
      int_max = int_max.cwiseMax(xyz);
      PutPoint(p, xyz, options, buffer);
      ++written;
    }
    stream.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    return static_cast<bool>(stream);  // stop early on a write error (disk full)
  });
  if (Status s = CheckSecondPass(name, finite, written); stream && !s.ok()) return s;

  // The final header: counts and the bounds of the stored coordinates.
  const std::uint64_t bytes = static_cast<std::uint64_t>(stream.tellp());
  header.point_count = written;
  header.bounds = Eigen::AlignedBox3d(int_min.cast<double>().cwiseProduct(header.scale) + header.offset,
                                      int_max.cast<double>().cwiseProduct(header.scale) + header.offset);
  buffer.Clear();
  PutHeader(header, buffer);
  stream.seekp(0);
  stream.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
  if (Status s = file.Commit(); !s.ok()) return s;
  if (stats) *stats = {written, finite.nonfinite, 1, bytes};
  return {};
}

}  // namespace uf::exporting
