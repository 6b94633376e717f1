// The .pdc masks' context-modelled range coder: exact round trips, and far fewer bytes than the
// deflated bitmaps of version 2 on the blob-shaped masks the codec writes.
#include "codec/mask_coding.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

using pcl::patchdict::detail::decodeMasks;
using pcl::patchdict::detail::encodeMasks;

namespace {

std::vector<std::vector<char>> blobs(std::size_t count, int grid, std::uint32_t seed)
{
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<std::vector<char>> masks(count, std::vector<char>(static_cast<std::size_t>(grid * grid), 0));
  for (auto& mask : masks) {
    // A disc cut by a half-plane: the shape of a patch's kept or observed bins.
    const double cx = unit(random) * grid, cy = unit(random) * grid, r = (0.2 + 0.5 * unit(random)) * grid;
    const double angle = 6.2832 * unit(random), offset = (unit(random) - 0.5) * grid;
    for (int row = 0; row < grid; ++row)
      for (int col = 0; col < grid; ++col)
        mask[static_cast<std::size_t>(row * grid + col)] =
            std::hypot(col - cx, row - cy) < r && std::cos(angle) * (col - grid / 2.0) + std::sin(angle) * (row - grid / 2.0) < offset;
  }
  return masks;
}

std::size_t deflatedBitmapBytes(const std::vector<std::vector<char>>& masks)
{
  std::string bitmaps;
  for (const auto& mask : masks) {
    std::string bitmap((mask.size() + 7) / 8, '\0');
    for (std::size_t b = 0; b < mask.size(); ++b)
      if (mask[b])
        bitmap[b / 8] = static_cast<char>(bitmap[b / 8] | (1 << (b % 8)));
    bitmaps += bitmap;
  }
  return test_support::deflatedSize(bitmaps);
}

}  // namespace

TEST(MaskCoding, RoundTripsBlobsNoiseAndConstantMasks)
{
  for (const int grid : {16, 24, 5}) {
    std::vector<std::vector<char>> masks = blobs(300, grid, 7);
    std::mt19937 random(3);
    masks.emplace_back(static_cast<std::size_t>(grid * grid), 0);
    masks.emplace_back(static_cast<std::size_t>(grid * grid), 1);
    for (int k = 0; k < 20; ++k) {  // coin flips: the coder's worst case
      masks.emplace_back(static_cast<std::size_t>(grid * grid));
      for (char& bin : masks.back())
        bin = static_cast<char>(random() & 1);
    }
    const std::string coded = encodeMasks(masks, grid);
    std::vector<std::vector<char>> decoded;
    ASSERT_TRUE(decodeMasks(coded, masks.size(), grid, decoded));
    EXPECT_EQ(decoded, masks) << "grid " << grid;
  }
  std::vector<std::vector<char>> none;
  EXPECT_TRUE(decodeMasks(encodeMasks({}, 16), 0, 16, none));
  EXPECT_TRUE(none.empty());
}

TEST(MaskCoding, BlobsTakeFarFewerBytesThanDeflatedBitmaps)
{
  const std::vector<std::vector<char>> masks = blobs(400, 16, 11);
  const std::size_t coded = encodeMasks(masks, 16).size(), deflated = deflatedBitmapBytes(masks);
  std::printf("400 blob masks of 16 x 16: %zu bytes coded, %zu as deflated bitmaps (%zu raw)\n", coded, deflated,
              masks.size() * 32);
  EXPECT_LT(static_cast<double>(coded), 0.7 * static_cast<double>(deflated));  // measured 1812 / 2864
}

TEST(MaskCoding, ATruncatedStreamIsRefusedNotOverread)
{
  const std::vector<std::vector<char>> masks = blobs(200, 16, 5);
  const std::string coded = encodeMasks(masks, 16);
  std::vector<std::vector<char>> decoded;
  EXPECT_FALSE(decodeMasks(coded.substr(0, coded.size() / 2), masks.size(), 16, decoded));
  EXPECT_FALSE(decodeMasks(std::string(), masks.size(), 16, decoded));
  // Asking for more masks than were coded runs out of stream as well; one byte short or over is
  // refused too.
  EXPECT_FALSE(decodeMasks(coded, 4 * masks.size(), 16, decoded));
  EXPECT_FALSE(decodeMasks(coded.substr(0, coded.size() - 1), masks.size(), 16, decoded));
  EXPECT_FALSE(decodeMasks(coded + '\x5a', masks.size(), 16, decoded));
  EXPECT_TRUE(decodeMasks(coded, masks.size(), 16, decoded));
}
