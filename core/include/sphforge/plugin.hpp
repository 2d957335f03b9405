// Plugin descriptors and the export macro. A plugin is a shared library that exports, via
// Boost.DLL aliases, two symbols:
//   sphforge_plugin_abi         int()                       -- checked first by the loader
//   sphforge_plugin_descriptor  const PluginDescriptor&()   -- read only if the ABI matches
// Use SPHFORGE_PLUGIN(function_returning_descriptor) once in the plugin's source, and the CMake
// function sphforge_add_plugin(NAME SOURCES...) to build it.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <type_traits>

#include <boost/dll/alias.hpp>

#include "sphforge/contact_law.hpp"
#include "sphforge/controller.hpp"
#include "sphforge/material.hpp"
#include "sphforge/parameters.hpp"
#include "sphforge/process.hpp"
#include "sphforge/version.hpp"

namespace sphforge {

enum class PluginKind { Material, Contact, Process, Controller };

const char* to_string(PluginKind kind);

struct PluginDescriptor {
  PluginKind kind = PluginKind::Material;
  std::string name;      ///< the name case files use ("elastoplastic")
  std::string version;   ///< plugin version, written to summary.json
  std::string doc;       ///< one line
  ParamSpecs parameters; ///< everything the plugin reads from its case section

  // Exactly one factory is set, matching `kind`. The ParamValues were validated against
  // `parameters` by the core; plugins may check cross-parameter conditions and call fail().
  std::function<std::unique_ptr<Material>(const ParamValues&)> make_material;
  std::function<std::unique_ptr<ContactLaw>(const ParamValues&)> make_contact;
  std::function<std::unique_ptr<Process>(const ParamValues&)> make_process;
  std::function<std::unique_ptr<Controller>(const ParamValues&)> make_controller;
};

namespace detail {
inline int plugin_abi_version() { return kPluginAbiVersion; }
}  // namespace detail

/// Builds the descriptor of a plugin whose implementation `Impl` derives from one of the four
/// interfaces and is constructible from its validated ParamValues; sets the kind and the factory.
///   static const PluginDescriptor d = make_plugin_descriptor<Elastoplastic>("elastoplastic", "0.1.0", "doc", {...});
template <class Impl>
PluginDescriptor make_plugin_descriptor(std::string name, std::string version, std::string doc,
                                        ParamSpecs parameters) {
  PluginDescriptor p;
  p.name = std::move(name);
  p.version = std::move(version);
  p.doc = std::move(doc);
  p.parameters = std::move(parameters);
  if constexpr (std::is_base_of_v<Material, Impl>) {
    p.kind = PluginKind::Material;
    p.make_material = [](const ParamValues& v) { return std::make_unique<Impl>(v); };
  } else if constexpr (std::is_base_of_v<ContactLaw, Impl>) {
    p.kind = PluginKind::Contact;
    p.make_contact = [](const ParamValues& v) { return std::make_unique<Impl>(v); };
  } else if constexpr (std::is_base_of_v<Process, Impl>) {
    p.kind = PluginKind::Process;
    p.make_process = [](const ParamValues& v) { return std::make_unique<Impl>(v); };
  } else {
    static_assert(std::is_base_of_v<Controller, Impl>, "Impl must derive from a sphforge plugin interface");
    p.kind = PluginKind::Controller;
    p.make_controller = [](const ParamValues& v) { return std::make_unique<Impl>(v); };
  }
  return p;
}

}  // namespace sphforge

/// Exports the plugin. DESCRIPTOR_FN: a function `const sphforge::PluginDescriptor& f()`.
#define SPHFORGE_PLUGIN(DESCRIPTOR_FN)                                          \
  BOOST_DLL_ALIAS(sphforge::detail::plugin_abi_version, sphforge_plugin_abi)   \
  BOOST_DLL_ALIAS(DESCRIPTOR_FN, sphforge_plugin_descriptor)
