// CUDA side of backend.hpp: device query and a self-test proving that the physics written once in
// sphforge/kernels.hpp (SPH_HD functions) runs on the device and agrees with the host.
// Compiled into libsphforge_core only when CMake finds nvcc (SPHFORGE_HAVE_CUDA=1).
#include <cuda_runtime.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "backend.hpp"
#include "sphforge/kernels.hpp"

namespace sphforge {
namespace {

// Values per sample: W, dW/dr and (dW/dr)/r for the cubic spline, then the same for Wendland C2.
constexpr int kOutputsPerSample = 6;

SPH_HD SPH_INLINE void evaluate_kernels(double r, double h, double* out) {
  out[0] = kernel_value(KernelKind::CubicSpline, r, h);
  out[1] = kernel_derivative(KernelKind::CubicSpline, r, h);
  out[2] = kernel_gradient_factor(KernelKind::CubicSpline, r, h);
  out[3] = kernel_value(KernelKind::WendlandC2, r, h);
  out[4] = kernel_derivative(KernelKind::WendlandC2, r, h);
  out[5] = kernel_gradient_factor(KernelKind::WendlandC2, r, h);
}

__global__ void evaluate_kernels_on_device(const double* r, double h, int n, double* out) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) evaluate_kernels(r[i], h, out + static_cast<std::size_t>(i) * kOutputsPerSample);
}

std::string cuda_error(const char* what, cudaError_t status) {
  return std::string(what) + ": " + cudaGetErrorName(status) + " (" + cudaGetErrorString(status) + ")";
}

// Device buffer released on every return path.
struct DeviceBuffer {
  double* ptr = nullptr;
  ~DeviceBuffer() {
    if (ptr != nullptr) cudaFree(ptr);
  }
};

}  // namespace

int cuda_device_count() {
  int count = 0;
  const cudaError_t status = cudaGetDeviceCount(&count);
  if (status != cudaSuccess) {
    cudaGetLastError();  // clear the sticky error so later CUDA calls start clean
    return 0;
  }
  return count;
}

bool cuda_kernel_self_test(std::string& message) {
  if (cuda_device_count() == 0) {
    message = "no CUDA device";
    return false;
  }

  // Samples cover r = 0, both branches of the cubic spline, q = 1 and q = 2 exactly, and q > 2.
  const double h = 1.3e-3;
  const int n = 1001;
  std::vector<double> r(n);
  for (int i = 0; i < n; ++i) r[i] = 2.5 * h * static_cast<double>(i) / static_cast<double>(n - 1);
  r[400] = h;
  r[800] = 2.0 * h;

  std::vector<double> host(static_cast<std::size_t>(n) * kOutputsPerSample);
  for (int i = 0; i < n; ++i) evaluate_kernels(r[i], h, host.data() + static_cast<std::size_t>(i) * kOutputsPerSample);

  DeviceBuffer d_r, d_out;
  cudaError_t status = cudaMalloc(&d_r.ptr, n * sizeof(double));
  if (status == cudaSuccess) status = cudaMalloc(&d_out.ptr, host.size() * sizeof(double));
  if (status != cudaSuccess) {
    message = cuda_error("cudaMalloc", status);
    return false;
  }
  status = cudaMemcpy(d_r.ptr, r.data(), n * sizeof(double), cudaMemcpyHostToDevice);
  if (status != cudaSuccess) {
    message = cuda_error("cudaMemcpy to device", status);
    return false;
  }
  const int block = 128;
  evaluate_kernels_on_device<<<(n + block - 1) / block, block>>>(d_r.ptr, h, n, d_out.ptr);
  status = cudaGetLastError();
  if (status == cudaSuccess) status = cudaDeviceSynchronize();
  if (status != cudaSuccess) {
    message = cuda_error("kernel launch", status);
    return false;
  }
  std::vector<double> device(host.size());
  status = cudaMemcpy(device.data(), d_out.ptr, device.size() * sizeof(double), cudaMemcpyDeviceToHost);
  if (status != cudaSuccess) {
    message = cuda_error("cudaMemcpy to host", status);
    return false;
  }

  // Same IEEE double arithmetic on both sides; nvcc may contract a*b+c into FMA (and g++ may not),
  // which changes the last bits only. Compare relative to the largest magnitude of each quantity.
  const double tolerance = 1e-12;
  double scale[kOutputsPerSample] = {};
  for (std::size_t k = 0; k < host.size(); ++k)
    scale[k % kOutputsPerSample] = std::fmax(scale[k % kOutputsPerSample], std::fabs(host[k]));
  double worst = 0.0;
  std::size_t worst_index = 0;
  for (std::size_t k = 0; k < host.size(); ++k) {
    const double error = std::fabs(device[k] - host[k]) / scale[k % kOutputsPerSample];
    if (error > worst) {
      worst = error;
      worst_index = k;
    }
  }
  char text[256];
  std::snprintf(text, sizeof(text),
                "%d samples x %d kernel quantities on the device; worst relative difference %.3e "
                "(quantity %zu at r = %.6e m, tolerance %.0e)",
                n, kOutputsPerSample, worst, worst_index % kOutputsPerSample,
                r[worst_index / kOutputsPerSample], tolerance);
  message = text;
  return worst <= tolerance;
}

}  // namespace sphforge
