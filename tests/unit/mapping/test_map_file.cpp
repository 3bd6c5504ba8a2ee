// map.vdb: a save -> load round trip gives the same map (points, stats, config, georeference), and broken
// files (missing, not VDB, truncated, a grid missing, an unwritable folder) give errors naming the file.
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "mapping/map_file.h"
#include "mapping/map_view.h"
#include "tests/unit/mapping/map_test_support.h"

namespace uf::mapping {
namespace {

namespace fs = std::filesystem;

class TempDir {
 public:
  TempDir()
      : path_(fs::temp_directory_path() /
              ("uf_map_file_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name())) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// A map of a few scans of random points with colours and intensities, some seen twice.
GlobalMap RandomMap() {
  GlobalMapConfig config;
  config.voxel_size_m = 0.1;
  config.min_observations = 1;
  config.max_voxels = 50000;
  auto map = GlobalMap::Create(config);
  EXPECT_TRUE(map.ok());
  std::mt19937_64 engine(3);
  std::uniform_real_distribution<float> uniform(-2.0f, 2.0f);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int scan = 0; scan < 3; ++scan) {
    std::vector<Eigen::Vector3f> points;
    std::vector<float> intensity;
    std::vector<PointColor> colors;
    for (int i = 0; i < 2000; ++i) {
      const float x = uniform(engine), y = uniform(engine), z = 0.1f * uniform(engine);
      points.emplace_back(x + 1000.0f, y, z);
      intensity.push_back(static_cast<float>(byte(engine)));
      if (i % 2 == 0) {
        const int r = byte(engine), g = byte(engine), b = byte(engine);
        colors.push_back(std::array<std::uint8_t, 3>{
            static_cast<std::uint8_t>(r), static_cast<std::uint8_t>(g), static_cast<std::uint8_t>(b)});
      } else {
        colors.push_back(std::nullopt);
      }
    }
    EXPECT_TRUE(
        map->Insert(WorldScan{scan * 100, Eigen::Vector3d(1000, 0, 2), points, intensity, colors}).ok());
  }
  return std::move(map).value();
}

using ::uf::mapping::testing::AllPoints;

TEST(MapFile, RoundTripGivesTheSameMap) {
  TempDir dir;
  const GlobalMap map = RandomMap();
  const fs::path file = dir.path() / kMapFileName;
  const MapGeoreference georef{
      {49.0069, 8.4037, 115.25},
      SE3(SO3::Exp(Eigen::Vector3d(0.01, -0.02, 0.8)), Eigen::Vector3d(12.5, -3, 0.25))};
  ASSERT_TRUE(SaveMap(map, georef, file).ok());
  // map.vdb and map.voxels, no temporary file left
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 2);
  auto loaded = LoadMap(file);
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  ASSERT_TRUE(loaded->georef.has_value());
  EXPECT_EQ(loaded->georef->origin.latitude_deg, georef.origin.latitude_deg);
  EXPECT_EQ(loaded->georef->origin.longitude_deg, georef.origin.longitude_deg);
  EXPECT_EQ(loaded->georef->origin.height_m, georef.origin.height_m);
  EXPECT_LT((loaded->georef->T_enu_map.matrix() - georef.T_enu_map.matrix()).norm(), 1e-12);
  const GlobalMap& again = loaded->map;
  EXPECT_EQ(again.config().voxel_size_m, map.config().voxel_size_m);
  EXPECT_EQ(again.config().max_voxels, map.config().max_voxels);
  EXPECT_EQ(again.config().min_observations, map.config().min_observations);
  EXPECT_EQ(again.stats().points_inserted, map.stats().points_inserted);
  EXPECT_EQ(again.stats().colors_rejected, map.stats().colors_rejected);
  const auto before = AllPoints(MapView(map)), after = AllPoints(MapView(again));
  ASSERT_EQ(before.size(), after.size());
  ASSERT_GT(before.size(), 1000u);
  for (std::size_t i = 0; i < before.size(); ++i) {
    EXPECT_EQ(before[i].position, after[i].position);
    EXPECT_EQ(before[i].normal, after[i].normal);
    EXPECT_EQ(before[i].rgb, after[i].rgb);
    EXPECT_EQ(before[i].has_color, after[i].has_color);
    EXPECT_EQ(before[i].intensity, after[i].intensity);
    EXPECT_EQ(before[i].count, after[i].count);
    EXPECT_EQ(before[i].last_stamp, after[i].last_stamp);
  }
  // Without a georeference, none comes back; saving over an existing file replaces it.
  ASSERT_TRUE(SaveMap(map, std::nullopt, file).ok());
  auto plain = LoadMap(file);
  ASSERT_TRUE(plain.ok()) << plain.error();
  EXPECT_FALSE(plain->georef.has_value());
}

TEST(MapFile, TruncatedFilesGiveErrors) {
  TempDir dir;
  const fs::path good = dir.path() / kMapFileName;
  ASSERT_TRUE(SaveMap(RandomMap(), std::nullopt, good).ok());
  const auto size = fs::file_size(good);
  for (const double fraction : {0.0, 0.001, 0.01, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99}) {
    const fs::path cut = dir.path() / "cut.vdb";
    fs::copy_file(good, cut, fs::copy_options::overwrite_existing);
    fs::copy_file(VoxelAttributesFile(good), VoxelAttributesFile(cut), fs::copy_options::overwrite_existing);
    fs::resize_file(cut, static_cast<std::uintmax_t>(static_cast<double>(size) * fraction));
    const auto loaded = LoadMap(cut);
    ASSERT_FALSE(loaded.ok()) << "fraction " << fraction;
    EXPECT_NE(loaded.error().find(cut.string()), std::string::npos) << loaded.error();
  }
}

TEST(MapFile, MissingOrForeignFilesGiveErrors) {
  TempDir dir;
  auto missing = LoadMap(dir.path() / "nothing.vdb");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().find("no such map file"), std::string::npos);

