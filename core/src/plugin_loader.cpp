#include "sphforge/plugin_loader.hpp"

#include <algorithm>
#include <cstdlib>
#include <list>
#include <map>
#include <set>
#include <sstream>

#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/dll/shared_library.hpp>

#include "sphforge/errors.hpp"

namespace sphforge {

namespace fs = std::filesystem;

namespace {
constexpr const char* kAbiSymbol = "sphforge_plugin_abi";
constexpr const char* kDescriptorSymbol = "sphforge_plugin_descriptor";
constexpr const char* kFilePrefix = "sphforge_";
constexpr const char* kFileSuffix = ".so";

bool valid_plugin_name(const std::string& name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
  });
}

std::vector<fs::path> default_search_path() {
  std::vector<fs::path> dirs;
  if (const char* env = std::getenv("SPHFORGE_PLUGIN_PATH")) {
    std::stringstream ss(env);
    std::string item;
    while (std::getline(ss, item, ':'))
      if (!item.empty()) dirs.emplace_back(item);
  }
  // Relative to the running program, so a moved build or install tree still finds its plugins:
  // build tree <build>/bin/sphforge -> <build>/plugins; install <prefix>/bin -> <prefix>/lib/sphforge/plugins.
  boost::dll::fs::error_code ec;
  const auto exe_dir = boost::dll::program_location(ec).parent_path();
  if (!ec) {
    dirs.emplace_back(fs::path(exe_dir.string()) / ".." / "plugins");
    dirs.emplace_back(fs::path(exe_dir.string()) / ".." / "lib" / "sphforge" / "plugins");
  }
  dirs.emplace_back(SPHFORGE_PLUGIN_BUILD_DIR);
  dirs.emplace_back(SPHFORGE_PLUGIN_INSTALL_DIR);
  // Drop duplicates and folders that do not exist, keeping the order.
  std::vector<fs::path> unique;
  std::set<fs::path> seen;
  for (const auto& d : dirs) {
    std::error_code fec;
    if (!fs::is_directory(d, fec)) continue;
    const fs::path canon = fs::weakly_canonical(d, fec);
    if (seen.insert(canon).second) unique.push_back(canon);
  }
  return unique;
}

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "" : ", ") + s;
  return out.empty() ? "none" : out;
}
}  // namespace

struct PluginLoader::Impl {
  struct Entry {
    boost::dll::shared_library library;
    LoadedPlugin plugin;
  };
  std::list<Entry> entries;               // std::list: addresses stay valid
  std::map<fs::path, Entry*> by_path;
};

PluginLoader::PluginLoader() : PluginLoader(default_search_path()) {}
PluginLoader::PluginLoader(std::vector<fs::path> search_path)
    : impl_(std::make_unique<Impl>()), search_path_(std::move(search_path)) {}
PluginLoader::~PluginLoader() = default;

const LoadedPlugin& PluginLoader::load_file(const fs::path& path, const std::string& file,
                                            const std::string& pointer) {
  std::error_code fec;
  const fs::path canon = fs::weakly_canonical(path, fec);
  if (auto it = impl_->by_path.find(canon); it != impl_->by_path.end()) return it->second->plugin;

  boost::dll::shared_library library;
  boost::dll::fs::error_code ec;
  library.load(boost::dll::fs::path(canon.string()), ec, boost::dll::load_mode::rtld_lazy);
  if (ec) throw InputError(file, pointer, "cannot load plugin library " + canon.string() + ": " + ec.message());
  for (const char* symbol : {kAbiSymbol, kDescriptorSymbol})
    if (!library.has(symbol))
      throw InputError(file, pointer,
                       canon.string() + " is not a sphforge plugin: it does not export '" + symbol +
                           "' (build it with sphforge_add_plugin() and SPHFORGE_PLUGIN(...))");
  // The ABI number is read through a function whose signature never changes, before the
  // descriptor (whose layout may differ between ABI versions) is touched.
  const int abi = library.get_alias<int()>(kAbiSymbol)();
  if (abi != kPluginAbiVersion)
    throw InputError(file, pointer,
                     "plugin " + canon.string() + " was built for plugin ABI " + std::to_string(abi) +
                         ", but this sphforge uses ABI " + std::to_string(kPluginAbiVersion) +
                         ": rebuild the plugin against this sphforge");
  const PluginDescriptor& descriptor = library.get_alias<const PluginDescriptor&()>(kDescriptorSymbol)();

  impl_->entries.push_back({std::move(library), LoadedPlugin{&descriptor, canon}});
  impl_->by_path[canon] = &impl_->entries.back();
  return impl_->entries.back().plugin;
}

const LoadedPlugin& PluginLoader::load(PluginKind kind, const std::string& name, const std::string& file,
                                       const std::string& pointer) {
  const std::string kind_name = to_string(kind);
  if (!valid_plugin_name(name))
    throw InputError(file, pointer, "invalid " + kind_name + " plugin name '" + name +
                                        "' (expected lower-case letters, digits and '_')");
  for (const auto& dir : search_path_) {
    const fs::path candidate = dir / (std::string(kFilePrefix) + name + kFileSuffix);
    std::error_code fec;
    if (!fs::exists(candidate, fec)) continue;
    const LoadedPlugin& plugin = load_file(candidate, file, pointer);
    if (plugin.descriptor->kind != kind)
      throw InputError(file, pointer, "plugin '" + name + "' is a " + to_string(plugin.descriptor->kind) +
                                          " plugin, but a " + kind_name + " plugin was expected here");
    if (plugin.descriptor->name != name)
      throw InputError(file, pointer, "library " + candidate.string() + " declares plugin name '" +
                                          plugin.descriptor->name + "', expected '" + name + "'");
    return plugin;
  }
  std::vector<std::string> available;
  for (const LoadedPlugin* p : discover())
    if (p->descriptor->kind == kind) available.push_back(p->descriptor->name);
  std::vector<std::string> dirs;
  for (const auto& d : search_path_) dirs.push_back(d.string());
  throw InputError(file, pointer, "unknown " + kind_name + " plugin '" + name + "'; available: " +
                                      join(available) + " (searched: " + join(dirs) + ")");
}

std::vector<const LoadedPlugin*> PluginLoader::discover(std::vector<std::string>* problems) {
  std::vector<const LoadedPlugin*> found;
  std::set<std::string> names;
  for (const auto& dir : search_path_) {
    std::error_code fec;
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir, fec)) {
      const std::string fname = entry.path().filename().string();
      if (fname.rfind(kFilePrefix, 0) == 0 && entry.path().extension() == kFileSuffix) files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      try {
        const LoadedPlugin& p = load_file(f);
        // The first folder on the search path wins, as in load().
        if (names.insert(std::string(to_string(p.descriptor->kind)) + "/" + p.descriptor->name).second)
          found.push_back(&p);
      } catch (const InputError& e) {
        if (problems) problems->push_back(e.message());
      }
    }
  }
  return found;
}

std::vector<const LoadedPlugin*> PluginLoader::loaded() const {
  std::vector<const LoadedPlugin*> out;
  for (const auto& e : impl_->entries) out.push_back(&e.plugin);
  return out;
}

}  // namespace sphforge
