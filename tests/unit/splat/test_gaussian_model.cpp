// GaussianModel: the constant-colour SH encoding and Validate's messages.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "splat/gaussian_model.h"

namespace uf::splat {
namespace {

GaussianModel OneGaussian(int sh_degree) {
  GaussianModel model;
  model.sh_degree = sh_degree;
  model.AddConstantColor(Eigen::Vector3f(1, 2, 3), Eigen::Vector3f(-2, -2, -3),
                         Eigen::Quaternionf::Identity(), 0.5f, Eigen::Vector3f(0.2f, 0.5f, 0.9f));
  return model;
}

TEST(GaussianModel, ConstantColourIsTheDcTermAndTheRestIsZero) {
  const GaussianModel model = OneGaussian(3);
  ASSERT_EQ(model.ShStride(), 48);
  ASSERT_EQ(model.sh.size(), 48u);
  // colour = Y_0 f_dc + 0.5 with Y_0 = 1 / (2 sqrt(pi)).
  const float y0 = 0.5f / std::sqrt(static_cast<float>(M_PI));
  EXPECT_NEAR(y0 * model.sh[0] + 0.5f, 0.2f, 1e-6f);
  EXPECT_NEAR(y0 * model.sh[1] + 0.5f, 0.5f, 1e-6f);
  EXPECT_NEAR(y0 * model.sh[2] + 0.5f, 0.9f, 1e-6f);
  for (int k = 3; k < 48; ++k) EXPECT_EQ(model.sh[k], 0.0f);
  EXPECT_TRUE(model.Validate().ok());
}

TEST(GaussianModel, WithShDegreePadsWithZerosAndTruncates) {
  GaussianModel model = OneGaussian(1);
  model.AddConstantColor(Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero(), Eigen::Quaternionf::Identity(), 0,
                         Eigen::Vector3f(0.1f, 0.3f, 0.7f));
  for (std::size_t k = 0; k < model.sh.size(); ++k) model.sh[k] = static_cast<float>(k + 1);
  const GaussianModel up = WithShDegree(model, 3);
  ASSERT_EQ(up.sh.size(), 2u * 48);
  for (int i = 0; i < 2; ++i)
    for (int k = 0; k < 48; ++k)
      EXPECT_EQ(up.sh[i * 48 + k], k < 12 ? static_cast<float>(i * 12 + k + 1) : 0.0f) << i << " " << k;
  const GaussianModel down = WithShDegree(up, 0);
  ASSERT_EQ(down.sh.size(), 2u * 3);
  for (int i = 0; i < 2; ++i)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(down.sh[i * 3 + c], static_cast<float>(i * 12 + c + 1));
  EXPECT_EQ(down.positions, model.positions);
}

TEST(GaussianModel, ValidateNamesTheGaussianAndTheField) {
  GaussianModel model = OneGaussian(1);
  model.AddConstantColor(Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero(), Eigen::Quaternionf::Identity(),
                         0.0f, Eigen::Vector3f::Constant(0.5f));
  model.opacity_logits[1] = std::numeric_limits<float>::quiet_NaN();
  Status status = model.Validate("scene.ply");
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("scene.ply: Gaussian 1: opacity"), std::string::npos) << status.message();

  model = OneGaussian(1);
  model.rotations[0] = Eigen::Quaternionf(0, 0, 0, 0);
  EXPECT_NE(model.Validate().message().find("rotation"), std::string::npos);
  model = OneGaussian(1);
  model.log_scales[0].y() = -std::numeric_limits<float>::infinity();
  EXPECT_NE(model.Validate().message().find("scale_1"), std::string::npos);
  model = OneGaussian(1);
  model.sh[7] = std::numeric_limits<float>::infinity();  // coefficient 2, channel 1
  EXPECT_NE(model.Validate().message().find("SH coefficient 2 channel 1"), std::string::npos)
      << model.Validate().message();
  model = OneGaussian(2);
  model.sh.pop_back();
  EXPECT_NE(model.Validate().message().find("different lengths"), std::string::npos);
  model.sh_degree = 4;
  EXPECT_NE(model.Validate().message().find("sh_degree"), std::string::npos);
}

}  // namespace
}  // namespace uf::splat
