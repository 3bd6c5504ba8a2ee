// Read speed and peak memory of the ROS bag reader. Generates bags of Velodyne-like PointCloud2 messages
// (120k points of 22 bytes: x y z intensity float32, ring uint16, time float32) with librosbag, then reads
// each with OpenRosBag + Next() in a fresh process, so the peak RSS printed is the reader's alone, and
// prints bag size, read time, MB/s, messages, points/s and peak RSS. A large and a small bag show that the
// reader's memory does not grow with the bag.
//
// usage: bench_rosbag_read [--size-gb 1.2] [--small-gb 0.25] [--dir DIR] [--compression none|lz4|bz2]
//                          [--cold] [--keep]
//   --cold  evict the bag from the page cache before reading (posix_fadvise), to include the disk
//   --keep  keep the generated bags (deleted by default)
#include <fcntl.h>
#include <rosbag/bag.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "bench/bench_figures.h"
#include "odometry/io/rosbag/rosbag_reader.h"

namespace {

// A message already serialized, written by rosbag::Bag as a sensor_msgs/PointCloud2.
struct SerializedCloud {
  const std::vector<std::uint8_t>* bytes;
};

}  // namespace

namespace ros::message_traits {
template <>
struct MD5Sum<SerializedCloud> {
  static const char* value(const SerializedCloud&) { return "1158d486dd51d683ce2f1be655c3c181"; }
  static const char* value() { return "1158d486dd51d683ce2f1be655c3c181"; }
};
template <>
struct DataType<SerializedCloud> {
  static const char* value(const SerializedCloud&) { return "sensor_msgs/PointCloud2"; }
  static const char* value() { return "sensor_msgs/PointCloud2"; }
};
template <>
struct Definition<SerializedCloud> {
  static const char* value(const SerializedCloud&) { return "(sensor_msgs/PointCloud2)"; }
  static const char* value() { return "(sensor_msgs/PointCloud2)"; }
};
}  // namespace ros::message_traits
namespace ros::serialization {
template <>
struct Serializer<SerializedCloud> {
  template <typename Stream>
  static void write(Stream& stream, const SerializedCloud& cloud) {
    std::memcpy(stream.advance(cloud.bytes->size()), cloud.bytes->data(), cloud.bytes->size());
  }
  static uint32_t serializedLength(const SerializedCloud& cloud) {
    return static_cast<uint32_t>(cloud.bytes->size());
  }
};
}  // namespace ros::serialization

namespace {

constexpr int kRings = 32;
constexpr int kColumns = 3750;  // 32 x 3750 = 120k points, one 10 Hz sweep
constexpr double kSweepSeconds = 0.1;

template <typename T>
void Append(std::vector<std::uint8_t>& bytes, T value) {
  const std::size_t at = bytes.size();
  bytes.resize(at + sizeof(T));
  std::memcpy(bytes.data() + at, &value, sizeof(T));
}

void AppendString(std::vector<std::uint8_t>& bytes, const std::string& text) {
  Append<std::uint32_t>(bytes, static_cast<std::uint32_t>(text.size()));
  for (const char c : text) Append(bytes, c);
}

// A serialized sensor_msgs/PointCloud2 of one clockwise sweep; the header stamp is at bytes 4..11.
std::vector<std::uint8_t> VelodyneCloud() {
  std::vector<std::uint8_t> bytes;
  Append<std::uint32_t>(bytes, 0);  // header: seq, stamp (patched per message), frame_id
  Append<std::uint64_t>(bytes, 0);
  AppendString(bytes, "velodyne");
  Append<std::uint32_t>(bytes, 1);  // height
  Append<std::uint32_t>(bytes, kRings * kColumns);
  const struct {
    const char* name;
    std::uint32_t offset;
    std::uint8_t datatype;
  } fields[] = {{"x", 0, 7},          {"y", 4, 7},     {"z", 8, 7},
                {"intensity", 12, 7}, {"ring", 16, 4}, {"time", 18, 7}};
  Append<std::uint32_t>(bytes, 6);
  for (const auto& field : fields) {
    AppendString(bytes, field.name);
    Append(bytes, field.offset);
    Append(bytes, field.datatype);
    Append<std::uint32_t>(bytes, 1);
  }
  Append<std::uint8_t>(bytes, 0);  // is_bigendian
  Append<std::uint32_t>(bytes, 22);
  Append<std::uint32_t>(bytes, 22 * kRings * kColumns);
  Append<std::uint32_t>(bytes, 22 * kRings * kColumns);
  for (int column = 0; column < kColumns; ++column) {
    const double azimuth = -2 * M_PI * column / kColumns;  // clockwise
    for (int ring = 0; ring < kRings; ++ring) {
      const double elevation = (-30.0 + ring * 40.0 / kRings) * M_PI / 180;
      const double range = 5 + 40 * std::fabs(std::sin(3 * azimuth + ring));
      Append(bytes, static_cast<float>(range * std::cos(elevation) * std::cos(azimuth)));
      Append(bytes, static_cast<float>(range * std::cos(elevation) * std::sin(azimuth)));
      Append(bytes, static_cast<float>(range * std::sin(elevation)));
      Append(bytes, static_cast<float>((column + ring) % 256));
      Append(bytes, static_cast<std::uint16_t>(ring));
      Append(bytes, static_cast<float>(kSweepSeconds * column / kColumns));
    }
  }
  Append<std::uint8_t>(bytes, 1);  // is_dense
  return bytes;
}

void WriteBag(const std::string& path, double gigabytes, rosbag::CompressionType compression) {
  std::vector<std::uint8_t> cloud = VelodyneCloud();
  const long messages = std::max(1L, std::lround(gigabytes * 1e9 / static_cast<double>(cloud.size())));
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  bag.setCompression(compression);
  for (long i = 0; i < messages; ++i) {
    const ros::Time stamp(1'600'000'000 + static_cast<std::uint32_t>(i / 10),
                          static_cast<std::uint32_t>(i % 10) * 100'000'000);
    std::memcpy(&cloud[4], &stamp.sec, 4);
    std::memcpy(&cloud[8], &stamp.nsec, 4);
    bag.write("/velodyne_points", stamp, SerializedCloud{&cloud});
  }
  bag.close();
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd >= 0) {
    ::fsync(fd);  // no writeback competing with the read
    ::close(fd);
  }
}

