// A plugin that claims another plugin ABI: the loader must refuse it before reading its descriptor.
#include <boost/dll/alias.hpp>

namespace {
int wrong_abi() { return 999999; }
int descriptor_never_read() { return 0; }
}  // namespace

BOOST_DLL_ALIAS(wrong_abi, sphforge_plugin_abi)
BOOST_DLL_ALIAS(descriptor_never_read, sphforge_plugin_descriptor)
