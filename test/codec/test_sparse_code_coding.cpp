// The .pdc sparse codes' entropy coder (format version 3): exact round trips of atom sets and
// quantised coefficients, fewer bytes than version 2's deflated bitmaps and byte planes on codes
// shaped like the codec's, and cut streams refused.
#include "codec/sparse_code_coding.h"
#include "test_support.h"

#include <pcl_patchdict/core/error.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <cmath>
#include <random>
#include <string>
#include <vector>

using namespace pcl::patchdict::detail;

namespace {

struct Codes {
  std::vector<std::vector<std::uint32_t>> atoms;
  std::vector<std::vector<std::int32_t>> values;
};

/** Codes like the codec's: 0–20 atoms of 100, used unevenly; 6-bit-ish values, a few large. */
Codes codecLikeCodes(std::size_t patches, std::uint32_t seed)
{
  std::mt19937 random(seed);
  std::geometric_distribution<int> count(0.15);
  std::exponential_distribution<double> popularity(1.0);
  std::vector<double> weight(100);
  for (double& w : weight)
    w = popularity(random);
  std::discrete_distribution<int> atom(weight.begin(), weight.end());
  std::normal_distribution<double> value(0.0, 12.0);
  Codes codes;
  for (std::size_t p = 0; p < patches; ++p) {
    std::vector<std::uint32_t> list;
    const int n = std::min(count(random), 20);
    while (static_cast<int>(list.size()) < n) {
      const auto a = static_cast<std::uint32_t>(atom(random));
      if (std::find(list.begin(), list.end(), a) == list.end())
        list.push_back(a);
    }
    std::sort(list.begin(), list.end());
    std::vector<std::int32_t> values;
    for (std::size_t i = 0; i < list.size(); ++i) {
      auto v = static_cast<std::int32_t>(std::lround(value(random)));
      if (random() % 50 == 0)
        v = (random() % 2 ? 1 : -1) * static_cast<std::int32_t>(1000 + random() % 31767);
      values.push_back(v == 0 ? 1 : v);
    }
    codes.atoms.push_back(list);
    codes.values.push_back(values);
  }
  return codes;
}

}  // namespace

TEST(SparseCodeCoding, RoundTripsAtomSetsAndCoefficients)
{
  Codes codes = codecLikeCodes(2000, 3);
  codes.atoms.push_back({});  // a patch with the mean alone
  codes.values.push_back({});
  codes.atoms.push_back({0, 99});  // the extreme atoms and values
  codes.values.push_back({32767, -32767});
  const std::string atoms = encodeAtomSets(codes.atoms, 100);
  const std::string values = encodeCoefficients(codes.values, codes.atoms, 100);
  std::vector<std::vector<std::uint32_t>> atoms_back;
  std::vector<std::vector<std::int32_t>> values_back;
  ASSERT_TRUE(decodeAtomSets(atoms, codes.atoms.size(), 100, 20, atoms_back));
  EXPECT_EQ(atoms_back, codes.atoms);
  ASSERT_TRUE(decodeCoefficients(values, atoms_back, 100, values_back));
  EXPECT_EQ(values_back, codes.values);
}

TEST(SparseCodeCoding, FewerBytesThanVersion2Sections)
{
  const Codes codes = codecLikeCodes(2000, 5);
  std::string bitmaps, low, high;
  std::size_t nonzeros = 0;
  for (std::size_t p = 0; p < codes.atoms.size(); ++p) {
    std::string bitmap(13, '\0');
    for (const std::uint32_t a : codes.atoms[p])
      bitmap[a / 8] = static_cast<char>(bitmap[a / 8] | (1 << (a % 8)));
    bitmaps += bitmap;
    for (const std::int32_t v : codes.values[p]) {
      const std::uint32_t z = (static_cast<std::uint32_t>(v) << 1) ^ static_cast<std::uint32_t>(v >> 31);
      low.push_back(static_cast<char>(z & 0xff));
      high.push_back(static_cast<char>((z >> 8) & 0xff));
      ++nonzeros;
    }
  }
  const std::size_t atoms = encodeAtomSets(codes.atoms, 100).size(), atoms_v2 = test_support::deflatedSize(bitmaps);
  const std::size_t values = encodeCoefficients(codes.values, codes.atoms, 100).size(), values_v2 = test_support::deflatedSize(low + high);
  std::printf("%zu non-zeros: atom sets %zu bytes (deflated bitmaps %zu), coefficients %zu (deflated planes %zu)\n",
              nonzeros, atoms, atoms_v2, values, values_v2);
  EXPECT_LT(atoms, atoms_v2 * 9 / 10);  // measured 7196 / 8957
  EXPECT_LT(values, values_v2);         // measured 8157 / 8805
}

TEST(SparseCodeCoding, CutStreamsAreRefused)
{
  const Codes codes = codecLikeCodes(500, 7);
  const std::string atoms = encodeAtomSets(codes.atoms, 100);
  const std::string values = encodeCoefficients(codes.values, codes.atoms, 100);
  std::vector<std::vector<std::uint32_t>> atoms_back;
  std::vector<std::vector<std::int32_t>> values_back;
  EXPECT_FALSE(decodeAtomSets(atoms.substr(0, atoms.size() / 2), codes.atoms.size(), 100, 20, atoms_back));
  EXPECT_FALSE(decodeAtomSets(std::string(), codes.atoms.size(), 100, 20, atoms_back));
  EXPECT_FALSE(decodeCoefficients(values.substr(0, values.size() / 2), codes.atoms, 100, values_back));
  // One byte short, one byte over, more patches than coded, more atoms per patch than allowed.
  EXPECT_FALSE(decodeAtomSets(atoms.substr(0, atoms.size() - 1), codes.atoms.size(), 100, 20, atoms_back));
  EXPECT_FALSE(decodeAtomSets(atoms + '\x5a', codes.atoms.size(), 100, 20, atoms_back));
  EXPECT_FALSE(decodeAtomSets(atoms, codes.atoms.size() + 50, 100, 20, atoms_back));
  EXPECT_FALSE(decodeAtomSets(atoms, codes.atoms.size(), 100, 2, atoms_back));
  EXPECT_FALSE(decodeCoefficients(values + '\x5a', codes.atoms, 100, values_back));
  ASSERT_TRUE(decodeAtomSets(atoms, codes.atoms.size(), 100, 20, atoms_back));
  ASSERT_TRUE(decodeCoefficients(values, codes.atoms, 100, values_back));
  EXPECT_EQ(values_back, codes.values);
}

TEST(SparseCodeCoding, TheEncoderRefusesWhatTheFormatCannotHold)
{
  const std::vector<std::vector<std::uint32_t>> atoms{{3, 7}};
  EXPECT_THROW(encodeAtomSets({{7, 3}}, 100), pcl::patchdict::Error);
  EXPECT_THROW(encodeAtomSets({{3, 3}}, 100), pcl::patchdict::Error);
  EXPECT_THROW(encodeAtomSets({{100}}, 100), pcl::patchdict::Error);
  EXPECT_THROW(encodeCoefficients({{1, 0}}, atoms, 100), pcl::patchdict::Error);
  EXPECT_THROW(encodeCoefficients({{1, 32768}}, atoms, 100), pcl::patchdict::Error);
  EXPECT_THROW(encodeCoefficients({{1, std::numeric_limits<std::int32_t>::min()}}, atoms, 100), pcl::patchdict::Error);
  EXPECT_THROW(encodeCoefficients({{1}}, atoms, 100), pcl::patchdict::Error);
  EXPECT_NO_THROW(encodeCoefficients({{-32767, 32767}}, atoms, 100));
}