  const fs::path text = dir.path() / "text.vdb";
  std::ofstream(text) << "not a vdb file at all\n";
  auto foreign = LoadMap(text);
  ASSERT_FALSE(foreign.ok());
  EXPECT_NE(foreign.error().find(text.string()), std::string::npos);

  // A VDB file with our metadata but without the index grid.
  const fs::path good = dir.path() / kMapFileName;
  ASSERT_TRUE(SaveMap(RandomMap(), std::nullopt, good).ok());
  openvdb::initialize();
  openvdb::io::File in(good.string());
  in.open(false);
  const openvdb::MetaMap::Ptr meta = in.getMetadata();
  openvdb::GridPtrVecPtr grids = in.getGrids();
  in.close();
  const fs::path partial = dir.path() / "partial.vdb";
  fs::copy_file(VoxelAttributesFile(good), VoxelAttributesFile(partial));
  openvdb::io::File(partial.string()).write(openvdb::GridPtrVec{}, *meta);
  auto broken = LoadMap(partial);
  ASSERT_FALSE(broken.ok());
  EXPECT_NE(broken.error().find("grid 'voxel_index' is missing"), std::string::npos) << broken.error();

  // The attributes missing, truncated, or of another map.
  const fs::path lone = dir.path() / "lone.vdb";
  fs::copy_file(good, lone);
  auto no_voxels = LoadMap(lone);
  ASSERT_FALSE(no_voxels.ok());
  EXPECT_NE(no_voxels.error().find("lone.voxels: cannot open"), std::string::npos) << no_voxels.error();
  fs::copy_file(VoxelAttributesFile(good), VoxelAttributesFile(lone));
  fs::resize_file(VoxelAttributesFile(lone), fs::file_size(VoxelAttributesFile(good)) - 10);
  auto cut = LoadMap(lone);
  ASSERT_FALSE(cut.ok());
  EXPECT_NE(cut.error().find("truncated, or from another map"), std::string::npos) << cut.error();
  GlobalMap other = RandomMap();
  const std::vector<Eigen::Vector3f> extra = {{0, 0, 70}};
  ASSERT_TRUE(other.Insert(WorldScan{5, Eigen::Vector3d::Zero(), extra, {}, {}}).ok());
  const fs::path other_file = dir.path() / "other.vdb";
  ASSERT_TRUE(SaveMap(other, std::nullopt, other_file).ok());
  fs::copy_file(VoxelAttributesFile(other_file), VoxelAttributesFile(lone),
                fs::copy_options::overwrite_existing);
  auto mixed = LoadMap(lone);
  ASSERT_FALSE(mixed.ok());
  EXPECT_NE(mixed.error().find("lone.voxels"), std::string::npos) << mixed.error();

  // A VDB file without our metadata.
  const fs::path bare = dir.path() / "bare.vdb";
  openvdb::io::File(bare.string()).write(*grids);
  auto no_meta = LoadMap(bare);
  ASSERT_FALSE(no_meta.ok());
  EXPECT_NE(no_meta.error().find("ultrafusion_map_format"), std::string::npos) << no_meta.error();
}

TEST(MapFile, UnwritableFolderFailsAndLeavesNothing) {
  TempDir dir;
  const fs::path file = dir.path() / "no_such_folder" / kMapFileName;
  const Status status = SaveMap(RandomMap(), std::nullopt, file);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find(file.string()), std::string::npos);
  EXPECT_FALSE(fs::exists(file));
}

TEST(MapFile, LoadedMapKeepsGrowing) {
  TempDir dir;
  const fs::path file = dir.path() / kMapFileName;
  ASSERT_TRUE(SaveMap(RandomMap(), std::nullopt, file).ok());
  auto loaded = LoadMap(file);
  ASSERT_TRUE(loaded.ok());
  GlobalMap& map = loaded->map;
  const std::size_t before = map.size();
  const std::vector<Eigen::Vector3f> points = {{0, 0, 50}, {0, 0, 50}};
  ASSERT_TRUE(map.Insert(WorldScan{1000, Eigen::Vector3d::Zero(), points, {}, {}}).ok());
  EXPECT_EQ(map.size(), before + 1);
  const auto found = MapView(map).Nearest(Eigen::Vector3d(0, 0, 50), 0.01);
  ASSERT_TRUE(found.has_value());
  EXPECT_EQ(found->count, 2u);
  EXPECT_EQ(found->last_stamp, 1000);
}

}  // namespace
}  // namespace uf::mapping
