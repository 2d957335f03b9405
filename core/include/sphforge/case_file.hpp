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

/// Reads and parses `path`. Missing file, unreadable file and JSON syntax errors (with line and
/// column) throw InputError. Then applies each override "a.b.c=value" (array elements by index,
/// "controllers.0.value=2 mm/s"); value is parsed as JSON when it is valid JSON, else taken as a
/// string. Missing objects on the way are created (so an optional section the file leaves out can
/// be set); walking into a non-object or past an array's end is an error, reported at the
/// pointer "--set a.b.c". Validation of the result then rejects keys that do not exist.
CaseDocument load_case(const std::string& path, const std::vector<std::string>& overrides = {});

}  // namespace sphforge
