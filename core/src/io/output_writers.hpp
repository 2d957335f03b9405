// Writers of the output contract (DESIGN.md "Outputs"): VTK XML series for ParaView,
// history.csv and summary.json. Internal to the core (not plugin API).
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/particle_array.hpp"
#include "sphforge/fields.hpp"
#include "sphforge/tool.hpp"

namespace sphforge::io {

// Errors: a file or directory that cannot be created or written -> std::runtime_error naming
// the path; a caller mistake (missing "position" field, row of the wrong length) ->
// std::logic_error.

/// particles.pvd + particles_NNNNNN.vtu (binary, appended, vtkXMLUnstructuredGridWriter).
/// Every allocated field with FieldInfo::output is written as point data under its own name;
/// points are the "position" field; cells are VTK_VERTEX so ParaView shows them directly.
/// The .pvd collection is rewritten after each frame so it is valid even if a run stops early.
/// Each .vtu also carries field data "TimeValue" (the time) and "units" ("name=unit" strings).
class ParticleSeriesWriter {
 public:
  /// Creates `directory` if needed.
  explicit ParticleSeriesWriter(std::filesystem::path directory);
  /// Writes frame number `frame` at simulated time `time_s` for particles [0, count).
  /// Writing a frame number again replaces that frame (file and .pvd entry).
  /// `extra`: arrays held outside the registry, written after the fields (`count` particles each).
  void write(int frame, double time_s, const FieldRegistry& fields, std::size_t count,
             const std::vector<ParticleArray>& extra = {});
  /// Restart (docs/checkpoints.md): the frames of an earlier run's `particles.pvd` up to
  /// `up_to_time_s` open this series (by their path relative to this folder), so that the new
  /// particles.pvd shows the whole run. Returns how many; 0 when the file cannot be read.
  std::size_t continue_series(const std::filesystem::path& earlier_pvd, double up_to_time_s);

 private:
  std::filesystem::path directory_;
  std::vector<std::pair<double, std::string>> frames_;
};

/// tools.pvd + tools_NNNNNN_<toolname>.vtp: each rigid tool's surface (RigidTool::surface) in its
/// current pose, one part per tool. Surfaces of revolution: the profile revolved about z in
/// `segments` angular steps, points numbered profile-major (profile point j at angle step k is
/// j*segments + k; fillet arcs subdivided), quads wound so that their normal points to the
/// workpiece side. Planes: a square of two triangles; STL meshes: their triangles.
/// Characters of a tool name other than [A-Za-z0-9_.-] become '_' in the file name.
class ToolSeriesWriter {
 public:
  /// Creates `directory` if needed; `segments` must be >= 3 (std::invalid_argument otherwise).
  explicit ToolSeriesWriter(std::filesystem::path directory, int segments = 48);
  void write(int frame, double time_s, const std::vector<RigidTool>& tools);
  /// Restart: as ParticleSeriesWriter::continue_series, for `tools.pvd`.
  std::size_t continue_series(const std::filesystem::path& earlier_pvd, double up_to_time_s);

 private:
  std::filesystem::path directory_;
  int segments_;
  struct Entry { double time; int part; std::string file; };
  std::vector<Entry> entries_;
};

/// history.csv: header once, then one row per call. Full precision (%.17g).
/// The file is truncated on construction; its directory must exist.
class HistoryWriter {
 public:
  HistoryWriter(const std::filesystem::path& file, const std::vector<std::string>& columns);
  /// `row.size()` must equal the number of columns (std::logic_error otherwise).
  void append(const std::vector<double>& row);
  void flush();

 private:
  std::filesystem::path path_;
  std::ofstream out_;
  std::size_t columns_;
};

/// Restart (docs/checkpoints.md): appends to `out` the rows of an earlier run's history.csv
/// `file` up to and including time `up_to_time_s`, when its header equals `columns`. Returns the
/// number of rows copied: 0 when the file is missing or has other columns (the new file then
/// starts at the restart).
std::size_t copy_history_rows(const std::filesystem::path& file, const std::vector<std::string>& columns,
                              double up_to_time_s, HistoryWriter& out);

/// Writes summary.json (pretty-printed, atomically via a temporary file and rename).
void write_summary(const std::filesystem::path& file, const nlohmann::json& summary);

/// The datasets (time, part, file as written) of a .pvd collection, read with VTK's XML parser;
/// empty when the file is missing or not a collection.
std::vector<std::tuple<double, int, std::string>> read_pvd(const std::filesystem::path& file);

/// Writes the small XML collection file of a .pvd series. VTK has no writer for the plain
/// time-series collection format that ParaView reads, so this one file is written by hand.
/// Each tuple is (time, part, file name relative to the .pvd). Replaced atomically (tmp + rename).
void write_pvd(const std::filesystem::path& file,
               const std::vector<std::tuple<double, int, std::string>>& datasets);

}  // namespace sphforge::io
