// `sphforge bench`: the same case at several particle spacings, each as a child `sphforge run`
// (so that wait4() reports that run's own peak RSS), then bench.csv, bench.json and bench.png.
#include "bench_command.hpp"
#include "output_folder.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "bench_plot.hpp"
#include "engine/simulation.hpp"
#include "sphforge/case_file.hpp"
#include "sphforge/errors.hpp"
#include "sphforge/parameters.hpp"
#include "sphforge/units.hpp"

extern char** environ;

namespace sphforge::cli {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\n\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\n\r");
  return s.substr(b, e - b + 1);
}

std::string format_number(double v, int digits = 17) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

/// A spacing for people: "0.75 mm" (metres when 1 m or more, micrometres below 1 um).
std::string spacing_label(double dx) {
  if (dx >= 1.0) return format_number(dx, 6) + " m";
  if (dx < 1e-6) return format_number(dx * 1e6, 6) + " um";
  return format_number(dx * 1e3, 6) + " mm";
}

/// The run folder's name: "dx_0.75mm".
std::string spacing_folder(double dx) {
  std::string label = spacing_label(dx);
  label.erase(std::remove(label.begin(), label.end(), ' '), label.end());
  return "dx_" + label;
}

/// The unit a metric's name ends with ("peak_extrusion_pressure_Pa" -> "Pa"), if the last
/// '_'-separated part is a unit expression the units API knows.
std::optional<std::string> metric_unit(const std::string& name) {
  const auto us = name.rfind('_');
  if (us == std::string::npos || us + 1 >= name.size()) return std::nullopt;
  const std::string suffix = name.substr(us + 1);
  try {
    parse_unit(suffix);
    return suffix;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

/// The CSV column of a metric: its name when that ends with a unit, else name + "_1" (the
/// project's convention is that metric names carry their unit; one without it is a count or ratio).
std::string metric_column(const std::string& name) { return metric_unit(name) ? name : name + "_1"; }

std::string read_text(const std::string& path, const char* what) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path, "", std::string("cannot open ") + what + ": " + std::strerror(ENOENT));
  if (fs::is_directory(path, ec)) throw InputError(path, "", std::string("cannot open ") + what + ": it is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", std::string("cannot open ") + what);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Reference values of summary metrics, each in the unit its metric name ends with.
struct Reference {
  std::string file;  ///< empty: against the finest spacing
  std::map<std::string, double> metrics;
};

Reference read_reference(const std::string& file) {
  Reference ref;
  ref.file = file;
  const std::string text = read_text(file, "reference file");
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    // Located the way the case loader does it: e.byte is the 1-based position of the bad byte.
    std::size_t line = 1, column = 1;
    for (std::size_t i = 0; i + 1 < e.byte && i < text.size(); ++i) {
      if (text[i] == '\n') {
        ++line;
        column = 1;
      } else {
        ++column;
      }
    }
    throw InputError(file, "", "JSON syntax error at line " + std::to_string(line) + ", column " + std::to_string(column));
  }
  if (!root.is_object()) throw InputError(file, "", std::string("expected a JSON object, got ") + root.type_name());
  if (!root.contains("metrics"))
    throw InputError(file, "/metrics", "missing; expected {\"metrics\": {\"metric name\": value or \"value unit\", ...}}");
  const json& metrics = root["metrics"];
  if (!metrics.is_object() || metrics.empty())
    throw InputError(file, "/metrics",
                     std::string("expected a non-empty object of metric name -> value, got ") + metrics.type_name());
  for (const auto& [name, value] : metrics.items()) {
    const std::string pointer = "/metrics/" + json_pointer_escape(name);
    const std::optional<std::string> unit = metric_unit(name);
    double v = 0.0;
    if (value.is_number()) {
      v = value.get<double>();
    } else if (value.is_string()) {
      // "1.2 MPa" for the metric peak_extrusion_pressure_Pa: converted to the metric's own unit.
      try {
        const std::string expected = unit.value_or("1");
        const Unit u = parse_unit(expected);
        v = (parse_quantity(value.get<std::string>(), expected) - u.offset) / u.scale;
      } catch (const std::invalid_argument& e) {
        throw InputError(file, pointer, e.what());
      }
    } else {
      throw InputError(file, pointer, std::string("expected a number or a string \"value unit\", got ") + value.type_name());
    }
    if (!std::isfinite(v)) throw InputError(file, pointer, "the reference value is not finite");
    ref.metrics[name] = v;
  }
  return ref;
}

