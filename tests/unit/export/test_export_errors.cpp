// Bad input and failing output for every writer: an unwritable folder, a full disk (simulated with a file
// size limit), an empty map. Each must return an error naming the path, leave no file (nor temporary) under
// the folder, and never replace an existing good file.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <csignal>
#include <functional>

#include "export/gltf_writer.h"
#include "export/las_writer.h"
#include "export/ply_writer.h"
#include "export_test_util.h"
#include "mapping/point_source.h"

namespace uf::exporting {
namespace {

using Writer = std::function<Status(const std::filesystem::path&, const mapping::PointSource&)>;

std::vector<std::pair<std::string, Writer>> AllWriters() {
  return {
      {"ply", [](const auto& p, const auto& s) { return WritePly(p, s); }},
      {"las", [](const auto& p, const auto& s) { return WriteLas(p, s); }},
      {"glb", [](const auto& p, const auto& s) { return WriteGlb(p, &s, nullptr); }},
  };
}

TEST(ExportErrors, UnwritableFolderNamesThePathAndWritesNothing) {
  const mapping::VectorPointSource source(test::MakePoints(10, Eigen::Vector3d::Zero(), 1.0));
  for (const auto& [format, write] : AllWriters()) {
    // A folder that does not exist, and one on a read-only pseudo file system (we may run as root, so
    // permission bits would not stop us).
    for (const std::filesystem::path& path : {std::filesystem::path("/nonexistent_uf_dir/map." + format),
                                              std::filesystem::path("/proc/uf_export_test_map." + format)}) {
      const Status s = write(path, source);
      ASSERT_FALSE(s.ok()) << path;
      EXPECT_NE(s.message().find(path.string()), std::string::npos) << s.message();
      EXPECT_FALSE(std::filesystem::exists(path));
    }
  }
}

TEST(ExportErrors, EmptyOrAllNonFiniteMapIsAnErrorAndKeepsTheOldFile) {
  test::ScratchDir dir;
  std::vector<mapping::MapPoint> nan_points = test::MakePoints(3, Eigen::Vector3d::Zero(), 1.0);
  for (mapping::MapPoint& p : nan_points) p.position.z() = std::nan("");
  const mapping::VectorPointSource empty({}), all_nan(nan_points);
  for (const auto& [format, write] : AllWriters()) {
    const std::filesystem::path path = dir / ("map." + format);
    { std::ofstream(path) << "good old file"; }
    for (const mapping::PointSource* source : {static_cast<const mapping::PointSource*>(&empty),
                                               static_cast<const mapping::PointSource*>(&all_nan)}) {
      const Status s = write(path, *source);
      ASSERT_FALSE(s.ok()) << format;
      EXPECT_NE(s.message().find(path.string()), std::string::npos) << s.message();
      EXPECT_EQ(test::ReadBytes(path).size(), std::string("good old file").size());
    }
  }
  EXPECT_EQ(dir.Entries().size(), 3u);  // the three old files, no temporaries
}

// Limits the size of any file this process writes (a disk that fills up after `bytes`), restoring the old
// limit on destruction. Writes past the limit fail with EFBIG once SIGXFSZ is ignored.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &old_);
    old_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit limited = old_;
    limited.rlim_cur = bytes;
    ok_ = setrlimit(RLIMIT_FSIZE, &limited) == 0;
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &old_);
    std::signal(SIGXFSZ, old_handler_);
  }
  bool ok() const { return ok_; }

 private:
  rlimit old_{};
  void (*old_handler_)(int) = nullptr;
  bool ok_ = false;
};

TEST(ExportErrors, FullDiskFailsCleanlyAndKeepsTheOldFile) {
  test::ScratchDir dir;
  const mapping::VectorPointSource source(test::MakePoints(20000, Eigen::Vector3d::Zero(), 10.0), 1000);
  for (const auto& [format, write] : AllWriters()) {
    const std::filesystem::path path = dir / ("map." + format);
    { std::ofstream(path) << "good old file"; }
    Status s;
    {
      FileSizeLimit limit(64 * 1024);  // far below the ~500 KB each format needs
      ASSERT_TRUE(limit.ok());
      s = write(path, source);
    }
    ASSERT_FALSE(s.ok()) << format;
    EXPECT_NE(s.message().find(path.string()), std::string::npos) << s.message();
    EXPECT_EQ(test::ReadBytes(path).size(), std::string("good old file").size()) << format;
    // And with room again, the same call succeeds and replaces the file.
    ASSERT_TRUE(write(path, source).ok()) << format;
    EXPECT_GT(std::filesystem::file_size(path), 64u * 1024u);
  }
  EXPECT_EQ(dir.Entries().size(), 3u);  // no temporaries left behind
}

}  // namespace
}  // namespace uf::exporting
