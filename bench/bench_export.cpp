// Export speed on a synthetic 10 M point map (VectorPointSource, a 2 km x 2 km x 50 m block of coloured
// points): times WritePly, WriteLas and WriteGlb (which subsamples to its default 5 M point cap), in the
// local frame and, with --utm, projected to UTM as well. Writes into a temporary folder it removes, and
// prints seconds, MB/s of file written, points/s and the process's peak memory after each export.
//
//   bench_export [--points N] [--utm]
#include <stdlib.h>
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <random>
#include <string>

#include "export/gltf_writer.h"
#include "export/las_writer.h"
#include "export/ply_writer.h"
#include "mapping/point_source.h"

namespace fs = std::filesystem;
using uf::exporting::ExportStats;

namespace {

double PeakMemoryMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;
}

std::vector<uf::mapping::MapPoint> SyntheticMap(std::size_t n) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> xy(-1000.0, 1000.0), z(0.0, 50.0);
  std::vector<uf::mapping::MapPoint> points(n);
  for (std::size_t i = 0; i < n; ++i) {
    uf::mapping::MapPoint& p = points[i];
    p.position = {xy(rng), xy(rng), z(rng)};
    p.normal = {0, 0, 1};
    p.has_color = (i & 7) != 0;
    p.rgb = {std::uint8_t(rng()), std::uint8_t(rng()), std::uint8_t(rng())};
    p.intensity = float(rng() % 256);
    p.count = 1 + std::uint32_t(rng() % 50);
    p.last_stamp = 1'700'000'000'000'000'000 + std::int64_t(i) * 1000;
  }
  return points;
}

void Time(const std::string& label, std::size_t input_points,
          const std::function<uf::Status(ExportStats*)>& write) {
  ExportStats stats;
  const auto start = std::chrono::steady_clock::now();
  const uf::Status status = write(&stats);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!status.ok()) {
    std::printf("%-10s FAILED: %s\n", label.c_str(), status.message().c_str());
    return;
  }
  std::printf(
      "%-10s %7.2f s  %8.1f MB  %7.1f MB/s  %6.2f M input points/s  %zu written (stride %zu)  peak %.0f "
      "MiB\n",
      label.c_str(), seconds, stats.bytes / 1e6, stats.bytes / 1e6 / seconds, input_points / 1e6 / seconds,
      stats.points_written, stats.point_stride, PeakMemoryMiB());
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t n = 10'000'000;
  bool utm = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--points" && i + 1 < argc) {
      n = std::strtoull(argv[++i], nullptr, 10);
    } else if (arg == "--utm") {
      utm = true;
    } else {
      std::fprintf(stderr, "usage: bench_export [--points N] [--utm]\n");
      return 2;
    }
  }
  std::string pattern = (fs::temp_directory_path() / "bench_export_XXXXXX").string();
  const fs::path dir = mkdtemp(pattern.data());

  auto t0 = std::chrono::steady_clock::now();
  const uf::mapping::VectorPointSource map(SyntheticMap(n));
  std::printf("map: %zu points built in %.2f s, peak %.0f MiB\n", n,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), PeakMemoryMiB());

  Time("ply", n, [&](ExportStats* s) { return uf::exporting::WritePly(dir / "map.ply", map, {}, s); });
  Time("las", n, [&](ExportStats* s) { return uf::exporting::WriteLas(dir / "map.las", map, {}, s); });
  Time("glb", n,
       [&](ExportStats* s) { return uf::exporting::WriteGlb(dir / "map.glb", &map, nullptr, {}, s); });
  if (utm) {
    const uf::exporting::Georeference georef =
        uf::exporting::Georeference::Create({48.1, 11.5, 520.0}).value();
    uf::exporting::PlyOptions ply;
    ply.crs = uf::exporting::OutputCrs::kUtm;
    ply.georef = &georef;
    uf::exporting::LasOptions las;
    las.crs = uf::exporting::OutputCrs::kUtm;
    las.georef = &georef;
    Time("ply utm", n, [&](ExportStats* s) { return uf::exporting::WritePly(dir / "utm.ply", map, ply, s); });
    Time("las utm", n, [&](ExportStats* s) { return uf::exporting::WriteLas(dir / "utm.las", map, las, s); });
  }
  std::error_code ignored;
  fs::remove_all(dir, ignored);
  return 0;
}