/// The output folder, by the rules of `sphforge run`; the default is runs/<case>-bench.
fs::path bench_folder(const BenchOptions& o, const std::string& case_name) {
  return cli::choose_output_folder(o.out, o.force, fs::path("runs") / (case_name + "-bench"));
}

struct ChildResult {
  int exit_code = -1;     ///< 128 + signal when killed
  double peak_rss_MB = 0; ///< ru_maxrss of the child
  double process_wall_s = 0;
};

/// Runs this executable with `args` (argv[1...]), stdin from /dev/null, stdout and stderr into
/// `log`, and waits for it, collecting its resource usage.
ChildResult spawn_self(const std::vector<std::string>& args, const fs::path& log) {
  std::vector<std::string> full = {"sphforge"};
  full.insert(full.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : full) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  const std::string log_path = log.string();
  posix_spawn_file_actions_addopen(&actions, 1, log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = 0;
  const auto start = std::chrono::steady_clock::now();
  const int rc = posix_spawn(&pid, "/proc/self/exe", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw std::runtime_error(std::string("cannot start a child sphforge run: ") + std::strerror(rc));

  int status = 0;
  struct rusage usage {};
  while (wait4(pid, &status, 0, &usage) < 0)
    if (errno != EINTR) throw std::runtime_error(std::string("waiting for a child sphforge run: ") + std::strerror(errno));
  ChildResult r;
  r.process_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  else if (WIFSIGNALED(status)) r.exit_code = 128 + WTERMSIG(status);
  r.peak_rss_MB = static_cast<double>(usage.ru_maxrss) * 1024.0 / 1e6;  // ru_maxrss is in KiB on Linux
  return r;
}

/// The last non-empty line of a (child's) log, for the one-line report of a failed run.
std::string last_line(const fs::path& file) {
  std::ifstream in(file);
  std::string line, last;
  while (std::getline(in, line))
    if (!trim(line).empty()) last = trim(line);
  return last;
}

struct BenchRow {
  double spacing_m = 0;
  fs::path folder;
  ChildResult child;
  std::string status;  ///< summary.json "status", or why there is none
  std::string message; ///< diagnosis of a failed run
  std::optional<double> particles, steps, wall_s, particle_steps_per_s;
  std::map<std::string, double> metrics;  ///< numeric metrics only
  bool ok() const { return child.exit_code == 0; }
};

std::optional<double> number_at(const json& j, const char* key) {
  if (j.contains(key) && j[key].is_number()) return j[key].get<double>();
  return std::nullopt;
}

void read_summary(BenchRow& row) {
  const fs::path file = row.folder / "summary.json";
  std::ifstream in(file);
  if (!in) {
    if (row.status.empty()) row.status = "no summary.json";
    return;
  }
  const json s = json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!s.is_object()) {
    row.status = "unreadable summary.json";
    return;
  }
  if (s.contains("status") && s["status"].is_string()) row.status = s["status"].get<std::string>();
  if (s.contains("diagnosis") && s["diagnosis"].is_string() && row.message.empty())
    row.message = s["diagnosis"].get<std::string>();
  row.particles = number_at(s, "particles");
  row.steps = number_at(s, "steps");
  row.wall_s = number_at(s, "wall_time_s");
  row.particle_steps_per_s = number_at(s, "particle_steps_per_s");
  if (s.contains("metrics") && s["metrics"].is_object())
    for (const auto& [name, value] : s["metrics"].items())
      if (value.is_number()) row.metrics[name] = value.get<double>();
}

/// Everything derived from the rows: metric columns, the reference in use, relative errors.
struct Table {
  std::vector<std::string> metrics;                 ///< numeric in at least one run, sorted
  std::map<std::string, double> reference;          ///< per metric
  std::optional<std::size_t> reference_row;         ///< without --reference: the finest finished run
  std::vector<std::map<std::string, double>> errors;  ///< per row, per metric
  std::vector<std::string> zero_reference;          ///< metrics whose reference is 0 (no relative error)
};

Table tabulate(const std::vector<BenchRow>& rows, const Reference& ref) {
  Table t;
  std::map<std::string, bool> seen;
  for (const auto& r : rows)
    for (const auto& [name, v] : r.metrics) seen[name] = true;
  for (const auto& [name, _] : seen) t.metrics.push_back(name);
  if (!ref.file.empty()) {
    t.reference = ref.metrics;
  } else {
    for (std::size_t i = 0; i < rows.size(); ++i)
      if (rows[i].ok() && (!t.reference_row || rows[i].spacing_m < rows[*t.reference_row].spacing_m))
        t.reference_row = i;
    if (t.reference_row) t.reference = rows[*t.reference_row].metrics;
  }
  t.errors.resize(rows.size());
  for (const auto& [name, value] : t.reference)
    if (value == 0.0 && seen.count(name)) t.zero_reference.push_back(name);
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (const auto& [name, value] : rows[i].metrics) {
      const auto it = t.reference.find(name);
      if (it == t.reference.end() || it->second == 0.0) continue;
      t.errors[i][name] = std::abs(value - it->second) / std::abs(it->second);
    }
  return t;
}

std::vector<std::string> csv_header(const Table& t) {
  std::vector<std::string> h = {"spacing_m", "particles_1", "steps_1", "wall_s", "particle_steps_per_s",
                                "peak_rss_MB", "exit_code_1"};
  for (const auto& m : t.metrics) {
    h.push_back(metric_column(m));
    h.push_back(m + "_error_1");
  }
  return h;
}

/// Writes `text` to `file` through a temporary file and a rename (a reader never sees half a file).
void write_atomically(const fs::path& file, const std::string& text) {
  const fs::path tmp = file.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) throw std::runtime_error("cannot write '" + file.string() + "'");
  }
  fs::rename(tmp, file);
}

