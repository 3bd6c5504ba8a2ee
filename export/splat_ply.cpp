#include "export/splat_ply.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include "export/byte_buffer.h"
#include "export/ply_header.h"
#include "odometry/io/atomic_file.h"

namespace uf::exporting {
namespace {

using splat::GaussianModel;

constexpr std::size_t kRecordsPerChunk = 1 << 14;

// The number of f_rest properties of SH degree 0..3: 3 channels x ((degree + 1)^2 - 1) coefficients.
int RestCount(int degree) { return 3 * (splat::ShCoefficientsPerChannel(degree) - 1); }

// Where each field of the 3DGS layout sits among the vertex properties (indices into `properties`).
struct SplatColumns {
  std::array<int, 3> position{}, dc{}, scale{};
  std::array<int, 4> rotation{};  // w x y z
  int opacity = 0;
  std::vector<int> rest;  // f_rest_0 .. f_rest_{N-1}
  int sh_degree = 0;
};

Expected<SplatColumns> FindColumns(const PlyElement& vertex, const std::string& name,
                                   std::vector<std::string>* ignored) {
  std::map<std::string, int> index;
  for (std::size_t p = 0; p < vertex.properties.size(); ++p) {
    const PlyProperty& property = vertex.properties[p];
    if (property.is_list)
      return Status::Error(name + ": vertex property '" + property.name +
                           "' is a list; the 3DGS layout has scalar properties only");
    if (!index.emplace(property.name, static_cast<int>(p)).second)
      return Status::Error(name + ": vertex property '" + property.name + "' appears twice");
  }
  std::vector<bool> used(vertex.properties.size(), false);
  std::string missing;
  auto column = [&](const std::string& field) {
    const auto it = index.find(field);
    if (it == index.end()) {
      if (missing.empty()) missing = field;
      return 0;
    }
    used[it->second] = true;
    return it->second;
  };
  SplatColumns c;
  const char* xyz[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) c.position[a] = column(xyz[a]);
  for (int a = 0; a < 3; ++a) c.dc[a] = column("f_dc_" + std::to_string(a));
  c.opacity = column("opacity");
  for (int a = 0; a < 3; ++a) c.scale[a] = column("scale_" + std::to_string(a));
  for (int a = 0; a < 4; ++a) c.rotation[a] = column("rot_" + std::to_string(a));
  if (!missing.empty())
    return Status::Error(name + ": vertex property '" + missing +
                         "' is missing (a 3DGS splat PLY needs x y z, f_dc_0..2, opacity, scale_0..2, "
                         "rot_0..3)");
  for (const char* normal : {"nx", "ny", "nz"})
    if (const auto it = index.find(normal); it != index.end()) used[it->second] = true;

  // f_rest_N: count them, then require exactly f_rest_0 .. f_rest_{count-1}.
  int rest_count = 0;
  for (const auto& [property, p] : index)
    if (property.rfind("f_rest_", 0) == 0) ++rest_count;
  for (c.sh_degree = 0; c.sh_degree <= splat::kMaxShDegree; ++c.sh_degree)
    if (RestCount(c.sh_degree) == rest_count) break;
  if (c.sh_degree > splat::kMaxShDegree)
    return Status::Error(name + ": " + std::to_string(rest_count) +
                         " f_rest properties; the 3DGS layout has 0, 9, 24 or 45 (SH degree 0, 1, 2, 3)");
  for (int j = 0; j < rest_count; ++j) {
    const int p = column("f_rest_" + std::to_string(j));
    if (!missing.empty())
      return Status::Error(name + ": vertex property '" + missing + "' is missing (" +
                           std::to_string(rest_count) + " f_rest properties must be f_rest_0..f_rest_" +
                           std::to_string(rest_count - 1) + ")");
    c.rest.push_back(p);
  }
  if (ignored)
    for (std::size_t p = 0; p < used.size(); ++p)
      if (!used[p]) ignored->push_back(vertex.properties[p].name);
  return c;
}

// Appends the Gaussian of one row of property values, converting f_rest from channel-major to the
// model's coefficient-major order (see splat_ply.h).
void AppendRow(const std::vector<float>& row, const SplatColumns& c, std::vector<float>& sh,
               GaussianModel& model) {
  const int rest_per_channel = splat::ShCoefficientsPerChannel(c.sh_degree) - 1;
  for (int ch = 0; ch < 3; ++ch) sh[ch] = row[c.dc[ch]];
  for (int j = 0; j < static_cast<int>(c.rest.size()); ++j) {
    const int channel = j / rest_per_channel, coefficient = j % rest_per_channel + 1;
    sh[coefficient * 3 + channel] = row[c.rest[j]];
  }
  const Eigen::Quaternionf rotation(row[c.rotation[0]], row[c.rotation[1]], row[c.rotation[2]],
                                    row[c.rotation[3]]);
  model.Add({row[c.position[0]], row[c.position[1]], row[c.position[2]]},
            {row[c.scale[0]], row[c.scale[1]], row[c.scale[2]]}, rotation, row[c.opacity], sh.data());
}

Status ReadBinaryBody(std::istream& in, const PlyElement& vertex, bool big_endian, const SplatColumns& c,
                      const std::string& name, GaussianModel& model) {
  const std::size_t record = vertex.record_bytes;
  std::vector<char> chunk(std::min<std::uint64_t>(vertex.count, kRecordsPerChunk) * record);
  std::vector<float> row(vertex.properties.size()), sh(model.ShStride());
  for (std::uint64_t done = 0; done < vertex.count;) {
    const std::size_t n = std::min<std::uint64_t>(kRecordsPerChunk, vertex.count - done);
    in.read(chunk.data(), static_cast<std::streamsize>(n * record));
    if (static_cast<std::size_t>(in.gcount()) != n * record)
      return Status::Error(name + ": file ends inside vertex " + std::to_string(done + in.gcount() / record));
    for (std::size_t r = 0; r < n; ++r) {
      const char* bytes = chunk.data() + r * record;
      for (std::size_t p = 0; p < row.size(); ++p) {
        const PlyProperty& property = vertex.properties[p];
        row[p] = static_cast<float>(DecodePlyValue(bytes + property.offset, property.type, big_endian));
      }
      AppendRow(row, c, sh, model);
    }
    done += n;
  }
  return {};
}

Status ReadAsciiBody(std::istream& in, const PlyElement& vertex, const SplatColumns& c,
                     const std::string& name, GaussianModel& model) {
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const char* at = text.data();
  const char* const end = text.data() + text.size();
  std::vector<float> row(vertex.properties.size()), sh(model.ShStride());
  for (std::uint64_t v = 0; v < vertex.count; ++v) {
    for (std::size_t p = 0; p < row.size(); ++p) {
      while (at < end && std::isspace(static_cast<unsigned char>(*at))) ++at;
      if (at == end)
        return Status::Error(name + ": file ends inside vertex " + std::to_string(v) + " (property '" +
                             vertex.properties[p].name + "')");
      if (*at == '+' && at + 1 < end) ++at;  // from_chars does not take a leading '+'
      double value = 0;
      const auto [next, error] = std::from_chars(at, end, value);
      if (error != std::errc() || (next < end && !std::isspace(static_cast<unsigned char>(*next))))
        return Status::Error(
            name + ": vertex " + std::to_string(v) + " property '" + vertex.properties[p].name + "': '" +
            std::string(at,
                        std::find_if(at, std::min(end, at + 40),
                                     [](char ch) { return std::isspace(static_cast<unsigned char>(ch)); })) +
            "' is not a number (or is out of range)");
      row[p] = static_cast<float>(value);
      at = next;
    }
    AppendRow(row, c, sh, model);
  }
  return {};
}

}  // namespace

Expected<GaussianModel> ReadSplatPly(const std::string& path, std::vector<std::string>* ignored_properties) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::Error(path + ": cannot open the file");
  std::error_code size_error;
  const std::uintmax_t file_size = std::filesystem::file_size(path, size_error);
  if (size_error) return Status::Error(path + ": cannot read the file size: " + size_error.message());
  Expected<PlyHeader> header = ParsePlyHeader(in, path);
  if (!header.ok()) return header.status();

