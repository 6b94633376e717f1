// The core's frames (rows X, Y, Z in double) and pcl::ReferenceFrame: the core's float rounding is
// bit for bit the round trip through PCL's float axes, and the conversions of whole lists agree.
#include <pcl_patchdict/core/local_frame.h>
#include <pcl_patchdict/pcl/reference_frame.h>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

using namespace pcl::patchdict;

namespace {

bool sameBits(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b)
{
  return std::memcmp(a.data(), b.data(), sizeof(double) * 9) == 0;
}

/** Rows X, Y, Z of a uniformly random rotation (normalised Gaussian quaternion). */
Eigen::Matrix3d randomRotation(std::mt19937_64& random)
{
  std::normal_distribution<double> gaussian;
  Eigen::Quaterniond q(gaussian(random), gaussian(random), gaussian(random), gaussian(random));
  q.normalize();
  return q.toRotationMatrix().transpose();
}

}  // namespace

TEST(LocalFrame, RoundingIsTheRoundTripThroughReferenceFrameBitForBit)
{
  std::mt19937_64 random(26);
  for (int i = 0; i < 100000; ++i) {
    const Eigen::Matrix3d rows = randomRotation(random);
    const Eigen::Matrix3d rounded = roundToSinglePrecision(rows);
    ASSERT_TRUE(sameBits(rounded, fromReferenceFrame(toReferenceFrame(rows)))) << "rotation " << i;
    ASSERT_TRUE(sameBits(roundToSinglePrecision(rounded), rounded)) << "rounding twice, rotation " << i;
    ASSERT_LT((rounded - rows).cwiseAbs().maxCoeff(), 1e-7);
  }
  // Entries on the way to float's edges (signed zeros, subnormals, ties) and a non-rotation.
  Eigen::Matrix3d odd;
  odd << 0.0, -0.0, 1e-40, -1e-46, 1.0 + 0x1p-24, 1.0 + 0x1p-23 + 0x1p-24, 3e38, -0.1, 1.0 / 3.0;
  EXPECT_TRUE(sameBits(roundToSinglePrecision(odd), fromReferenceFrame(toReferenceFrame(odd))));
}

TEST(LocalFrame, ListsConvertToAndFromACloudOfReferenceFrames)
{
  std::mt19937_64 random(3);
  std::vector<Eigen::Matrix3d> frames;
  for (int i = 0; i < 50; ++i)
    frames.push_back(roundToSinglePrecision(randomRotation(random)));
  const pcl::PointCloud<pcl::ReferenceFrame> cloud = toReferenceFrames(frames);
  ASSERT_EQ(cloud.size(), frames.size());
  EXPECT_EQ(cloud.width, static_cast<std::uint32_t>(frames.size()));
  EXPECT_EQ(cloud.height, 1u);
  const std::vector<Eigen::Matrix3d> back = fromReferenceFrames(cloud);
  ASSERT_EQ(back.size(), frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    EXPECT_TRUE(sameBits(back[i], frames[i]));  // rounded frames survive the float type exactly
    EXPECT_EQ(cloud[i].x_axis[1], static_cast<float>(frames[i](0, 1)));
    EXPECT_EQ(cloud[i].z_axis[2], static_cast<float>(frames[i](2, 2)));
  }
  EXPECT_TRUE(toReferenceFrames({}).empty());
}
