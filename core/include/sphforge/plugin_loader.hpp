// Finds and loads plugins (Boost.DLL). Search path, in order: $SPHFORGE_PLUGIN_PATH (':'-separated),
// the build's plugin folder, the install prefix's lib/sphforge/plugins. A plugin named NAME lives in
// a file sphforge_NAME.so.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "sphforge/plugin.hpp"

namespace sphforge {

struct LoadedPlugin {
  const PluginDescriptor* descriptor = nullptr;
  std::filesystem::path path;
};

class PluginLoader {
 public:
  /// Uses the default search path (see above).
  PluginLoader();
  explicit PluginLoader(std::vector<std::filesystem::path> search_path);
  ~PluginLoader();
  PluginLoader(const PluginLoader&) = delete;
  PluginLoader& operator=(const PluginLoader&) = delete;

  const std::vector<std::filesystem::path>& search_path() const { return search_path_; }

  /// Loads plugin `name` of `kind`. Throws InputError (file, pointer as given) when not found
  /// (listing the available ones), when the library lacks the plugin symbols, when its ABI
  /// differs, or when it is of another kind.
  const LoadedPlugin& load(PluginKind kind, const std::string& name, const std::string& file = {},
                           const std::string& pointer = {});

  /// Loads a library by path (used by load() and by tests). Same errors.
  const LoadedPlugin& load_file(const std::filesystem::path& path, const std::string& file = {},
                                const std::string& pointer = {});

  /// Every loadable plugin on the search path (unloadable files are reported in `problems`).
  std::vector<const LoadedPlugin*> discover(std::vector<std::string>* problems = nullptr);

  /// Plugins loaded so far (for the versions in summary.json).
  std::vector<const LoadedPlugin*> loaded() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<std::filesystem::path> search_path_;
};

}  // namespace sphforge