void write_csv(const fs::path& file, const std::vector<BenchRow>& rows, const Table& t) {
  std::ostringstream out;
  const auto header = csv_header(t);
  for (std::size_t i = 0; i < header.size(); ++i) out << (i ? "," : "") << header[i];
  out << '\n';
  auto cell = [&](const std::optional<double>& v) { out << ',' << (v ? format_number(*v) : ""); };
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const BenchRow& r = rows[i];
    out << format_number(r.spacing_m);
    cell(r.particles);
    cell(r.steps);
    cell(r.wall_s);
    cell(r.particle_steps_per_s);
    cell(r.child.peak_rss_MB);
    cell(static_cast<double>(r.child.exit_code));
    for (const auto& m : t.metrics) {
      const auto v = r.metrics.find(m);
      cell(v == r.metrics.end() ? std::nullopt : std::optional<double>(v->second));
      const auto e = t.errors[i].find(m);
      cell(e == t.errors[i].end() ? std::nullopt : std::optional<double>(e->second));
    }
    out << '\n';
  }
  write_atomically(file, out.str());
}

}  // namespace

std::vector<double> parse_spacing_list(const std::string& text) {
  const std::string where = "--spacing";
  if (trim(text).empty())
    throw InputError("", where, "expected a comma-separated list of particle spacings, e.g. \"0.5 mm,0.25 mm\"");
  std::vector<double> out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = text.find(',', start);
    const std::string item = trim(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (item.empty())
      throw InputError("", where, "empty item in '" + text + "'; expected a comma-separated list such as \"0.5 mm,0.25 mm\"");
    double dx = 0.0;
    try {
      dx = parse_quantity(item, "m");
    } catch (const std::invalid_argument& e) {
      throw InputError("", where, "'" + item + "': " + e.what());
    }
    if (!(dx > 0.0) || !std::isfinite(dx)) throw InputError("", where, "'" + item + "': a spacing must be positive and finite");
    out.push_back(dx);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  std::sort(out.begin(), out.end(), std::greater<>());
  for (std::size_t i = 1; i < out.size(); ++i)
    if (spacing_folder(out[i]) == spacing_folder(out[i - 1]))
      throw InputError("", where, "spacing " + spacing_label(out[i]) + " is given twice");
  return out;
}

std::string parameter_key(const std::string& parameter) {
  std::string key;  // the dotted form, which the child runs' --set takes
  for (const auto& segment : case_key_segments(parameter, "--parameter")) key += (key.empty() ? "" : ".") + segment;
  return key;
}


namespace {

std::string status_of(const BenchRow& r) {
  if (!r.status.empty()) return r.status;
  switch (r.child.exit_code) {
    case 0: return "done";
    case 2: return "invalid input";
    case 3: return "unstable";
    default: return r.child.exit_code > 128 ? "killed by signal " + std::to_string(r.child.exit_code - 128)
                                            : "failed (exit " + std::to_string(r.child.exit_code) + ")";
  }
}

void print_row(const BenchRow& r) {
  auto num = [](const std::optional<double>& v, const char* fmt) {
    if (!v) return std::string("-");
    char buf[48];
    std::snprintf(buf, sizeof buf, fmt, *v);
    return std::string(buf);
  };
  std::printf("%12s %10s %8s %10s %17s %14s  %s\n", spacing_label(r.spacing_m).c_str(),
              num(r.particles, "%.0f").c_str(), num(r.steps, "%.0f").c_str(), num(r.wall_s, "%.3f").c_str(),
              num(r.particle_steps_per_s, "%.4g").c_str(), num(r.child.peak_rss_MB, "%.1f").c_str(),
              status_of(r).c_str());
  if (!r.ok() && !r.message.empty()) std::printf("%12s %s\n", "", r.message.c_str());
  std::fflush(stdout);
}

std::string describe_reference(const Reference& ref, const Table& t, const std::vector<BenchRow>& rows) {
  if (!ref.file.empty()) return "reference values from " + ref.file;
  if (t.reference_row)
    return "reference: the finest finished spacing, dx = " + spacing_label(rows[*t.reference_row].spacing_m) +
           " (its own error, 0, is not drawn on the log axis)";
  return "reference: the finest finished spacing (no run finished)";
}

void print_errors(const std::vector<BenchRow>& rows, const Table& t, const Reference& ref) {
  std::printf("\nrelative error |value - ref| / |ref|, %s:\n", describe_reference(ref, t, rows).c_str());
  std::size_t width = 6;
  for (const auto& m : t.metrics) width = std::max(width, m.size());
  std::printf("  %-*s", static_cast<int>(width), "metric");
  for (const auto& r : rows) std::printf(" %12s", spacing_label(r.spacing_m).c_str());
  std::printf("\n");
  for (const auto& m : t.metrics) {
    std::printf("  %-*s", static_cast<int>(width), m.c_str());
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const auto e = t.errors[i].find(m);
      if (e == t.errors[i].end()) std::printf(" %12s", "-");
      else std::printf(" %12.4g", e->second);
    }
    std::printf("\n");
  }
  std::fflush(stdout);
}

/// One plot series per metric: (wall time, relative error) of every run that has both.
std::vector<PlotSeries> error_series(const std::vector<BenchRow>& rows, const Table& table) {
  std::vector<PlotSeries> series;
  for (const auto& m : table.metrics) {
    PlotSeries s{m, {}};
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const auto e = table.errors[i].find(m);
      if (rows[i].wall_s && e != table.errors[i].end()) s.points.emplace_back(*rows[i].wall_s, e->second);
    }
    series.push_back(std::move(s));
  }
  return series;
}

