// Reading a case file: JSON parse with a clear error, and `--set a.b.c=value` overrides.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace sphforge {

struct CaseDocument {
  nlohmann::json root;
  std::string file;  ///< path as given by the user, used in every error message
};

/// The names along a case key: a dotted path "a.b.c" (array elements by index,
/// "controllers.0.value") or a JSON pointer "/a/b/c" (~1 and ~0 unescaped). A segment that is empty,
/// or that holds '.' or '=', throws InputError at `where` (e.g. "--set" or "--parameter"): such a key
/// cannot be written as a dotted path.
std::vector<std::string> case_key_segments(const std::string& key, const std::string& where);

/// Reads and parses `path`. Missing file, unreadable file and JSON syntax errors (with line and
/// column) throw InputError. Then applies each override "a.b.c=value" or "/a/b/c=value" (array
/// elements by index, "controllers.0.value=2 mm/s"; case_key_segments); value is parsed as JSON when it is valid JSON, else taken as a
/// string. Missing objects on the way are created (so an optional section the file leaves out can
/// be set); walking into a non-object or past an array's end is an error, reported at the
/// pointer "--set a.b.c". Validation of the result then rejects keys that do not exist.
CaseDocument load_case(const std::string& path, const std::vector<std::string>& overrides = {});

}  // namespace sphforge
