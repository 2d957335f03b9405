// PluginLoader: loading by name and by path, every error path (with the file and JSON pointer
// of the case that asked for the plugin), discovery, and the default search path.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <unistd.h>

#include "sphforge/errors.hpp"
#include "sphforge/plugin_loader.hpp"
#include "sphforge/version.hpp"

using namespace sphforge;
namespace fs = std::filesystem;

namespace {

const fs::path kTestDir = SPHFORGE_TEST_PLUGIN_DIR;
const fs::path kPluginBuildDir = SPHFORGE_PLUGIN_BUILD_DIR;

bool contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

/// Runs `fn`, which must throw InputError; returns it (or nullopt after recording a failure).
template <typename Fn>
std::optional<InputError> input_error(Fn&& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected InputError, got another exception: " << e.what();
    return std::nullopt;
  }
  ADD_FAILURE() << "expected InputError, nothing was thrown";
  return std::nullopt;
}

/// A fresh temporary folder per test, removed afterwards.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() / ("sphforge_loader_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

/// Sets an environment variable for the scope, restoring the previous value afterwards.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (old_) ::setenv(name_, old_->c_str(), 1);
    else ::unsetenv(name_);
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

}  // namespace

TEST(PluginLoader, TestPluginsWereBuilt) {
  EXPECT_TRUE(fs::exists(kTestDir / "sphforge_test_good.so")) << kTestDir;
  EXPECT_TRUE(fs::exists(kTestDir / "sphforge_test_abi_mismatch.so")) << kTestDir;
  EXPECT_TRUE(fs::exists(kTestDir / "sphforge_test_no_symbol.so")) << kTestDir;
  EXPECT_TRUE(fs::exists(kTestDir / "sphforge_test_throwing.so")) << kTestDir;
}

TEST(PluginLoader, LoadsGoodPluginByName) {
  PluginLoader loader({kTestDir});
  ASSERT_EQ(loader.search_path().size(), 1u);
  const LoadedPlugin& p = loader.load(PluginKind::Contact, "test_good");
  ASSERT_NE(p.descriptor, nullptr);
  EXPECT_EQ(p.descriptor->kind, PluginKind::Contact);
  EXPECT_EQ(p.descriptor->name, "test_good");
  EXPECT_EQ(p.descriptor->version, "9.9.9");
  EXPECT_EQ(p.descriptor->doc, "test plugin");
  ASSERT_EQ(p.descriptor->parameters.size(), 1u);
  EXPECT_EQ(p.descriptor->parameters[0].name, "gain");
  EXPECT_EQ(p.descriptor->parameters[0].unit, "1");
  ASSERT_TRUE(p.descriptor->parameters[0].default_value.has_value());
  EXPECT_DOUBLE_EQ(p.descriptor->parameters[0].default_value->get<double>(), 1.0);
  EXPECT_EQ(p.path.filename(), "sphforge_test_good.so");
  EXPECT_EQ(p.path, fs::weakly_canonical(kTestDir / "sphforge_test_good.so"));
  EXPECT_TRUE(static_cast<bool>(p.descriptor->make_contact));
  EXPECT_FALSE(static_cast<bool>(p.descriptor->make_material));
  EXPECT_FALSE(static_cast<bool>(p.descriptor->make_process));
  EXPECT_FALSE(static_cast<bool>(p.descriptor->make_controller));

  // The factory works and the law it makes is callable.
  auto law = p.descriptor->make_contact(ParamValues(json{{"gain", 1.0}}, "f.json", "/contact/law"));
  ASSERT_NE(law, nullptr);
  double tf[3] = {7, 7, 7}, normal = 1.0, vt[3] = {1, 2, 3}, mass = 1.0, sticking = 0.0;
  ContactBatch batch{};
  batch.count = 1;
  batch.tangential_force = tf;
  batch.normal_force = &normal;
  batch.tangential_velocity = vt;
  batch.mass = &mass;
  batch.sticking = &sticking;
  batch.dt = 1e-3;
  law->tangential_forces(batch);
  EXPECT_EQ(tf[0], 0.0);
  EXPECT_EQ(tf[1], 0.0);
  EXPECT_EQ(tf[2], 0.0);

  // Loading again gives the same entry, not a second copy.
  const LoadedPlugin& again = loader.load(PluginKind::Contact, "test_good");
  EXPECT_EQ(&again, &p);
  ASSERT_EQ(loader.loaded().size(), 1u);
  EXPECT_EQ(loader.loaded()[0], &p);
}

