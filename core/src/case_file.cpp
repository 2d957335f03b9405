// Case file loading: strict JSON with located syntax errors, then `--set key.path=value`
// overrides applied in the order given.

#include "sphforge/case_file.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "sphforge/errors.hpp"
#include "sphforge/parameters.hpp"  // json_pointer_escape

namespace sphforge {

namespace {

using nlohmann::json;

std::string read_file(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) {
    const std::string reason = ec ? ec.message() : std::strerror(ENOENT);
    throw InputError(path, "", "cannot open case file: " + reason);
  }
  if (fs::is_directory(st)) throw InputError(path, "", "cannot open case file: it is a directory");

  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int err = errno;
    throw InputError(path, "", std::string("cannot open case file: ") +
                                   (err != 0 ? std::strerror(err) : "unknown error"));
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(path, "", "cannot read case file");
  return text.str();
}

/// nlohmann reports the byte count read when the error was detected (1-based position of the
/// offending byte); line and column are derived here so the message does not depend on the
/// library version's wording. Columns count bytes, which matches what editors show for ASCII.
std::pair<std::size_t, std::size_t> line_and_column(const std::string& text, std::size_t byte) {
  const std::size_t offset = std::min(byte > 0 ? byte - 1 : 0, text.size());
  std::size_t line = 1, line_start = 0;
  for (std::size_t i = 0; i < offset; ++i)
    if (text[i] == '\n') {
      ++line;
      line_start = i + 1;
    }
  return {line, offset - line_start + 1};
}

/// The library's explanation without its "[json.exception.parse_error.101] parse error at
/// line 1, column 2: " preamble, which would repeat (or contradict) our own location.
std::string parse_error_reason(const json::parse_error& e) {
  std::string what = e.what();
  const auto colon = what.find(": ");
  if (colon != std::string::npos) what = what.substr(colon + 2);
  return what;
}

json parse_case(const std::string& text, const std::string& path) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    const auto [line, column] = line_and_column(text, e.byte);
    throw InputError(path, "",
                     "JSON syntax error at line " + std::to_string(line) + ", column " +
                         std::to_string(column) + ": " + parse_error_reason(e));
  }
  if (!root.is_object())
    throw InputError(path, "", std::string("expected a JSON object at the top level, got ") + root.type_name());
  return root;
}

/// An array index segment: digits only (no sign, no spaces), within the array's bounds.
bool parse_index(const std::string& segment, std::size_t& index) {
  if (segment.empty() || !std::all_of(segment.begin(), segment.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return false;
  const auto [end, ec] = std::from_chars(segment.data(), segment.data() + segment.size(), index);
  return ec == std::errc() && end == segment.data() + segment.size();
}

void apply_override(json& root, const std::string& override_text, const std::string& path) {
  const std::size_t eq = override_text.find('=');
  if (eq == std::string::npos)
    throw InputError(path, "--set " + override_text,
                     "malformed override; expected key.path=value (e.g. run.end_time=0.5)");
  const std::string key = override_text.substr(0, eq);
  const std::string value_text = override_text.substr(eq + 1);
  const std::string where = "--set " + key;

  std::vector<std::string> segments;
  try {
    segments = case_key_segments(key, where);
  } catch (const InputError& e) {
    throw InputError(path, where, e.message());
  }

  // Valid JSON (numbers, true, [1,2], "quoted") is taken as such; anything else is a string,
  // so that unit quantities like 0.4 MPa need no JSON quoting on the command line.
  json value = json::parse(value_text, nullptr, /*allow_exceptions=*/false);
  if (value.is_discarded()) value = value_text;

  json* node = &root;
  std::string pointer;
  for (std::size_t i = 0; i + 1 < segments.size(); ++i) {
    const std::string& seg = segments[i];
    pointer += "/" + json_pointer_escape(seg);
    std::size_t index = 0;
    if (node->is_object() && node->contains(seg)) {
      node = &(*node)[seg];
    } else if (node->is_object()) {
      // An optional section the file leaves out (e.g. numerics.artificial_viscosity) is created;
      // validation then rejects it if no such section exists.
      node = &((*node)[seg] = json::object());
    } else if (node->is_array() && parse_index(seg, index) && index < node->size()) {
      node = &(*node)[index];
    } else {
      throw InputError(path, where, "no object at " + pointer);
    }
    if (!node->is_object() && !node->is_array()) throw InputError(path, where, "no object at " + pointer);
  }

  const std::string& last = segments.back();
  if (node->is_object()) {
    (*node)[last] = std::move(value);  // the last key may be new: optional values can be added
    return;
  }
  std::size_t index = 0;
  if (!parse_index(last, index))
    throw InputError(path, where, "'" + last + "' is not an index into the array at " + pointer);
  if (index >= node->size())
    throw InputError(path, where,
                     "index " + last + " is out of range: the array at " + pointer + " has " +
                         std::to_string(node->size()) + " elements");
  (*node)[index] = std::move(value);
}

}  // namespace

std::vector<std::string> case_key_segments(const std::string& key, const std::string& where) {
  std::vector<std::string> segments;
  const bool pointer = !key.empty() && key[0] == '/';
  const char separator = pointer ? '/' : '.';
  for (std::size_t start = pointer ? 1 : 0;;) {
    const std::size_t end = key.find(separator, start);
    std::string segment = key.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (pointer) {  // RFC 6901: ~1 is '/', ~0 is '~'
      std::string unescaped;
      for (std::size_t i = 0; i < segment.size(); ++i) {
        const bool escape = segment[i] == '~' && i + 1 < segment.size() && (segment[i + 1] == '0' || segment[i + 1] == '1');
        unescaped += escape ? (segment[++i] == '0' ? '~' : '/') : segment[i];
      }
      segment = unescaped;
    }
    if (segment.empty() || segment.find_first_of(".=") != std::string::npos)
      throw InputError("", where,
                       "'" + key + "' is not a key path; expected dot-separated names such as material.density, or a JSON "
                       "pointer such as /material/density");
    segments.push_back(segment);
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return segments;
}

CaseDocument load_case(const std::string& path, const std::vector<std::string>& overrides) {
  CaseDocument doc;
  doc.file = path;
  doc.root = parse_case(read_file(path), path);
  for (const auto& o : overrides) apply_override(doc.root, o, path);
  return doc;
}

}  // namespace sphforge
