// SPH smoothing kernels (core/include/sphforge/kernels.hpp): normalisation, derivatives, compact
// support, the r = 0 gradient factor, and the host/device agreement of the shared code (CUDA).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "backend.hpp"
#include "sphforge/kernels.hpp"

namespace {

using sphforge::KernelKind;

constexpr double kPi = 3.14159265358979323846;
const KernelKind kKinds[] = {KernelKind::CubicSpline, KernelKind::WendlandC2};
// Smoothing lengths spanning the scales of the bundled cases (sub-mm to m) and a non-round one.
const double kSmoothingLengths[] = {2.5e-4, 1.3e-3, 1.0, 7.0};

std::string name(KernelKind kind) {
  return kind == KernelKind::CubicSpline ? "cubic_spline" : "wendland_c2";
}

// Composite Simpson rule on [a, b] with `panels` (even) sub-intervals.
template <class F>
double simpson(F f, double a, double b, int panels) {
  const double dx = (b - a) / panels;
  double sum = f(a) + f(b);
  for (int i = 1; i < panels; ++i) sum += (i % 2 == 1 ? 4.0 : 2.0) * f(a + i * dx);
  return sum * dx / 3.0;
}

// int_0^{2h} 4 pi r^2 W(r, h) dr, split at r = h where the cubic spline changes branch (each piece
// is then a polynomial in r, of degree <= 7, so Simpson with 2000 panels per piece is exact to
// round-off; the Wendland kernel is one polynomial and the split does it no harm).
double radial_integral(KernelKind kind, double h) {
  auto integrand = [&](double r) { return 4.0 * kPi * r * r * sphforge::kernel_value(kind, r, h); };
  return simpson(integrand, 0.0, h, 2000) + simpson(integrand, h, 2.0 * h, 2000);
}

TEST(SphKernels, NormalisedToOneIn3D) {
  for (KernelKind kind : kKinds)
    for (double h : kSmoothingLengths)
      EXPECT_NEAR(radial_integral(kind, h), 1.0, 1e-6) << name(kind) << " h = " << h;
}

TEST(SphKernels, CentralValuesMatchTheDocumentedNormalisation) {
  for (double h : kSmoothingLengths) {
    const double h3 = h * h * h;
    EXPECT_DOUBLE_EQ(sphforge::cubic_spline_value(0.0, h), 1.0 / (kPi * h3)) << h;
    EXPECT_DOUBLE_EQ(sphforge::wendland_c2_value(0.0, h), 21.0 / (16.0 * kPi * h3)) << h;
    // Cubic spline at q = 1 is sigma/4 from both branches.
    EXPECT_NEAR(sphforge::cubic_spline_value(h, h) * kPi * h3, 0.25, 1e-14) << h;
  }
}

TEST(SphKernels, DerivativeMatchesCentralFiniteDifference) {
  for (KernelKind kind : kKinds) {
    for (double h : kSmoothingLengths) {
      const double step = 1e-6 * h;
      // Magnitude of dW/dr over the support, to state the tolerance relative to it.
      double scale = 0.0;
      for (int i = 0; i <= 400; ++i)
        scale = std::fmax(scale, std::fabs(sphforge::kernel_derivative(kind, 2.0 * h * i / 400.0, h)));
      ASSERT_GT(scale, 0.0);
      // Interior points of (0, 2h), including both sides of q = 1 (the cubic spline is C2 there,
      // so the central difference is accurate across it).
      for (int i = 1; i < 200; ++i) {
        const double r = 2.0 * h * i / 200.0;
        const double fd = (sphforge::kernel_value(kind, r + step, h) -
                           sphforge::kernel_value(kind, r - step, h)) / (2.0 * step);
        // Truncation O(step^2 W''') ~ 1e-12 and round-off ~ 1e-16 W / step ~ 1e-10, relative.
        EXPECT_NEAR(sphforge::kernel_derivative(kind, r, h), fd, 1e-8 * scale)
            << name(kind) << " h = " << h << " q = " << r / h;
      }
    }
  }
}

TEST(SphKernels, GradientFactorIsDerivativeOverRAndFiniteAtZero) {
  for (KernelKind kind : kKinds) {
    for (double h : kSmoothingLengths) {
      for (int i = 1; i <= 250; ++i) {
        const double r = 2.5 * h * i / 250.0;
        const double expected = sphforge::kernel_derivative(kind, r, h) / r;
        EXPECT_NEAR(sphforge::kernel_gradient_factor(kind, r, h), expected,
                    1e-13 * std::fabs(sphforge::kernel_gradient_factor(kind, 0.0, h)))
            << name(kind) << " h = " << h << " q = " << r / h;
      }
      // Limit r -> 0: -3 sigma/h^2 (cubic spline), -5 sigma/h^2 (Wendland C2).
      const double at_zero = sphforge::kernel_gradient_factor(kind, 0.0, h);
      const double expected_at_zero = kind == KernelKind::CubicSpline
                                          ? -3.0 * sphforge::cubic_spline_sigma(h) / (h * h)
                                          : -5.0 * sphforge::wendland_c2_sigma(h) / (h * h);
      EXPECT_TRUE(std::isfinite(at_zero)) << name(kind);
      EXPECT_DOUBLE_EQ(at_zero, expected_at_zero) << name(kind);
      const double tiny = 1e-9 * h;
      EXPECT_NEAR(sphforge::kernel_gradient_factor(kind, tiny, h), at_zero, 1e-8 * std::fabs(at_zero));
    }
  }
}

TEST(SphKernels, CompactSupportOfRadius2h) {
  for (KernelKind kind : kKinds) {
    for (double h : kSmoothingLengths) {
      EXPECT_DOUBLE_EQ(sphforge::kernel_support_radius(h), 2.0 * h);
      for (double q : {2.0, 2.0 + 1e-12, 2.5, 3.0, 10.0, 1e6}) {
        EXPECT_EQ(sphforge::kernel_value(kind, q * h, h), 0.0) << name(kind) << " q = " << q;
        EXPECT_EQ(sphforge::kernel_derivative(kind, q * h, h), 0.0) << name(kind) << " q = " << q;
        EXPECT_EQ(sphforge::kernel_gradient_factor(kind, q * h, h), 0.0) << name(kind) << " q = " << q;
      }
      // Inside the support: positive, strictly decreasing, and going to 0 continuously at q = 2.
      double previous = sphforge::kernel_value(kind, 0.0, h);
      for (int i = 1; i < 1000; ++i) {
        const double w = sphforge::kernel_value(kind, 2.0 * h * i / 1000.0, h);
        EXPECT_GT(w, 0.0) << name(kind) << " i = " << i;
        EXPECT_LT(w, previous) << name(kind) << " i = " << i;
        previous = w;
      }
      const double near_edge = sphforge::kernel_value(kind, (2.0 - 1e-4) * h, h);
      EXPECT_GT(near_edge, 0.0);
      EXPECT_LT(near_edge, 1e-9 * sphforge::kernel_value(kind, 0.0, h)) << name(kind);
    }
  }
}

TEST(SphKernels, DispatchMatchesSpecificFunctions) {
  const double h = 1.3e-3;
  for (int i = 0; i <= 50; ++i) {
    const double r = 2.5 * h * i / 50.0;
    EXPECT_EQ(sphforge::kernel_value(KernelKind::CubicSpline, r, h), sphforge::cubic_spline_value(r, h));
    EXPECT_EQ(sphforge::kernel_value(KernelKind::WendlandC2, r, h), sphforge::wendland_c2_value(r, h));
    EXPECT_EQ(sphforge::kernel_derivative(KernelKind::CubicSpline, r, h),
              sphforge::cubic_spline_derivative(r, h));
    EXPECT_EQ(sphforge::kernel_derivative(KernelKind::WendlandC2, r, h),
              sphforge::wendland_c2_derivative(r, h));
  }
}

TEST(SphBackend, DescriptionNamesTheCpuBackend) {
  const std::string text = sphforge::backend_description();
  EXPECT_EQ(text.rfind("cpu (", 0), 0u) << text;
#if defined(SPHFORGE_HAVE_CUDA)
  EXPECT_NE(text.find(" + cuda: "), std::string::npos) << text;
#else
  EXPECT_EQ(text.find("cuda"), std::string::npos) << text;
  EXPECT_EQ(sphforge::cuda_device_count(), 0);
#endif
}

// The CUDA backend shares kernels.hpp with the CPU; on a machine with a GPU this proves the device
// evaluation agrees with the host one. Without a device (or a build without CUDA) it is skipped,
// and the skip message says why.
TEST(SphKernelsCuda, DeviceEvaluationMatchesHost) {
  std::string message;
  const bool ok = sphforge::cuda_kernel_self_test(message);
  if (!ok && sphforge::cuda_device_count() == 0) GTEST_SKIP() << message;
  EXPECT_TRUE(ok) << message;
}

}  // namespace
