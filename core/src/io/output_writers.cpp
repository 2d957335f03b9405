#include "io/output_writers.hpp"

#include <cstdlib>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <system_error>

#include <vtkAOSDataArrayTemplate.h>
#include <vtkCellArray.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>

namespace sphforge::io {

namespace fs = std::filesystem;

namespace {

void ensure_directory(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  // create_directories reports no error for an existing directory, but does for an existing
  // regular file of that name only on some implementations; check explicitly.
  if (ec || !fs::is_directory(dir))
    throw std::runtime_error("cannot create output directory '" + dir.string() + "'" +
                             (ec ? ": " + ec.message() : std::string()));
}

/// Atomically replaces `file` with `tmp` (same directory, so rename is atomic on POSIX):
/// a reader (ParaView polling the .pvd, a script reading summary.json) never sees half a file.
void replace_file(const fs::path& tmp, const fs::path& file) {
  std::error_code ec;
  fs::rename(tmp, file, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error("cannot write '" + file.string() + "': rename failed");
  }
}

fs::path tmp_path(const fs::path& file) {
  fs::path tmp = file;
  tmp += ".tmp";
  return tmp;
}

std::string xml_escape(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (const char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

/// Tool names come from the case file; keep them from escaping the directory or breaking
/// the file name on any platform.
std::string file_safe(const std::string& name) {
  std::string out = name.empty() ? std::string("tool") : name;
  for (char& c : out) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-' || c == '.';
    if (!ok) c = '_';
  }
  return out;
}

std::string frame_name(const char* prefix, int frame, const char* suffix) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%06d", frame);
  return std::string(prefix) + buf + suffix;
}

/// One-tuple "TimeValue" field data: the name ParaView uses for the time of a single dataset,
/// so a .vtu opened on its own (without the .pvd) still shows its time.
void add_time(vtkFieldData* fd, double time_s) {
  vtkNew<vtkDoubleArray> t;
  t->SetName("TimeValue");
  t->SetNumberOfTuples(1);
  t->SetValue(0, time_s);
  fd->AddArray(t);
}

/// Shared writer settings: binary appended data (raw, not base64), zlib-compressed (the VTK
/// default), 64-bit block headers so arrays over 4 GiB stay representable.
template <typename Writer>
void configure(Writer* w, const fs::path& file) {
  w->SetFileName(file.string().c_str());
  w->SetDataModeToAppended();
  w->EncodeAppendedDataOff();
  w->SetHeaderTypeToUInt64();
  w->SetCompressorTypeToZLib();
}

template <typename Writer>
void run_writer(Writer* w, const fs::path& file) {
  if (w->Write() != 1 || w->GetErrorCode() != 0)
    throw std::runtime_error("cannot write '" + file.string() + "'");
}

/// Component names for ParaView: without them a 9-component array shows as 0..8.
/// Symmetric tensors use VTK's order, which is also the registry's (xx yy zz xy yz xz);
/// full tensors are row-major (L_ab at a*3 + b).
void name_components(vtkDataArray* a, int comps) {
  static constexpr const char* sym[6] = {"XX", "YY", "ZZ", "XY", "YZ", "XZ"};
  static constexpr const char* full[9] = {"XX", "XY", "XZ", "YX", "YY", "YZ", "ZX", "ZY", "ZZ"};
  if (comps == 6)
    for (int c = 0; c < 6; ++c) a->SetComponentName(c, sym[c]);
  else if (comps == 9)
    for (int c = 0; c < 9; ++c) a->SetComponentName(c, full[c]);
}

/// Wraps registry memory in a VTK array without copying (`save = 1`: VTK never frees it).
/// The const_cast is safe because the array lives only until the writer, which only reads,
/// has finished. vtkAOSDataArrayTemplate<std::int64_t> is used rather than vtkTypeInt64Array
/// because the latter is `long long`, not the registry's `long`; both are "Int64" on disk.
template <typename T>
vtkSmartPointer<vtkAOSDataArrayTemplate<T>> wrap(const T* data, std::size_t count, int comps,
                                                 const std::string& name) {
  auto a = vtkSmartPointer<vtkAOSDataArrayTemplate<T>>::New();
  a->SetName(name.c_str());
  a->SetNumberOfComponents(comps);
  a->SetArray(const_cast<T*>(data), static_cast<vtkIdType>(count) * comps, /*save=*/1);
  return a;
}

}  // namespace

// ----------------------------------------------------------------------------------------------

void write_pvd(const fs::path& file,
               const std::vector<std::tuple<double, int, std::string>>& datasets) {
  const fs::path tmp = tmp_path(file);
  {
    std::FILE* f = std::fopen(tmp.c_str(), "w");
    if (!f) throw std::runtime_error("cannot create '" + file.string() + "'");
    std::fputs("<?xml version=\"1.0\"?>\n"
               "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
               "  <Collection>\n",
               f);
    for (const auto& [time, part, name] : datasets)
      std::fprintf(f, "    <DataSet timestep=\"%.17g\" group=\"\" part=\"%d\" file=\"%s\"/>\n", time,
                   part, xml_escape(name).c_str());
    std::fputs("  </Collection>\n</VTKFile>\n", f);
    const bool ok = !std::ferror(f);
    if (std::fclose(f) != 0 || !ok) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw std::runtime_error("cannot write '" + file.string() + "'");
    }
  }
  replace_file(tmp, file);
}

