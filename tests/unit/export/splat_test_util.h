// Helpers for the splat format tests: random Gaussian models and a PLY builder independent of the reader
// and writer under test (header text + typed values, either byte order).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "splat/gaussian_model.h"

namespace uf::exporting::test {

// `n` Gaussians of SH degree `degree` with every field varied (unnormalized quaternions, logits in [-6, 6],
// log-scales in [-5, 2], SH coefficients in [-2, 2]). Deterministic in `seed`.
inline splat::GaussianModel RandomModel(int degree, std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  splat::GaussianModel model;
  model.sh_degree = degree;
  std::vector<float> sh(model.ShStride());
  for (std::size_t i = 0; i < n; ++i) {
    for (float& c : sh) c = 2.0f * u(rng);
    Eigen::Quaternionf q(u(rng), u(rng), u(rng), u(rng));
    if (q.norm() < 0.1f) q = Eigen::Quaternionf(1, 0, 0, 0);
    model.Add(50.0f * Eigen::Vector3f(u(rng), u(rng), u(rng)),
              Eigen::Vector3f(-1.5f + 3.5f * u(rng), -1.5f + 3.5f * u(rng), -1.5f + 3.5f * u(rng)), q,
              6.0f * u(rng), sh.data());
  }
  return model;
}

// The 3DGS property names in the standard order for SH degree `degree`.
inline std::vector<std::string> StandardPropertyNames(int degree) {
  std::vector<std::string> names = {"x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"};
  const int rest = 3 * ((degree + 1) * (degree + 1) - 1);
  for (int j = 0; j < rest; ++j) names.push_back("f_rest_" + std::to_string(j));
  for (const char* n : {"opacity", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"})
    names.push_back(n);
  return names;
}

// A PLY file written by hand: one vertex element of (type, name) properties and rows of values.
struct PlyBuilder {
  std::string format = "binary_little_endian";
  std::vector<std::pair<std::string, std::string>> properties;  // (type, name)
  std::vector<std::vector<double>> rows;
  std::string extra_header;  // inserted before `element vertex`
  long long declared = -1;   // vertex count in the header; -1: rows.size()

  void AddProperties(const std::vector<std::string>& names, const std::string& type = "float") {
    for (const std::string& n : names) properties.emplace_back(type, n);
  }
  // A valid row for properties named by the standard layout (unknown names get 7).
  std::vector<double> DefaultRow(double i) const {
    std::vector<double> row;
    for (const auto& [type, name] : properties) {
      if (name == "x" || name == "y" || name == "z")
        row.push_back(i);
      else if (name == "opacity")
        row.push_back(0.5);
      else if (name.rfind("scale_", 0) == 0)
        row.push_back(-1.0);
      else if (name == "rot_0")
        row.push_back(1.0);
      else if (name.rfind("rot_", 0) == 0 || name.rfind("n", 0) == 0)
        row.push_back(0.0);
      else if (name.rfind("f_", 0) == 0)
        row.push_back(0.25);
      else
        row.push_back(7.0);
    }
    return row;
  }

  std::string Build() const {
    std::string out = "ply\nformat " + format + " 1.0\n" + extra_header + "element vertex " +
                      std::to_string(declared >= 0 ? declared : static_cast<long long>(rows.size())) + "\n";
    for (const auto& [type, name] : properties) out += "property " + type + " " + name + "\n";
    out += "end_header\n";
    for (const std::vector<double>& row : rows) {
      for (std::size_t p = 0; p < row.size(); ++p) {
        const std::string& type = properties[p].first;
        if (format == "ascii") {
          char text[64];
          std::snprintf(text, sizeof text, "%.17g%s", row[p], p + 1 == row.size() ? "\n" : " ");
          out += text;
        } else if (type == "double") {
          Append(out, row[p]);
        } else if (type == "uchar") {
          Append(out, static_cast<std::uint8_t>(row[p]));
        } else if (type == "int") {
          Append(out, static_cast<std::int32_t>(row[p]));
        } else {
          Append(out, static_cast<float>(row[p]));
        }
      }
    }
    return out;
  }

 private:
  template <typename T>
  void Append(std::string& out, T value) const {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    if (format == "binary_big_endian") std::reverse(bytes, bytes + sizeof(T));
    out.append(bytes, sizeof(T));
  }
};

}  // namespace uf::exporting::test
