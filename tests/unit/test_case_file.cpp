// Case file loading: missing file, located syntax errors, --set overrides.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "sphforge/case_file.hpp"
#include "sphforge/errors.hpp"

namespace sphforge {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// Each test gets its own fresh directory under the system temp dir, removed afterwards.
class CaseFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string templ = (fs::temp_directory_path() / "sphforge_case_XXXXXX").string();
    ASSERT_NE(mkdtemp(templ.data()), nullptr);
    dir_ = templ;
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  std::string write(const std::string& name, const std::string& text) const {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }

  /// Loads expecting an InputError; fails the test if none is thrown.
  static InputError load_error(const std::string& path, const std::vector<std::string>& overrides = {}) {
    try {
      load_case(path, overrides);
    } catch (const InputError& e) {
      return e;
    }
    ADD_FAILURE() << "expected an InputError loading " << path;
    return InputError("", "", "");
  }

  std::string sample() const {
    return write("case.json", R"({
  "run": {"end_time": 1.0, "name": "demo"},
  "material": {"plugin": "elastoplastic", "yield_stress": "250 MPa"},
  "controllers": [{"plugin": "constant", "value": "1 mm/s"}, {"plugin": "pid", "gain": 2}],
  "flag": true
}
)");
  }

  fs::path dir_;
};

bool contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

TEST_F(CaseFileTest, LoadsObject) {
  const std::string path = sample();
  const CaseDocument doc = load_case(path);
  EXPECT_EQ(doc.file, path);
  EXPECT_EQ(doc.root["run"]["end_time"], 1.0);
  EXPECT_EQ(doc.root["controllers"][1]["gain"], 2);
}

TEST_F(CaseFileTest, MissingFile) {
  const std::string path = (dir_ / "nope.json").string();
  const InputError e = load_error(path);
  EXPECT_EQ(e.file(), path);
  EXPECT_EQ(e.pointer(), "");
  EXPECT_EQ(e.message(), "cannot open case file: No such file or directory");
}

TEST_F(CaseFileTest, DirectoryIsNotACaseFile) {
  const InputError e = load_error(dir_.string());
  EXPECT_TRUE(contains(e.message(), "cannot open case file")) << e.message();
}

TEST_F(CaseFileTest, SyntaxErrorNamesLineAndColumn) {
  const std::string path = write("bad.json", "{\n  \"a\": 1,\n  \"b\": }\n");
  const InputError e = load_error(path);
  EXPECT_EQ(e.file(), path);
  EXPECT_EQ(e.pointer(), "");
  EXPECT_EQ(e.message().rfind("JSON syntax error at line 3, column 8: ", 0), 0u) << e.message();
  EXPECT_TRUE(contains(e.message(), "unexpected '}'")) << e.message();
  EXPECT_FALSE(contains(e.message(), "json.exception")) << e.message();
}

TEST_F(CaseFileTest, SyntaxErrorTrailingComma) {
  const InputError e = load_error(write("comma.json", "{\n  \"a\": 1,\n  \"b\": 2,\n}\n"));
  EXPECT_EQ(e.message().rfind("JSON syntax error at line 4, column 1", 0), 0u) << e.message();
}

TEST_F(CaseFileTest, SyntaxErrorAtEndOfInput) {
  const InputError e = load_error(write("short.json", "{\"a\": [1, 2"));
  EXPECT_EQ(e.message().rfind("JSON syntax error at line 1, column ", 0), 0u) << e.message();
  EXPECT_TRUE(contains(e.message(), "end of input")) << e.message();
  EXPECT_TRUE(contains(load_error(write("empty.json", "")).message(), "line 1, column 1"));
}

TEST_F(CaseFileTest, TopLevelMustBeObject) {
  const InputError e = load_error(write("array.json", "[1, 2]"));
  EXPECT_EQ(e.pointer(), "");
  EXPECT_EQ(e.message(), "expected a JSON object at the top level, got array");
}

TEST_F(CaseFileTest, OverridesParseJsonOrString) {
  const CaseDocument doc =
      load_case(sample(), {"run.end_time=0.5", "material.yield_stress=0.4 MPa", "flag=false",
                           "run.name=\"quoted\"", "run.list=[1,2]", "run.empty="});
  EXPECT_EQ(doc.root["run"]["end_time"], 0.5);
  EXPECT_TRUE(doc.root["run"]["end_time"].is_number());
  EXPECT_EQ(doc.root["material"]["yield_stress"], "0.4 MPa");
  EXPECT_EQ(doc.root["flag"], false);
  EXPECT_EQ(doc.root["run"]["name"], "quoted");
  EXPECT_EQ(doc.root["run"]["list"], json({1, 2}));
  EXPECT_EQ(doc.root["run"]["empty"], "");
}