// ----------------------------------------------------------------------------------------------

ParticleSeriesWriter::ParticleSeriesWriter(fs::path directory) : directory_(std::move(directory)) {
  ensure_directory(directory_);
}

void ParticleSeriesWriter::write(int frame, double time_s, const FieldRegistry& fields,
                                 std::size_t count, const std::vector<ParticleArray>& extra) {
  if (count > fields.size())
    throw std::logic_error("ParticleSeriesWriter: " + std::to_string(count) +
                           " particles requested, registry holds " +
                           std::to_string(fields.size()));
  if (fields.declared(field::position) && fields.info(field::position).components != 3)
    throw std::logic_error("ParticleSeriesWriter: field 'position' must have 3 components");
  const double* position = fields.f64(field::position);  // throws if absent

  vtkNew<vtkUnstructuredGrid> grid;
  vtkNew<vtkPoints> points;
  points->SetData(wrap(position, count, 3, field::position));
  grid->SetPoints(points);

  // One vertex per particle: connectivity 0..n-1, offsets implied by the fixed cell size.
  vtkNew<vtkIdTypeArray> connectivity;
  connectivity->SetNumberOfTuples(static_cast<vtkIdType>(count));
  std::iota(connectivity->GetPointer(0), connectivity->GetPointer(0) + count, vtkIdType{0});
  vtkNew<vtkCellArray> cells;
  cells->SetData(1, connectivity);
  grid->SetCells(VTK_VERTEX, cells);

  vtkNew<vtkStringArray> units;
  units->SetName("units");
  units->InsertNextValue(std::string(field::position) + "=" + fields.info(field::position).unit);
  vtkPointData* pd = grid->GetPointData();
  for (const std::string& name : fields.names()) {
    const FieldInfo& info = fields.info(name);
    if (name == field::position || !info.output || !fields.allocated(name)) continue;
    vtkSmartPointer<vtkDataArray> a;
    if (info.type == FieldType::Float64)
      a = wrap(fields.f64(name), count, info.components, name);
    else
      a = wrap(fields.i64(name), count, info.components, name);
    name_components(a, info.components);
    pd->AddArray(a);
    units->InsertNextValue(name + "=" + info.unit);
  }
  for (const ParticleArray& e : extra) {
    if (e.values.size() != count * static_cast<std::size_t>(e.components))
      throw std::logic_error("ParticleSeriesWriter: array '" + e.name + "' does not hold " +
                             std::to_string(count) + " particles");
    vtkSmartPointer<vtkDataArray> a = wrap(e.values.data(), count, e.components, e.name);
    name_components(a, e.components);
    pd->AddArray(a);
    units->InsertNextValue(e.name + "=" + e.unit);
  }
  grid->GetFieldData()->AddArray(units);
  add_time(grid->GetFieldData(), time_s);

  const std::string file = frame_name("particles_", frame, ".vtu");
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  configure(writer.Get(), directory_ / file);
  writer->SetInputData(grid);
  run_writer(writer.Get(), directory_ / file);

  // Replace the entry of a rewritten frame (frame numbers, hence file names, are unique).
  auto it = std::find_if(frames_.begin(), frames_.end(),
                         [&](const auto& e) { return e.second == file; });
  if (it != frames_.end())
    it->first = time_s;
  else
    frames_.emplace_back(time_s, file);

  std::vector<std::tuple<double, int, std::string>> datasets;
  datasets.reserve(frames_.size());
  for (const auto& [t, f] : frames_) datasets.emplace_back(t, 0, f);
  write_pvd(directory_ / "particles.pvd", datasets);
}

