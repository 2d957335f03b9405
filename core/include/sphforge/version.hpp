#pragma once

namespace sphforge {

/// Version of the core engine, written to summary.json.
inline constexpr const char* kCoreVersion = "0.1.0";

/// Binary interface version of the plugin API (every header in include/sphforge/).
/// Bump it whenever a plugin interface, PluginDescriptor or a type they pass changes layout;
/// the loader refuses a plugin built against another number.
inline constexpr int kPluginAbiVersion = 4;

}  // namespace sphforge