json bench_json(const BenchOptions& o, const std::string& case_name, const std::string& key,
                const std::vector<BenchRow>& rows, const Table& t, const Reference& ref,
                const std::vector<PlotSeries>& series) {
  json j;
  j["case"] = case_name;
  j["case_file"] = o.case_path;
  j["parameter"] = key;
  j["overrides"] = o.overrides;
  j["error_definition"] = "|value - reference| / |reference| per metric; empty when there is no reference "
                          "value for the metric or it is 0";
  json r;
  if (!ref.file.empty()) {
    r["kind"] = "file";
    r["file"] = ref.file;
  } else {
    r["kind"] = "finest_spacing";
    if (t.reference_row) r["spacing_m"] = rows[*t.reference_row].spacing_m;
  }
  r["metrics"] = t.reference;
  if (!t.zero_reference.empty()) r["zero_reference_metrics"] = t.zero_reference;
  std::vector<std::string> unmatched;
  for (const auto& [name, _] : t.reference)
    if (std::find(t.metrics.begin(), t.metrics.end(), name) == t.metrics.end()) unmatched.push_back(name);
  if (!unmatched.empty()) r["unmatched_metrics"] = unmatched;
  j["reference"] = r;
  j["columns"] = csv_header(t);
  json legend = json::object();
  const std::vector<std::optional<std::array<int, 3>>> colours = plot_colours(series);  // as bench.png draws them
  for (std::size_t i = 0; i < t.metrics.size(); ++i) {
    if (!colours[i]) {
      legend[t.metrics[i]] = nullptr;  // not drawn: no positive error
      continue;
    }
    const std::array<int, 3>& c = *colours[i];
    char hex[8];
    std::snprintf(hex, sizeof hex, "#%02x%02x%02x", c[0], c[1], c[2]);
    legend[t.metrics[i]] = hex;
  }
  j["plot"] = {{"file", "bench.png"}, {"x", "wall_s (log)"}, {"y", "<metric>_error_1 (log)"}, {"colours", legend}};
  json runs = json::array();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const BenchRow& b = rows[i];
    json run = {{"spacing_m", b.spacing_m},
                {"folder", b.folder.string()},
                {"exit_code", b.child.exit_code},
                {"status", status_of(b)},
                {"peak_rss_MB", b.child.peak_rss_MB},
                {"process_wall_s", b.child.process_wall_s},
                {"metrics", b.metrics},
                {"errors", t.errors[i]}};
    if (!b.message.empty()) run["message"] = b.message;
    if (b.particles) run["particles"] = *b.particles;
    if (b.steps) run["steps"] = *b.steps;
    if (b.wall_s) run["wall_s"] = *b.wall_s;
    if (b.particle_steps_per_s) run["particle_steps_per_s"] = *b.particle_steps_per_s;
    runs.push_back(run);
  }
  j["runs"] = runs;
  return j;
}

}  // namespace