namespace {
/// The earlier run's datasets up to `up_to_time_s`, their files relative to `directory`.
std::vector<std::tuple<double, int, std::string>> earlier_datasets(const fs::path& earlier_pvd, double up_to_time_s,
                                                                   const fs::path& directory) {
  std::vector<std::tuple<double, int, std::string>> out;
  const fs::path from = fs::weakly_canonical(earlier_pvd.parent_path());
  const fs::path to = fs::weakly_canonical(directory);
  // Normalised first: after a chain of restarts the earlier .pvd already lists "../a/..." paths.
  for (auto& [time, part, file] : read_pvd(earlier_pvd))
    if (time <= up_to_time_s)
      out.emplace_back(time, part, (from / file).lexically_normal().lexically_relative(to).generic_string());
  return out;
}
}  // namespace

std::size_t ParticleSeriesWriter::continue_series(const fs::path& earlier_pvd, double up_to_time_s) {
  std::size_t added = 0;
  for (const auto& [time, part, file] : earlier_datasets(earlier_pvd, up_to_time_s, directory_)) {
    frames_.emplace_back(time, file);
    ++added;
  }
  return added;
}

// ----------------------------------------------------------------------------------------------

ToolSeriesWriter::ToolSeriesWriter(fs::path directory, int segments)
    : directory_(std::move(directory)), segments_(segments) {
  if (segments_ < 3)
    throw std::invalid_argument("ToolSeriesWriter: segments must be >= 3, got " +
                                std::to_string(segments_));
  ensure_directory(directory_);
}

void ToolSeriesWriter::write(int frame, double time_s, const std::vector<RigidTool>& tools) {
  std::vector<std::string> written;  // file names of this frame, to disambiguate clashes
  written.reserve(tools.size());

  for (std::size_t part = 0; part < tools.size(); ++part) {
    const RigidTool& tool = tools[part];
    // Every shape gives its surface in the current pose (planes as a finite square, revolved
    // profiles as quads with fillet arcs subdivided, meshes as their triangles).
    const SurfaceMesh mesh = tool.surface(segments_);
    vtkNew<vtkDoubleArray> xyz;
    xyz->SetNumberOfComponents(3);
    xyz->SetNumberOfTuples(static_cast<vtkIdType>(mesh.points.size()));
    double* p = xyz->GetPointer(0);
    for (const auto& q : mesh.points) {
      *p++ = q.x();
      *p++ = q.y();
      *p++ = q.z();
    }
    vtkNew<vtkPoints> points;
    points->SetData(xyz);
    vtkNew<vtkIdTypeArray> offsets, connectivity;
    offsets->SetNumberOfTuples(static_cast<vtkIdType>(mesh.offsets.size()));
    for (std::size_t k = 0; k < mesh.offsets.size(); ++k) offsets->SetValue(static_cast<vtkIdType>(k), mesh.offsets[k]);
    connectivity->SetNumberOfTuples(static_cast<vtkIdType>(mesh.connectivity.size()));
    for (std::size_t k = 0; k < mesh.connectivity.size(); ++k)
      connectivity->SetValue(static_cast<vtkIdType>(k), mesh.connectivity[k]);
    vtkNew<vtkCellArray> quads;
    quads->SetData(offsets, connectivity);

    vtkNew<vtkPolyData> poly;
    poly->SetPoints(points);
    poly->SetPolys(quads);
    add_time(poly->GetFieldData(), time_s);

    std::string base = "tools_" + frame_name("", frame, "_") + file_safe(tool.name());
    // Two names that differ only in replaced characters must not overwrite each other.
    if (std::find(written.begin(), written.end(), base + ".vtp") != written.end())
      base += "_" + std::to_string(part);
    const std::string file = base + ".vtp";
    written.push_back(file);

    vtkNew<vtkXMLPolyDataWriter> writer;
    configure(writer.Get(), directory_ / file);
    writer->SetInputData(poly);
    run_writer(writer.Get(), directory_ / file);

    const int part_index = static_cast<int>(part);
    auto it = std::find_if(entries_.begin(), entries_.end(),
                           [&](const Entry& e) { return e.file == file; });
    if (it != entries_.end())
      *it = Entry{time_s, part_index, file};
    else
      entries_.push_back(Entry{time_s, part_index, file});
  }

  std::vector<std::tuple<double, int, std::string>> datasets;
  datasets.reserve(entries_.size());
  for (const Entry& e : entries_) datasets.emplace_back(e.time, e.part, e.file);
  write_pvd(directory_ / "tools.pvd", datasets);
}

// ----------------------------------------------------------------------------------------------