  // The vertex element, first among the elements with any data.
  const PlyElement* vertex = nullptr;
  for (const PlyElement& element : header->elements) {
    if (element.name == "vertex") {
      vertex = &element;
      break;
    }
    if (element.count > 0)
      return Status::Error(path + ": element '" + element.name + "' comes before 'vertex'" +
                           (element.name == "chunk"
                                ? " (a compressed splat PLY; convert it to the plain 3DGS "
                                  "layout first, e.g. with SuperSplat)"
                                : "; the 3DGS layout starts with the vertex element"));
  }
  if (!vertex) return Status::Error(path + ": PLY header has no 'vertex' element");
  Expected<SplatColumns> columns = FindColumns(*vertex, path, ignored_properties);
  if (!columns.ok()) return columns.status();

  // Check the promised count against the bytes there before allocating anything for it.
  const std::uint64_t body_bytes = file_size - std::min<std::uintmax_t>(file_size, header->header_bytes);
  const bool ascii = header->format == PlyFormat::kAscii;
  const std::uint64_t min_record = ascii ? 2 * vertex->properties.size() : vertex->record_bytes;
  if (vertex->count > (body_bytes + (ascii ? 1 : 0)) / min_record)
    return Status::Error(path + ": header declares " + std::to_string(vertex->count) + " vertices of " +
                         (ascii ? "at least " : "") + std::to_string(min_record) + " bytes, but only " +
                         std::to_string(body_bytes) + " bytes follow the header (truncated file?)");