// The child process: one read of the bag, printed as one line.
int ReadBag(const std::string& path, bool cold) {
  if (cold) {
    const int fd = ::open(path.c_str(), O_RDONLY);
    if (fd >= 0) {
      ::posix_fadvise(fd, 0, 0, POSIX_FADV_DONTNEED);
      ::close(fd);
    }
  }
  const auto start = std::chrono::steady_clock::now();
  auto reader = uf::OpenRosBag(path, {});
  if (!reader.ok()) {
    std::fprintf(stderr, "%s\n", reader.error().c_str());
    return 1;
  }
  long messages = 0, points = 0;
  while (true) {
    auto next = (*reader)->Next();
    if (!next.ok()) {
      std::fprintf(stderr, "%s\n", next.error().c_str());
      return 1;
    }
    if (!next->has_value()) break;
    ++messages;
    points += static_cast<long>(std::get<uf::LidarScan>((*next)->data).points.size());
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  const double megabytes = static_cast<double>(std::filesystem::file_size(path)) / 1e6;
  std::printf("  bag %8.1f MB  read %6.2f s  %7.1f MB/s  %5ld messages  %6.1f Mpoints/s  peak RSS %6.1f MB\n",
              megabytes, seconds, megabytes / seconds, messages, points / seconds / 1e6,
              usage.ru_maxrss / 1024.0);
  return 0;
}

int ReadInChild(const std::string& path, bool cold) {
  std::fflush(stdout);
  const pid_t child = ::fork();
  if (child == 0) {
    const char* args[] = {"bench_rosbag_read", "--read", path.c_str(), cold ? "--cold" : nullptr, nullptr};
    ::execv("/proc/self/exe", const_cast<char* const*>(args));
    std::_Exit(127);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
}

}  // namespace

int main(int argc, char** argv) {
  double size_gb = 1.2, small_gb = 0.25;
  std::string dir, compression_name = "none";
  bool cold = false, keep = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--read" && has_value) {
      const std::string path = argv[++i];
      return ReadBag(path, i + 1 < argc && std::string(argv[i + 1]) == "--cold");
    } else if (arg == "--size-gb" && has_value) {
      size_gb = std::atof(argv[++i]);
    } else if (arg == "--small-gb" && has_value) {
      small_gb = std::atof(argv[++i]);
    } else if (arg == "--dir" && has_value) {
      dir = argv[++i];
    } else if (arg == "--compression" && has_value) {
      compression_name = argv[++i];
    } else if (arg == "--cold") {
      cold = true;
    } else if (arg == "--keep") {
      keep = true;
    } else {
      std::fprintf(stderr,
                   "usage: %s [--size-gb G] [--small-gb G] [--dir DIR] [--compression none|lz4|bz2] "
                   "[--cold] [--keep]\n",
                   argv[0]);
      return 2;
    }
  }
  const rosbag::CompressionType compression = compression_name == "lz4"   ? rosbag::compression::LZ4
                                              : compression_name == "bz2" ? rosbag::compression::BZ2
                                                                          : rosbag::compression::Uncompressed;
  const std::filesystem::path folder =
      dir.empty() ? std::filesystem::temp_directory_path() / ("uf_bench_rosbag_" + std::to_string(::getpid()))
                  : std::filesystem::path(dir);
  std::filesystem::create_directories(folder);
  std::printf("ROS bag read benchmark: PointCloud2, %d points x 22 bytes, %s chunks, %s page cache\n",
              kRings * kColumns, compression_name.c_str(), cold ? "cold" : "warm");
  std::printf("load average before: %s (%ld CPUs)\n", uf::bench::LoadAverage().c_str(),
              ::sysconf(_SC_NPROCESSORS_ONLN));
  int failures = 0;
  for (const double gigabytes : {size_gb, small_gb}) {
    const std::string path =
        (folder / ("velodyne_" + std::to_string(gigabytes).substr(0, 4) + "GB.bag")).string();
    const auto start = std::chrono::steady_clock::now();
    WriteBag(path, gigabytes, compression);
    std::printf("generated %s in %.1f s\n", path.c_str(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    failures += ReadInChild(path, cold) != 0;
    if (!keep) std::filesystem::remove(path);
  }
  if (!keep && dir.empty()) std::filesystem::remove(folder);
  std::printf("load average after: %s\n", uf::bench::LoadAverage().c_str());
  return failures == 0 ? 0 : 1;
}