TEST_F(CaseFileTest, OverrideValueMayContainEquals) {
  const CaseDocument doc = load_case(sample(), {"run.name=a=b"});
  EXPECT_EQ(doc.root["run"]["name"], "a=b");
}

TEST_F(CaseFileTest, OverrideArrayIndex) {
  const CaseDocument doc = load_case(sample(), {"controllers.0.value=2 mm/s", "controllers.1.gain=3"});
  EXPECT_EQ(doc.root["controllers"][0]["value"], "2 mm/s");
  EXPECT_EQ(doc.root["controllers"][1]["gain"], 3);
  // Replacing a whole element.
  const CaseDocument whole = load_case(sample(), {"controllers.1={\"plugin\":\"off\"}"});
  EXPECT_EQ(whole.root["controllers"][1], json({{"plugin", "off"}}));
}

TEST_F(CaseFileTest, OverrideNewKeys) {
  const CaseDocument doc = load_case(sample(), {"run.output_every=10", "newtop=1", "controllers.0.extra=x"});
  EXPECT_EQ(doc.root["run"]["output_every"], 10);
  EXPECT_EQ(doc.root["newtop"], 1);
  EXPECT_EQ(doc.root["controllers"][0]["extra"], "x");
}

TEST_F(CaseFileTest, OverridesApplyInOrder) {
  const CaseDocument doc = load_case(sample(), {"run.end_time=2", "run.end_time=3"});
  EXPECT_EQ(doc.root["run"]["end_time"], 3);
}

TEST_F(CaseFileTest, OverrideBadPaths) {
  const std::string path = sample();
  struct Case {
    std::string override_text;
    std::string pointer;
    std::string message_part;
  };
  const Case cases[] = {
      {"run.end_time.x=1", "--set run.end_time.x", "no object at /run/end_time"},
      {"controllers.5.value=1", "--set controllers.5.value", "no object at /controllers/5"},
      {"controllers.x.value=1", "--set controllers.x.value", "no object at /controllers/x"},
      {"controllers.7=1", "--set controllers.7", "index 7 is out of range: the array at /controllers has 2 elements"},
      {"controllers.first=1", "--set controllers.first", "'first' is not an index into the array at /controllers"},
      {"run..end_time=1", "--set run..end_time", "is not a key path"},
      {"=1", "--set ", "is not a key path"},
      {"/run//end_time=1", "--set /run//end_time", "is not a key path"},
      {"/run/end.time=1", "--set /run/end.time", "is not a key path"},
      {"run.end_time", "--set run.end_time", "malformed override; expected key.path=value"},
  };
  for (const auto& c : cases) {
    const InputError e = load_error(path, {c.override_text});
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.pointer(), c.pointer) << c.override_text;
    EXPECT_TRUE(contains(e.message(), c.message_part)) << c.override_text << ": " << e.message();
  }
}

// A JSON pointer names the same key as its dotted path (bench's --parameter takes both too), and
// unescapes ~1 and ~0 (RFC 6901).
TEST_F(CaseFileTest, OverrideTakesAJsonPointer) {
  const CaseDocument dotted = load_case(sample(), {"controllers.0.value=2 mm/s", "run.end_time=3"});
  const CaseDocument pointer = load_case(sample(), {"/controllers/0/value=2 mm/s", "/run/end_time=3"});
  EXPECT_EQ(pointer.root, dotted.root);
  EXPECT_EQ(pointer.root["controllers"][0]["value"], "2 mm/s");
  const std::string path = write("escaped.json", R"({"a/b": {"c~d": 1}})");
  EXPECT_EQ(load_case(path, {"/a~1b/c~0d=2"}).root["a/b"]["c~d"], 2);
  EXPECT_EQ(case_key_segments("/a~1b/c~0d", "--set"), (std::vector<std::string>{"a/b", "c~d"}));
  EXPECT_EQ(case_key_segments("process.particle_spacing", "--set"), (std::vector<std::string>{"process", "particle_spacing"}));
}

TEST_F(CaseFileTest, OverridePointerIsEscaped) {
  const std::string path = write("slash.json", R"({"a/b": {"c": 1}})");
  EXPECT_EQ(load_case(path, {"a/b.c=2"}).root["a/b"]["c"], 2);
  EXPECT_EQ(load_error(path, {"a/b.c.d=2"}).message(), "no object at /a~1b/c");
}

// A section the file leaves out (all defaults) can still be overridden: the missing objects are
// created, and the case validation later decides whether such a section exists.
TEST_F(CaseFileTest, OverrideCreatesMissingObjects) {
  const CaseDocument doc = load_case(sample(), {"numerics.artificial_viscosity.alpha=0.5"});
  EXPECT_EQ(doc.root["numerics"]["artificial_viscosity"]["alpha"], 0.5);
}

}  // namespace
}  // namespace sphforge
