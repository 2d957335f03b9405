// Which compute backends this build of the core has, and whether they work (internal, not plugin API).
//
// backend.cpp provides the CPU side and, when the core is built without CUDA (SPHFORGE_HAVE_CUDA not
// defined), stubs for the CUDA queries. With CUDA, core/cuda/cuda_backend.cu provides them.
#pragma once

#include <string>

namespace sphforge {

/// Number of usable CUDA devices; 0 when built without CUDA, when there is no device or driver,
/// or when cudaGetDeviceCount fails for any other reason.
int cuda_device_count();

/// One line for logs and summary.json, e.g. "cpu (OpenMP, 16 threads)" or
/// "cpu (OpenMP, 16 threads) + cuda: 1 device" (the CUDA part only when built with CUDA).
std::string backend_description();

/// Evaluates the shared kernels of sphforge/kernels.hpp on the device and compares them with the
/// host evaluation of the same functions. Returns true when they agree; otherwise false and a
/// reason in `message`: "no CUDA device" (also when built without CUDA), a CUDA error, or the worst
/// mismatch. Used by the unit tests to prove the shared host/device physics path.
bool cuda_kernel_self_test(std::string& message);

}  // namespace sphforge