TEST(PluginLoader, UnknownNameListsAvailableAndCarriesLocation) {
  PluginLoader loader({kTestDir});
  auto e = input_error([&] { loader.load(PluginKind::Contact, "nope", "case.json", "/contact/law/plugin"); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->file(), "case.json");
  EXPECT_EQ(e->pointer(), "/contact/law/plugin");
  EXPECT_TRUE(contains(e->message(), "unknown contact plugin 'nope'")) << e->what();
  EXPECT_TRUE(contains(e->message(), "available: test_good")) << e->what();
  EXPECT_TRUE(contains(e->message(), kTestDir.string()) ||
              contains(e->message(), fs::weakly_canonical(kTestDir).string()))
      << "the message should name the folders searched: " << e->what();
  // what() starts with "file at pointer: ".
  EXPECT_EQ(std::string(e->what()).rfind("case.json at /contact/law/plugin: ", 0), 0u) << e->what();

  // Of another kind, test_good is not "available".
  auto m = input_error([&] { loader.load(PluginKind::Material, "nope"); });
  ASSERT_TRUE(m);
  EXPECT_TRUE(contains(m->message(), "unknown material plugin 'nope'")) << m->what();
  EXPECT_TRUE(contains(m->message(), "available: none")) << m->what();
  EXPECT_FALSE(contains(m->message(), "test_good")) << m->what();
}

TEST(PluginLoader, LibraryWithoutSymbolsIsRefused) {
  PluginLoader loader({kTestDir});
  auto e = input_error(
      [&] { loader.load_file(kTestDir / "sphforge_test_no_symbol.so", "c.json", "/material/plugin"); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->file(), "c.json");
  EXPECT_EQ(e->pointer(), "/material/plugin");
  EXPECT_TRUE(contains(e->message(), "does not export 'sphforge_plugin_abi'")) << e->what();
  EXPECT_TRUE(contains(e->message(), "sphforge_test_no_symbol.so")) << e->what();
  EXPECT_TRUE(loader.loaded().empty());

  // By name too (the file name matches the name "test_no_symbol").
  auto n = input_error([&] { loader.load(PluginKind::Contact, "test_no_symbol", "c.json", "/p"); });
  ASSERT_TRUE(n);
  EXPECT_TRUE(contains(n->message(), "does not export 'sphforge_plugin_abi'")) << n->what();
  EXPECT_EQ(n->pointer(), "/p");
}

TEST(PluginLoader, AbiMismatchIsRefusedWithRebuildHint) {
  PluginLoader loader({kTestDir});
  auto e = input_error([&] { loader.load(PluginKind::Contact, "test_abi_mismatch", "x.json", "/contact/law/plugin"); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->file(), "x.json");
  EXPECT_EQ(e->pointer(), "/contact/law/plugin");
  EXPECT_TRUE(contains(e->message(), "ABI 999999")) << e->what();
  EXPECT_TRUE(contains(e->message(), "ABI " + std::to_string(kPluginAbiVersion))) << e->what();
  EXPECT_TRUE(contains(e->message(), "rebuild")) << e->what();
  EXPECT_TRUE(loader.loaded().empty());
}

TEST(PluginLoader, WrongKindIsRefused) {
  PluginLoader loader({kTestDir});
  auto e = input_error([&] { loader.load(PluginKind::Material, "test_good", "m.json", "/material/plugin"); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->file(), "m.json");
  EXPECT_EQ(e->pointer(), "/material/plugin");
  EXPECT_TRUE(contains(e->message(), "'test_good' is a contact plugin")) << e->what();
  EXPECT_TRUE(contains(e->message(), "material plugin was expected")) << e->what();
  for (PluginKind k : {PluginKind::Process, PluginKind::Controller})
    EXPECT_TRUE(input_error([&] { loader.load(k, "test_good"); })) << to_string(k);
}

TEST(PluginLoader, MissingOrGarbageLibraryCannotBeLoaded) {
  TempDir tmp;
  PluginLoader loader({tmp.path()});
  auto missing = input_error([&] { loader.load_file(tmp.path() / "sphforge_absent.so", "a.json", "/x"); });
  ASSERT_TRUE(missing);
  EXPECT_TRUE(contains(missing->message(), "cannot load plugin library")) << missing->what();
  EXPECT_TRUE(contains(missing->message(), "sphforge_absent.so")) << missing->what();
  EXPECT_EQ(missing->file(), "a.json");
  EXPECT_EQ(missing->pointer(), "/x");

  const fs::path garbage = tmp.path() / "sphforge_garbage.so";
  std::ofstream(garbage) << "this is not an ELF shared library\n";
  auto bad = input_error([&] { loader.load_file(garbage, "b.json", "/y"); });
  ASSERT_TRUE(bad);
  EXPECT_TRUE(contains(bad->message(), "cannot load plugin library")) << bad->what();
  EXPECT_TRUE(contains(bad->message(), "sphforge_garbage.so")) << bad->what();
  EXPECT_EQ(bad->pointer(), "/y");

  // By name, the garbage file is found and reported the same way.
  auto by_name = input_error([&] { loader.load(PluginKind::Material, "garbage", "c.json", "/material/plugin"); });
  ASSERT_TRUE(by_name);
  EXPECT_TRUE(contains(by_name->message(), "cannot load plugin library")) << by_name->what();
  EXPECT_TRUE(loader.loaded().empty());
}

TEST(PluginLoader, InvalidNamesAreRejectedBeforeTouchingTheDisk) {
  // A name is never used as a path fragment: "../x" would leave the search folder.
  PluginLoader loader({kTestDir});
  for (const std::string name : {"../x", "A", "", "test good", "Test_good", "a/b", "x.so"}) {
    auto e = input_error([&] { loader.load(PluginKind::Contact, name, "n.json", "/contact/law/plugin"); });
    ASSERT_TRUE(e) << "name '" << name << "'";
    EXPECT_TRUE(contains(e->message(), "invalid contact plugin name '" + name + "'")) << e->what();
    EXPECT_TRUE(contains(e->message(), "lower-case")) << e->what();
    EXPECT_EQ(e->pointer(), "/contact/law/plugin");
  }
  EXPECT_TRUE(loader.loaded().empty());
  // A valid name still works through the same loader.
  PluginLoader good({kTestDir});
  EXPECT_NO_THROW(good.load(PluginKind::Contact, "test_good"));
}

TEST(PluginLoader, DiscoverFindsGoodAndReportsBad) {
  PluginLoader loader({kTestDir});
  std::vector<std::string> problems;
  const auto found = loader.discover(&problems);
  // The three loadable test plugins (sorted by file name), and the two bad ones reported.
  ASSERT_EQ(found.size(), 3u);
  EXPECT_EQ(found[0]->descriptor->name, "test_free_block");
  EXPECT_EQ(found[0]->descriptor->kind, PluginKind::Process);
  EXPECT_EQ(found[1]->descriptor->name, "test_good");
  EXPECT_EQ(found[1]->descriptor->kind, PluginKind::Contact);
  EXPECT_EQ(found[2]->descriptor->name, "test_throwing");
  ASSERT_EQ(problems.size(), 2u);
  const bool abi_reported = std::any_of(problems.begin(), problems.end(), [](const std::string& p) {
    return contains(p, "sphforge_test_abi_mismatch.so") && contains(p, "ABI 999999");
  });
  const bool symbol_reported = std::any_of(problems.begin(), problems.end(), [](const std::string& p) {
    return contains(p, "sphforge_test_no_symbol.so") && contains(p, "does not export 'sphforge_plugin_abi'");
  });
  EXPECT_TRUE(abi_reported) << problems[0] << "\n" << problems[1];
  EXPECT_TRUE(symbol_reported) << problems[0] << "\n" << problems[1];

  // Without a problems list, the bad files are skipped silently; discovering twice is stable.
  const auto again = loader.discover();
  ASSERT_EQ(again.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(again[k], found[k]);
}

TEST(PluginLoader, DiscoverIgnoresFilesThatAreNotPluginCandidates) {
  TempDir tmp;
  fs::copy_file(kTestDir / "sphforge_test_good.so", tmp.path() / "libsomething.so");  // wrong prefix
  fs::copy_file(kTestDir / "sphforge_test_good.so", tmp.path() / "sphforge_test_good.so.bak");  // wrong suffix
  std::ofstream(tmp.path() / "README") << "x";
  PluginLoader loader({tmp.path(), tmp.path() / "does_not_exist"});
  std::vector<std::string> problems;
  EXPECT_TRUE(loader.discover(&problems).empty());
  EXPECT_TRUE(problems.empty()) << problems.front();
}

TEST(PluginLoader, DefaultSearchPathHonoursEnvironmentAndFindsRealPlugins) {
  ASSERT_TRUE(fs::is_directory(kPluginBuildDir)) << kPluginBuildDir;
  // The test folder is only reachable through SPHFORGE_PLUGIN_PATH; it must come first.
  ScopedEnv env("SPHFORGE_PLUGIN_PATH", kTestDir.string() + ":" + kPluginBuildDir.string() + "::/nonexistent/dir");
  PluginLoader loader;
  ASSERT_GE(loader.search_path().size(), 2u);
  EXPECT_EQ(loader.search_path()[0], fs::weakly_canonical(kTestDir));
  // Folders are listed once each, and only existing ones.
  std::set<fs::path> unique(loader.search_path().begin(), loader.search_path().end());
  EXPECT_EQ(unique.size(), loader.search_path().size());
  for (const auto& d : loader.search_path()) EXPECT_TRUE(fs::is_directory(d)) << d;
  EXPECT_EQ(std::count(loader.search_path().begin(), loader.search_path().end(),
                       fs::weakly_canonical(kPluginBuildDir)),
            1);

  EXPECT_EQ(loader.load(PluginKind::Contact, "test_good").descriptor->version, "9.9.9");

  struct Expected {
    PluginKind kind;
    const char* name;
  };
  for (const Expected& x : {Expected{PluginKind::Material, "elastoplastic"}, Expected{PluginKind::Contact, "coulomb"},
                            Expected{PluginKind::Controller, "prescribed"},
                            Expected{PluginKind::Process, "ram_extrusion"}}) {
    const LoadedPlugin& p = loader.load(x.kind, x.name, "case.json", "/p");
    EXPECT_EQ(p.descriptor->name, x.name);
    EXPECT_EQ(p.descriptor->kind, x.kind);
    EXPECT_FALSE(p.descriptor->version.empty()) << x.name;
    EXPECT_FALSE(p.descriptor->parameters.empty()) << x.name;
    EXPECT_EQ(p.path.parent_path(), fs::weakly_canonical(kPluginBuildDir)) << x.name;
  }
  EXPECT_EQ(loader.loaded().size(), 5u);

  std::vector<std::string> problems;
  std::set<std::string> names;
  for (const LoadedPlugin* p : loader.discover(&problems)) names.insert(p->descriptor->name);
  for (const char* n : {"test_good", "elastoplastic", "coulomb", "prescribed", "ram_extrusion"})
    EXPECT_EQ(names.count(n), 1u) << n;
  // The two bad test plugins are reported, nothing from the real plugin folder.
  const std::string test_dir = fs::weakly_canonical(kTestDir).string() + "/";
  const std::string build_dir = fs::weakly_canonical(kPluginBuildDir).string() + "/";
  EXPECT_EQ(std::count_if(problems.begin(), problems.end(), [&](const std::string& p) { return contains(p, test_dir); }),
            2);
  for (const auto& p : problems) EXPECT_FALSE(contains(p, build_dir)) << p;
}

TEST(PluginLoader, EnvironmentWithoutTestFolderDoesNotFindTestPlugins) {
  ScopedEnv env("SPHFORGE_PLUGIN_PATH", kPluginBuildDir.string());
  PluginLoader loader;
  auto e = input_error([&] { loader.load(PluginKind::Contact, "test_good", "c.json", "/contact/law/plugin"); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->message(), "unknown contact plugin 'test_good'")) << e->what();
  EXPECT_TRUE(contains(e->message(), "coulomb")) << e->what();  // the real one is listed as available
}

TEST(PluginLoader, InputErrorThrownByAPluginOutlivesThePlugin) {
  // A plugin may throw InputError itself. The error reaches main() after the loader holding the
  // library is gone (stack unwinding destroys it), so nothing of the error may live in the plugin:
  // before errors.hpp anchored the error types in the core, reading it here crashed.
  std::string message, pointer;
  try {
    PluginLoader loader({kTestDir});
    const LoadedPlugin& p = loader.load(PluginKind::Contact, "test_throwing");
    p.descriptor->make_contact(ParamValues(json{{"gain", 1.0}}, "f.json", "/contact/law"));
    ADD_FAILURE() << "the plugin did not throw";
  } catch (const InputError& e) {
    message = e.what();
    pointer = e.pointer();
  }
  EXPECT_EQ(message, "f.json at /contact/law/gain: gain refused by the plugin");
  EXPECT_EQ(pointer, "/contact/law/gain");
}
