#include "backend.hpp"

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace sphforge {

std::string backend_description() {
#if defined(_OPENMP)
  const int threads = omp_get_max_threads();
  std::string text = "cpu (OpenMP, " + std::to_string(threads) + (threads == 1 ? " thread)" : " threads)");
#else
  std::string text = "cpu (serial, built without OpenMP)";
#endif
#if defined(SPHFORGE_HAVE_CUDA)
  const int devices = cuda_device_count();
  text += " + cuda: " + std::to_string(devices) + (devices == 1 ? " device" : " devices");
#endif
  return text;
}

#if !defined(SPHFORGE_HAVE_CUDA)
// Built without CUDA: there is never a device. With CUDA, core/cuda/cuda_backend.cu defines these.
int cuda_device_count() { return 0; }

bool cuda_kernel_self_test(std::string& message) {
  message = "no CUDA device (sphforge was built without CUDA)";
  return false;
}
#endif

}  // namespace sphforge