int run_bench(const BenchOptions& o) {
  // Everything the user supplied is checked before a file is written.
  const std::vector<double> spacings = parse_spacing_list(o.spacing_list);
  const std::string key = parameter_key(o.parameter);
  const Reference ref = o.reference.empty() ? Reference{} : read_reference(o.reference);
  auto overrides_for = [&](double dx) {
    std::vector<std::string> v = o.overrides;
    v.push_back(key + "=" + format_number(dx));
    return v;
  };
  std::string case_name;
  {
    // The case with the coarsest spacing: validates the case, the overrides and the parameter key
    // (an unknown key is rejected at its JSON pointer) and builds that scene.
    PluginLoader loader;
    const CaseDocument doc = load_case(o.case_path, overrides_for(spacings.front()));
    Simulation sim(doc, loader);
    case_name = sim.settings().case_name;
  }
  const fs::path out = bench_folder(o, case_name);
  fs::create_directories(out / "runs");

  if (!o.quiet) {
    std::printf("sphforge bench: '%s', %zu spacings of %s -> %s\n", case_name.c_str(), spacings.size(), key.c_str(),
                out.string().c_str());
    std::printf("%12s %10s %8s %10s %17s %14s  %s\n", "spacing", "particles", "steps", "wall [s]",
                "particle-steps/s", "peak RSS [MB]", "status");
    std::fflush(stdout);
  }

  std::vector<BenchRow> rows;
  for (const double dx : spacings) {
    BenchRow row;
    row.spacing_m = dx;
    row.folder = out / "runs" / spacing_folder(dx);
    fs::create_directories(row.folder);
    std::vector<std::string> args = {"run", o.case_path, "--out", row.folder.string(), "--quiet", "--force"};
    for (const auto& ov : overrides_for(dx)) {
      args.push_back("--set");
      args.push_back(ov);
    }
    const fs::path log = row.folder / "run.log";
    row.child = spawn_self(args, log);
    // Runs that finish or blow up write summary.json; for any other exit an earlier file there
    // (--force) must not be mistaken for this run's.
    if (row.child.exit_code == 0 || row.child.exit_code == 3) read_summary(row);
    if (!row.ok() && row.message.empty()) row.message = last_line(log);
    rows.push_back(row);
    if (!o.quiet) print_row(rows.back());
    write_csv(out / "bench.csv", rows, tabulate(rows, ref));  // partial results survive an interrupted bench
  }

  const Table table = tabulate(rows, ref);
  write_csv(out / "bench.csv", rows, table);
  const std::vector<PlotSeries> series = error_series(rows, table);
  write_atomically(out / "bench.json", bench_json(o, case_name, key, rows, table, ref, series).dump(2) + "\n");
  std::string spacing_text;
  for (const double dx : spacings) spacing_text += (spacing_text.empty() ? "" : ", ") + spacing_label(dx);
  write_error_plot(out / "bench.png", series, case_name + ": relative error against wall time",
                   describe_reference(ref, table, rows) + "\n" + key + " = " + spacing_text);

  for (const auto& name : table.zero_reference)
    std::cerr << "warning: the reference value of metric '" << name << "' is 0; its relative error is left empty\n";
  for (const auto& [name, _] : table.reference)
    if (!ref.file.empty() && std::find(table.metrics.begin(), table.metrics.end(), name) == table.metrics.end())
      std::cerr << "warning: " << ref.file << " at /metrics/" << json_pointer_escape(name)
                << ": no run reported a numeric metric of that name\n";

  if (!o.quiet) {
    print_errors(rows, table, ref);
    std::printf("\nbench.csv, bench.json, bench.png: %s\n", fs::absolute(out).string().c_str());
    std::fflush(stdout);
  }

  const auto all = [&](int code) {
    return std::all_of(rows.begin(), rows.end(), [&](const BenchRow& r) { return r.child.exit_code == code; });
  };
  if (std::any_of(rows.begin(), rows.end(), [](const BenchRow& r) { return r.ok(); })) return 0;
  if (all(3)) return 3;
  if (all(2)) return 2;
  return 1;
}

}  // namespace sphforge::cli
