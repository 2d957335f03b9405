#include "sphforge/plugin.hpp"

#include <limits>

namespace sphforge {

const char* to_string(PluginKind kind) {
  switch (kind) {
    case PluginKind::Material: return "material";
    case PluginKind::Contact: return "contact";
    case PluginKind::Process: return "process";
    case PluginKind::Controller: return "controller";
  }
  return "unknown";
}

void Material::yield_stress(const MaterialBatch& batch, double* out) const {
  for (std::size_t i = 0; i < batch.count; ++i) out[i] = std::numeric_limits<double>::infinity();
}

}  // namespace sphforge
