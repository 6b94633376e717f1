// Height fields the cloud patch tests share (test_sparse_patch_inpainter.cpp,
// test_nonlocal_patch_denoising.cpp): a grooved relief and a smooth dome over [-0.25, 0.25]².
#pragma once

#include <cmath>
#include <functional>

namespace relief_test_shapes {

using Height = std::function<double(double, double)>;

/** Grooves 0.004 deep, 0.03 apart, at 30° to x, with walls a few spacings wide. */
inline double grooves(double x, double y)
{
  const double phase = (x * std::cos(0.5236) + y * std::sin(0.5236)) / 0.03;
  return 0.002 * std::tanh(4.0 * std::sin(2.0 * M_PI * phase));
}

inline double dome(double x, double y) { return -0.3 * (x * x + y * y); }

}  // namespace relief_test_shapes