  GaussianModel model;
  model.sh_degree = columns->sh_degree;
  model.positions.reserve(vertex->count);
  model.log_scales.reserve(vertex->count);
  model.rotations.reserve(vertex->count);
  model.opacity_logits.reserve(vertex->count);
  model.sh.reserve(vertex->count * model.ShStride());
  const Status body = ascii ? ReadAsciiBody(in, *vertex, *columns, path, model)
                            : ReadBinaryBody(in, *vertex, header->format == PlyFormat::kBinaryBigEndian,
                                             *columns, path, model);
  if (!body.ok()) return body;
  if (Status valid = model.Validate(path); !valid.ok()) return valid;
  return model;
}

Status WriteSplatPly(const GaussianModel& model, const std::string& path) {
  if (Status valid = model.Validate(path + " (model to write)"); !valid.ok()) return valid;
  const int coefficients = splat::ShCoefficientsPerChannel(model.sh_degree);
  std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment 3DGS layout written by ultrafusion: f_rest "
      "channel-major, "
      "opacity logit, log scales, rot w x y z\nelement vertex " +
      std::to_string(model.size()) + "\n";
  for (const char* name : {"x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"})
    header += std::string("property float ") + name + "\n";
  for (int j = 0; j < RestCount(model.sh_degree); ++j)
    header += "property float f_rest_" + std::to_string(j) + "\n";
  header += "property float opacity\n";
  for (const char* name : {"scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"})
    header += std::string("property float ") + name + "\n";
  header += "end_header\n";

  AtomicFileWriter file(path);
  if (Status s = file.status(); !s.ok()) return s;
  file.stream().write(header.data(), static_cast<std::streamsize>(header.size()));
  ByteBuffer chunk;
  for (std::size_t i = 0; i < model.size(); ++i) {
    for (float v : model.positions[i]) chunk.Put(v);
    for (int a = 0; a < 3; ++a) chunk.Put(0.0f);  // nx ny nz
    const float* sh = model.sh.data() + i * model.ShStride();
    for (int c = 0; c < 3; ++c) chunk.Put(sh[c]);  // f_dc: coefficient 0
    for (int c = 0; c < 3; ++c)                    // f_rest: channel-major
      for (int k = 1; k < coefficients; ++k) chunk.Put(sh[k * 3 + c]);
    chunk.Put(model.opacity_logits[i]);
    for (float v : model.log_scales[i]) chunk.Put(v);
    const Eigen::Quaternionf& q = model.rotations[i];
    for (float v : {q.w(), q.x(), q.y(), q.z()}) chunk.Put(v);
    if (chunk.size() >= (1u << 20) || i + 1 == model.size()) {
      file.stream().write(chunk.data(), static_cast<std::streamsize>(chunk.size()));
      chunk.Clear();
    }
  }
  return file.Commit();
}

}  // namespace uf::exporting
