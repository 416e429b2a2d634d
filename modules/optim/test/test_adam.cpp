#include <gtest/gtest.h>

#include <cmath>

#include "photoscene/core.hpp"
#include "photoscene/optim.hpp"

namespace ps {
namespace {

TEST(Optim_Adam, minimizes_an_ill_conditioned_quadratic) {
  // f(x) = sum_i a_i (x_i - c_i)^2 with a spread of curvatures over 4 orders of magnitude
  const std::vector<float> a = {1e-2f, 1.f, 10.f, 100.f}, c = {0.3f, -0.7f, 0.1f, 0.9f};
  std::vector<float> x(4, 0.f), g(4);
  Adam adam(4, {0.05f});
  for (int it = 0; it < 2000; ++it) {
    for (int i = 0; i < 4; ++i) g[i] = 2 * a[i] * (x[i] - c[i]);
    adam.step(x, g);
  }
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(x[i], c[i], 2e-2) << i;
}

TEST(Optim_Adam, respects_bounds_mask_and_ignores_non_finite_gradients) {
  std::vector<float> x = {0.5f, 0.5f, 0.5f};
  Adam adam(3, {0.1f});
  adam.setBounds({0.f, 0.f, 0.f}, {1.f, 1.f, 1.f});
  adam.setMask({1, 0, 1});
  for (int it = 0; it < 100; ++it) adam.step(x, {-1.f, -1.f, std::nanf("")});
  EXPECT_FLOAT_EQ(x[0], 1.0f);  // pushed against the upper bound
  EXPECT_FLOAT_EQ(x[1], 0.5f);  // masked
  EXPECT_FLOAT_EQ(x[2], 0.5f);  // NaN gradient skipped
  EXPECT_EQ(adam.steps(), 100);
  adam.reset();
  EXPECT_EQ(adam.steps(), 0);
  // the first step has magnitude lr whatever the gradient scale (bias correction)
  std::vector<float> y = {0.f};
  Adam one(1, {0.01f});
  one.step(y, {1e-6f});
  EXPECT_NEAR(y[0], -0.01f, 1e-4);
}

TEST(Optim_Plateau, stops_on_a_plateau_not_during_descent) {
  PlateauDetector p({10, 1e-3, 0});
  int stoppedAt = -1;
  for (int it = 0; it < 500; ++it) {
    const double loss = it < 200 ? std::exp(-0.02 * it) : std::exp(-0.02 * 200);
    if (p.update(loss)) {
      stoppedAt = it;
      break;
    }
  }
  EXPECT_GT(stoppedAt, 200);
  EXPECT_LT(stoppedAt, 230);
  PlateauDetector q;
  EXPECT_TRUE(q.update(std::nan("")));
}

}  // namespace
}  // namespace ps