HistoryWriter::HistoryWriter(const fs::path& file, const std::vector<std::string>& columns)
    : path_(file), out_(file, std::ios::out | std::ios::trunc), columns_(columns.size()) {
  if (!out_) throw std::runtime_error("cannot create '" + file.string() + "'");
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (i) out_ << ',';
    // RFC 4180 quoting, only where a name would otherwise split or break the header.
    const std::string& c = columns[i];
    if (c.find_first_of(",\"\n\r") == std::string::npos) {
      out_ << c;
    } else {
      out_ << '"';
      for (const char ch : c) out_ << (ch == '"' ? "\"\"" : std::string(1, ch));
      out_ << '"';
    }
  }
  out_ << '\n';
  if (!out_) throw std::runtime_error("cannot write '" + file.string() + "'");
}

void HistoryWriter::append(const std::vector<double>& row) {
  if (row.size() != columns_)
    throw std::logic_error("history row has " + std::to_string(row.size()) + " values for " +
                           std::to_string(columns_) + " columns");
  char buf[32];  // "%.17g" needs at most 24 characters plus the separator
  for (std::size_t i = 0; i < row.size(); ++i) {
    const int n = std::snprintf(buf, sizeof buf, i ? ",%.17g" : "%.17g", row[i]);
    out_.write(buf, n);
  }
  out_.put('\n');
  if (!out_) throw std::runtime_error("cannot write '" + path_.string() + "'");
}

void HistoryWriter::flush() {
  out_.flush();
  if (!out_) throw std::runtime_error("cannot write '" + path_.string() + "'");
}

std::size_t copy_history_rows(const fs::path& file, const std::vector<std::string>& columns, double up_to_time_s,
                              HistoryWriter& out) {
  std::ifstream in(file);
  if (!in) return 0;
  std::string line, expected;
  for (std::size_t i = 0; i < columns.size(); ++i) expected += (i ? "," : "") + columns[i];
  // A file saved by another tool may end its lines with CR LF (Python's csv module, spreadsheets).
  auto next_line = [&] {
    if (!std::getline(in, line)) return false;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  };
  if (!next_line() || line != expected) return 0;
  std::size_t copied = 0;
  std::vector<double> row;
  while (next_line()) {
    row.clear();
    const char* p = line.c_str();
    char* end = nullptr;
    while (*p) {
      row.push_back(std::strtod(p, &end));
      if (end == p) break;  // not a number: a torn last line of a killed run
      p = *end == ',' ? end + 1 : end;
    }
    // Rows written after the checkpoint (before the run was stopped) belong to the new run.
    if (row.size() != columns.size() || row[0] > up_to_time_s) break;
    out.append(row);
    ++copied;
  }
  return copied;
}

std::size_t ToolSeriesWriter::continue_series(const fs::path& earlier_pvd, double up_to_time_s) {
  std::size_t added = 0;
  for (const auto& [time, part, file] : earlier_datasets(earlier_pvd, up_to_time_s, directory_)) {
    entries_.push_back(Entry{time, part, file});
    ++added;
  }
  return added;
}

std::vector<std::tuple<double, int, std::string>> read_pvd(const fs::path& file) {
  std::vector<std::tuple<double, int, std::string>> out;
  if (!fs::is_regular_file(file)) return out;
  vtkNew<vtkXMLDataParser> parser;
  parser->SetFileName(file.string().c_str());
  if (parser->Parse() != 1) return out;
  vtkXMLDataElement* root = parser->GetRootElement();
  if (!root || std::string(root->GetName()) != "VTKFile" || root->GetNumberOfNestedElements() < 1) return out;
  vtkXMLDataElement* collection = root->GetNestedElement(0);
  for (int k = 0; k < collection->GetNumberOfNestedElements(); ++k) {
    vtkXMLDataElement* e = collection->GetNestedElement(k);
    const char* time = e->GetAttribute("timestep");
    const char* name = e->GetAttribute("file");
    if (!time || !name) continue;
    int part = 0;
    e->GetScalarAttribute("part", part);
    out.emplace_back(std::strtod(time, nullptr), part, name);
  }
  return out;
}

// ----------------------------------------------------------------------------------------------

void write_summary(const fs::path& file, const nlohmann::json& summary) {
  const fs::path tmp = tmp_path(file);
  {
    std::ofstream out(tmp, std::ios::out | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot create '" + file.string() + "'");
    out << summary.dump(2) << '\n';
    out.close();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw std::runtime_error("cannot write '" + file.string() + "'");
    }
  }
  replace_file(tmp, file);
}

}  // namespace sphforge::io
