// Bounded mutation fuzzing of the trajectory and times parsers: truncations, byte flips, inserted garbage and
// spliced lines of valid files must give either a trajectory or an error that names the file, never a crash
// or a hang. Run under AddressSanitizer/UBSan by scripts/test (build-asan).
#include <gtest/gtest.h>

#include <random>

#include "odometry/io/trajectory_file.h"
#include "tests/support/temp_dir.h"

namespace uf {
namespace {

const char* kSeeds[] = {
    "# timestamp tx ty tz qx qy qz qw\n1305031102.160407 1.344379 0.627206 1.661754 0.658249 0.611043 "
    "-0.294444 "
    "-0.326553\n1305031102.194330 1.343641 0.626458 1.652408 0.657327 0.613265 -0.295150 -0.323593\n",
    "1.000000e+00 9.043680e-12 2.326809e-11 5.551115e-17 9.043683e-12 1.000000e+00 2.392370e-10 3.330669e-16 "
    "2.326810e-11 2.392370e-10 9.999999e-01 -4.440892e-16\n",
    "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z []\n"
    "1403636579758555392,4.688319,-1.786938,0.783338,0.534108,-0.153029,-0.827383,-0.082152\n",
    "0.000000e+00\n1.037359e-01\n",
};

std::string Mutate(std::string text, std::mt19937& random) {
  const int kind = static_cast<int>(random() % 5);
  auto position = [&] { return text.empty() ? 0 : random() % text.size(); };
  switch (kind) {
    case 0:
      text.resize(position());
      break;  // truncation
    case 1:
      if (!text.empty()) text[position()] = static_cast<char>(random());
      break;  // byte flip
    case 2:
      text.insert(position(), std::string(1 + random() % 8, static_cast<char>(random())));
      break;
    case 3:
      text += text.substr(position());
      break;  // splice
    default:
      text.insert(position(), random() % 2 ? "nan" : "1e999");
      break;  // special values
  }
  return text;
}

TEST(TrajectoryFuzz, MutatedFilesGiveAValueOrANamedError) {
  testing::TempDir dir;
  std::mt19937 random(12345);
  const std::string path = dir.File("fuzz.txt");
  int errors = 0, parsed = 0;
  for (int iteration = 0; iteration < 3000; ++iteration) {
    std::string text = kSeeds[iteration % 4];
    for (int m = 1 + static_cast<int>(random() % 4); m > 0; --m) text = Mutate(text, random);
    dir.Write("fuzz.txt", text);
    for (TrajectoryFormat format : {TrajectoryFormat::kAuto, TrajectoryFormat::kTum, TrajectoryFormat::kKitti,
                                    TrajectoryFormat::kEuroc}) {
      auto read = ReadTrajectory(path, format);
      if (read) {
        ++parsed;
        for (const SE3& pose : read->poses) ASSERT_TRUE(pose.matrix().allFinite());
      } else {
        ++errors;
        ASSERT_EQ(read.error().rfind(path, 0), 0u) << read.error();  // message starts with the file name
      }
    }
    auto times = ReadTimesFile(path);
    if (!times) {
      ASSERT_EQ(times.error().rfind(path, 0), 0u) << times.error();
    }
  }
  EXPECT_GT(parsed, 100);  // the mutations leave many files valid: the parsers are not rejecting everything
  EXPECT_GT(errors, 1000);
}

}  // namespace
}  // namespace uf
