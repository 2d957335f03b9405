// The sphforge command: run, check, bench, plugins. Exit codes (DESIGN.md "Outputs"):
// 0 done, 1 other failure, 2 invalid input, 3 numerical instability.
#include <omp.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bench_command.hpp"
#include "engine/simulation.hpp"
#include "output_folder.hpp"
#include "sphforge/errors.hpp"
#include "sphforge/version.hpp"

namespace fs = std::filesystem;
using namespace sphforge;

namespace {

constexpr int kExitOk = 0, kExitOther = 1, kExitInput = 2, kExitUnstable = 3;
constexpr const char* kDefaultCase = "cases/ram_extrusion/paste_orifice_quick.json";

void usage(std::ostream& out) {
  out << "sphforge " << kCoreVersion << " - SPH workbench for thermo-mechanical forming processes\n\n"
      << "usage:\n"
      << "  sphforge run [CASE] [--out DIR] [--set key.path=value]... [--quiet] [--force] [--restart FILE]\n"
      << "      run a case (default: the bundled " << kDefaultCase << ")\n"
      << "      --restart: continue from a checkpoint_NNNNNN.h5 of an earlier run of the same case into a\n"
      << "      new folder (run.checkpoint_interval writes them; only \"run\" may change, e.g.\n"
      << "      --set run.end_time=...). See docs/checkpoints.md\n"
      << "      --set: a dotted key (controllers.0.value=90 rpm) or a JSON pointer (/controllers/0/value=90 rpm)\n"
      << "  sphforge check CASE [--set key.path=value]...\n"
      << "      validate a case, build its scene and list passes and fields, without running\n"
      << "  sphforge bench [CASE] --spacing DX,DX,... [--parameter KEY] [--reference FILE] [--out DIR]\n"
      << "                 [--set key.path=value]... [--force] [--quiet]\n"
      << "      run time against error: runs the case once per particle spacing (\"0.5 mm,0.25 mm\" or\n"
      << "      \"5e-4,2.5e-4\" in m), each as a child `sphforge run` into DIR/runs/dx_<spacing>, and writes\n"
      << "      DIR/bench.csv (spacing, particles, steps, wall time, throughput, peak RSS, every numeric\n"
      << "      metric and its relative error), bench.json and bench.png (error against wall time).\n"
      << "      --parameter: the key set to each spacing (default process.particle_spacing; a JSON\n"
      << "      pointer works too). --reference: {\"metrics\": {\"name\": value or \"value unit\"}};\n"
      << "      without it, errors are against the finest spacing that finished. DIR defaults to\n"
      << "      runs/<case>-bench. Exit 3 when every run was unstable. See docs/bench.md\n"
      << "  sphforge plugins [--json]\n"
      << "      list every plugin with its parameters (unit, default, range, doc)\n\n"
      << "exit codes: 0 done, 1 other error, 2 invalid input, 3 numerical instability\n";
}

/// The bundled default case: next to the source tree (build tree) or the install prefix.
fs::path default_case() {
  for (const fs::path& root : {fs::path(SPHFORGE_SOURCE_DIR), fs::path(SPHFORGE_INSTALL_DATA_DIR)}) {
    const fs::path candidate = root / kDefaultCase;
    if (fs::exists(candidate)) return candidate;
  }
  throw InputError(kDefaultCase, "", "the bundled default case was not found; give a case file");
}

struct Options {
  std::string command;
  std::string case_path;
  std::string out;
  std::vector<std::string> overrides;
  bool quiet = false, force = false, json = false;
  std::optional<std::string> spacing, parameter, reference;  // bench only
  std::optional<std::string> restart;                       // run only
};

Options parse(int argc, char** argv) {
  Options o;
  if (argc < 2) throw InputError("", "", "no command given (run, check, bench, plugins); see sphforge --help");
  o.command = argv[1];
  for (int k = 2; k < argc; ++k) {
    const std::string a = argv[k];
    auto value = [&](const char* name) -> std::string {
      if (k + 1 >= argc) throw InputError("", "", std::string(name) + " needs a value");
      return argv[++k];
    };
    if (a == "--out") o.out = value("--out");
    else if (a == "--set") o.overrides.push_back(value("--set"));
    else if (a.rfind("--set=", 0) == 0) o.overrides.push_back(a.substr(6));
    else if (a == "--quiet" || a == "-q") o.quiet = true;
    else if (a == "--force") o.force = true;
    else if (a == "--json") o.json = true;
    else if (a == "--spacing") o.spacing = value("--spacing");
    else if (a == "--parameter") o.parameter = value("--parameter");
    else if (a == "--reference") o.reference = value("--reference");
    else if (a == "--restart") o.restart = value("--restart");
    else if (!a.empty() && a[0] == '-') throw InputError("", "", "unknown option '" + a + "'; see sphforge --help");
    else if (o.case_path.empty()) o.case_path = a;
    else throw InputError("", "", "unexpected argument '" + a + "'");
  }
  if (o.command != "bench")
    for (const auto& [name, given] : {std::pair{"--spacing", o.spacing.has_value()},
                                      std::pair{"--parameter", o.parameter.has_value()},
                                      std::pair{"--reference", o.reference.has_value()}})
      if (given) throw InputError("", "", std::string(name) + " is an option of bench, not of " + o.command);
  if (o.restart && o.command != "run") throw InputError("", "", "--restart is an option of run, not of " + o.command);
  return o;
}

fs::path output_folder(const Options& o, const std::string& case_name) {
  return cli::choose_output_folder(o.out, o.force, fs::path("runs") / case_name);
}

int list_plugins(bool as_json) {
  PluginLoader loader;
  std::vector<std::string> problems;
  auto plugins = loader.discover(&problems);
  if (as_json) {
    json out = json::array();
    for (const LoadedPlugin* p : plugins) {
      json params = json::array();
      for (const auto& spec : p->descriptor->parameters) params.push_back(spec.describe());
      out.push_back({{"kind", to_string(p->descriptor->kind)}, {"name", p->descriptor->name},
                     {"version", p->descriptor->version}, {"doc", p->descriptor->doc},
                     {"library", p->path.string()}, {"parameters", params}});
    }
    std::cout << out.dump(2) << "\n";
  } else {
    for (PluginKind kind : {PluginKind::Process, PluginKind::Material, PluginKind::Contact, PluginKind::Controller}) {
      for (const LoadedPlugin* p : plugins) {
        if (p->descriptor->kind != kind) continue;
        std::cout << to_string(kind) << " " << p->descriptor->name << " " << p->descriptor->version << " - "
                  << p->descriptor->doc << "\n";
        for (const auto& spec : p->descriptor->parameters) {
          const json d = spec.describe();
          std::cout << "    " << spec.name;
          if (d.contains("unit") && d["unit"].is_string() && d["unit"] != "1")
            std::cout << " [" << d["unit"].get<std::string>() << "]";
          if (d.contains("default")) std::cout << " = " << d["default"].dump();
          else std::cout << " (required)";
          if (d.contains("min") || d.contains("max"))
            std::cout << " range " << (d.contains("min") ? d["min"].dump() : "-inf") << " .. "
                      << (d.contains("max") ? d["max"].dump() : "inf");
          if (d.contains("choices")) std::cout << " one of " << d["choices"].dump();
          std::cout << " - " << spec.doc << "\n";
        }
      }
    }
  }
  for (const auto& p : problems) std::cerr << "warning: " << p << "\n";
  return kExitOk;
}

int check_case(const Options& o) {
  if (o.case_path.empty()) throw InputError("", "", "check needs a case file");
  PluginLoader loader;
  const CaseDocument doc = load_case(o.case_path, o.overrides);
  Simulation sim(doc, loader);
  std::cout << "case '" << sim.settings().case_name << "' is valid: " << sim.particle_count() << " particles, "
            << sim.tools().size() << " tools\n";
  if (sim.symmetry().active())
    std::cout << "symmetry: the particles of 1/" << sim.symmetry().multiplier()
              << " of the scene are simulated, images across the cuts are ghosts (docs/theory.md section 11)\n";
  // Which thermal stepping the case runs: the two differ in cost and in when temperatures are current.
  if (sim.settings().thermal.enabled) {
    const auto& thermal = sim.settings().thermal;
    if (thermal.subcycling)
      std::cout << "thermal step: sub-cycled (docs/theory.md eq. 26b): conduction, convection and the tools' heat "
                   "once per dt_thermal = "
                << thermal.time_step_factor << " h^2 min(rho c / k) / f, the heat sources every step\n";
    else
      std::cout << "thermal step: every step, which is at most dt_thermal = " << thermal.time_step_factor
                << " h^2 min(rho c / k) / f (docs/theory.md eq. 26)\n";
  }
  std::cout << "passes:\n";
  for (const auto& pass : sim.passes()) std::cout << "  " << pass.name << "\n";
  std::cout << "fields allocated:";
  for (const auto& name : sim.fields().names()) std::cout << " " << name;
  std::cout << "\n";
  return kExitOk;
}

int run_case(const Options& o) {
  PluginLoader loader;
  const std::string path = o.case_path.empty() ? default_case().string() : o.case_path;
  const CaseDocument doc = load_case(path, o.overrides);
  // Everything the user supplied is validated (and the scene built) before a file is written.
  Simulation sim(doc, loader);
  if (o.restart) sim.restore(*o.restart);
  const fs::path out = output_folder(o, sim.settings().case_name);
  // The restarted run reads the earlier run's history.csv: it must not write over it.
  if (o.restart && fs::exists(out) && fs::equivalent(out, fs::absolute(*o.restart).parent_path()))
    throw InputError(*o.restart, "", "--out is the folder of this checkpoint; a restarted run writes a new folder");
  const ProgressMode mode = o.quiet ? ProgressMode::Quiet : ProgressMode::Auto;
  if (!o.quiet)
    std::cerr << "sphforge: " << (o.restart ? "restarting" : "running") << " '" << sim.settings().case_name << "' ("
              << sim.particle_count() << " particles, " << omp_get_max_threads() << " threads) -> " << out.string()
              << "\n";
  const Simulation::RunResult result = sim.run(out, mode);
  if (result.exit_code != 0) {
    std::cerr << "error: " << result.message << "\n"
              << "the last state is in " << (out / "particles.pvd").string() << "\n";
    return result.exit_code;
  }
  if (!o.quiet)
    std::cout << "output: " << fs::absolute(out).string() << "\n"
              << "open in ParaView: paraview " << (out / "particles.pvd").string() << " "
              << (out / "tools.pvd").string() << "\n";
  return kExitOk;
}

int bench(const Options& o) {
  if (!o.spacing) throw InputError("", "--spacing", "bench needs --spacing, e.g. --spacing \"0.5 mm,0.25 mm\"");
  cli::BenchOptions b;
  b.case_path = o.case_path.empty() ? default_case().string() : o.case_path;
  b.spacing_list = *o.spacing;
  if (o.parameter) b.parameter = *o.parameter;
  if (o.reference) b.reference = *o.reference;
  b.out = o.out;
  b.overrides = o.overrides;
  b.force = o.force;
  b.quiet = o.quiet;
  return cli::run_bench(b);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc >= 2 && (!std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "help"))) {
      usage(std::cout);
      return kExitOk;
    }
    if (argc >= 2 && !std::strcmp(argv[1], "--version")) {
      std::cout << "sphforge " << kCoreVersion << " (plugin ABI " << kPluginAbiVersion << ")\n";
      return kExitOk;
    }
    // `sphforge` alone and `sphforge run` run the default case.
    Options o = argc < 2 ? Options{"run"} : parse(argc, argv);
    if (o.command == "run") return run_case(o);
    if (o.command == "check") return check_case(o);
    if (o.command == "bench") return bench(o);
    if (o.command == "plugins") return list_plugins(o.json);
    throw InputError("", "", "unknown command '" + o.command + "' (expected run, check, bench or plugins)");
  } catch (const InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitInput;
  } catch (const InstabilityError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitUnstable;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitOther;
  }
}
