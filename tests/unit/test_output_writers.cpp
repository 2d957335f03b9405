// Output writers: VTK series read back with VTK's own readers, .pvd parsed as XML,
// history.csv and summary.json compared with exact expected text/values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <vtkCellArray.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>
#include <vtkXMLGenericDataObjectReader.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "io/output_writers.hpp"

using namespace sphforge;
namespace fs = std::filesystem;

namespace {

class OutputWriters : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("sphforge_out_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    if (!HasFailure()) fs::remove_all(dir_, ec);  // keep the files of a failed test to look at
  }
  fs::path dir_;
};

std::string slurp(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// A path whose parent is a regular file: no one, not even root, can create it.
fs::path uncreatable(const fs::path& dir, const std::string& leaf) {
  const fs::path blocker = dir / "blocker";
  std::ofstream(blocker) << "x";
  return blocker / leaf;
}

template <typename Fn>
void expect_runtime_error_naming(Fn&& fn, const std::string& needle) {
  try {
    fn();
    ADD_FAILURE() << "expected std::runtime_error mentioning '" << needle << "'";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

struct PvdEntry {
  std::string timestep, part, file;
};

/// Parses a .pvd with VTK's XML parser (so malformed XML fails) and returns its DataSets.
std::vector<PvdEntry> read_pvd(const fs::path& file) {
  vtkNew<vtkXMLDataParser> parser;
  parser->SetFileName(file.string().c_str());
  EXPECT_EQ(parser->Parse(), 1) << file;
  vtkXMLDataElement* root = parser->GetRootElement();
  std::vector<PvdEntry> out;
  if (!root) return out;
  EXPECT_STREQ(root->GetName(), "VTKFile");
  EXPECT_STREQ(root->GetAttribute("type"), "Collection");
  EXPECT_EQ(root->GetNumberOfNestedElements(), 1);
  vtkXMLDataElement* coll = root->GetNestedElement(0);
  EXPECT_STREQ(coll->GetName(), "Collection");
  for (int i = 0; i < coll->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* ds = coll->GetNestedElement(i);
    EXPECT_STREQ(ds->GetName(), "DataSet");
    out.push_back({ds->GetAttribute("timestep"), ds->GetAttribute("part"), ds->GetAttribute("file")});
  }
  return out;
}

constexpr std::size_t kParticles = 10;

/// position (0.1 i, 0.2 i, 0.3 i), velocity (i, -i, 0.5), pressure 100 + i + shift,
/// deviatoric_stress[c] = 10 i + c, id 1000 + i, and a non-output scratch field.
void fill(FieldRegistry& reg, double pressure_shift) {
  double* x = reg.f64(field::position);
  double* v = reg.f64(field::velocity);
  double* p = reg.f64(field::pressure);
  double* s = reg.f64(field::deviatoric_stress);
  std::int64_t* id = reg.i64(field::id);
  for (std::size_t i = 0; i < kParticles; ++i) {
    const double d = static_cast<double>(i);
    x[3 * i + 0] = 0.1 * d;
    x[3 * i + 1] = 0.2 * d;
    x[3 * i + 2] = 0.3 * d;
    v[3 * i + 0] = d;
    v[3 * i + 1] = -d;
    v[3 * i + 2] = 0.5;
    p[i] = 100.0 + d + pressure_shift;
    for (int c = 0; c < 6; ++c) s[6 * i + c] = 10.0 * d + c;
    id[i] = 1000 + static_cast<std::int64_t>(i);
  }
}

FieldRegistry make_registry() {
  FieldRegistry reg;
  reg.declare({field::position, 3, "m", FieldType::Float64, true}, "test");
  reg.declare({field::velocity, 3, "m/s", FieldType::Float64, true}, "test");
  reg.declare({field::pressure, 1, "Pa", FieldType::Float64, true}, "test");
  reg.declare({field::deviatoric_stress, 6, "Pa", FieldType::Float64, true}, "test");
  reg.declare({field::id, 1, "1", FieldType::Int64, true}, "test");
  reg.declare({"scratch", 1, "1", FieldType::Float64, false}, "test");
  reg.allocate(kParticles);
  return reg;
}

vtkSmartPointer<vtkUnstructuredGrid> read_vtu(const fs::path& file) {
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(file.string().c_str());
  reader->Update();
  EXPECT_EQ(reader->GetErrorCode(), 0) << file;
  return vtkSmartPointer<vtkUnstructuredGrid>(reader->GetOutput());
}

}  // namespace

TEST_F(OutputWriters, ParticleFramesReadBackWithVtk) {
  FieldRegistry reg = make_registry();
  io::ParticleSeriesWriter writer(dir_);
  fill(reg, 0.0);
  writer.write(0, 0.0, reg, kParticles);
  fill(reg, 50.0);
  const double t1 = 1.0 / 3.0;
  writer.write(1, t1, reg, kParticles);

  // Frame 1: geometry, topology, arrays and values.
  auto grid = read_vtu(dir_ / "particles_000001.vtu");
  ASSERT_EQ(grid->GetNumberOfPoints(), 10);
  ASSERT_EQ(grid->GetNumberOfCells(), 10);
  EXPECT_EQ(grid->GetCellType(7), VTK_VERTEX);
  EXPECT_EQ(grid->GetCell(7)->GetPointId(0), 7);
  double pt[3];
  grid->GetPoint(7, pt);
  EXPECT_DOUBLE_EQ(pt[0], 0.7);
  EXPECT_DOUBLE_EQ(pt[1], 0.2 * 7);
  EXPECT_DOUBLE_EQ(pt[2], 0.3 * 7);

  vtkPointData* pd = grid->GetPointData();
  EXPECT_EQ(pd->GetNumberOfArrays(), 4);  // velocity, pressure, deviatoric_stress, id
  EXPECT_EQ(pd->GetArray("position"), nullptr);  // positions are the points only
  EXPECT_EQ(pd->GetArray("scratch"), nullptr);   // output = false
  vtkDataArray* vel = pd->GetArray("velocity");
  vtkDataArray* pres = pd->GetArray("pressure");
  vtkDataArray* dev = pd->GetArray("deviatoric_stress");
  vtkDataArray* id = pd->GetArray("id");
  ASSERT_TRUE(vel && pres && dev && id);
  EXPECT_EQ(vel->GetNumberOfComponents(), 3);
  EXPECT_EQ(pres->GetNumberOfComponents(), 1);
  EXPECT_EQ(dev->GetNumberOfComponents(), 6);
  EXPECT_EQ(id->GetNumberOfComponents(), 1);
  EXPECT_EQ(vel->GetComponent(4, 1), -4.0);
  EXPECT_EQ(pres->GetComponent(3, 0), 153.0);  // frame 1 has the shifted pressure
  EXPECT_EQ(dev->GetComponent(5, 4), 54.0);    // particle 5, YZ
  EXPECT_STREQ(dev->GetComponentName(3), "XY");
  EXPECT_TRUE(id->GetDataType() == VTK_TYPE_INT64 || id->GetDataType() == VTK_LONG);
  EXPECT_EQ(id->GetDataTypeSize(), 8);
  EXPECT_EQ(id->GetVariantValue(9).ToTypeInt64(), 1009);

  vtkDataArray* time = grid->GetFieldData()->GetArray("TimeValue");
  ASSERT_NE(time, nullptr);
  EXPECT_EQ(time->GetComponent(0, 0), t1);
  auto* units = vtkStringArray::SafeDownCast(grid->GetFieldData()->GetAbstractArray("units"));
  ASSERT_NE(units, nullptr);
  EXPECT_NE(units->LookupValue("pressure=Pa"), -1);
  EXPECT_NE(units->LookupValue("position=m"), -1);

  // Frame 0 kept its own data.
  auto grid0 = read_vtu(dir_ / "particles_000000.vtu");
  ASSERT_EQ(grid0->GetNumberOfPoints(), 10);
  EXPECT_EQ(grid0->GetPointData()->GetArray("pressure")->GetComponent(3, 0), 103.0);

  // The collection lists both frames, relative names, full-precision times, and every listed
  // file opens with the generic reader ParaView's .pvd reader delegates to.
  const auto entries = read_pvd(dir_ / "particles.pvd");
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[0].file, "particles_000000.vtu");
  EXPECT_EQ(entries[1].file, "particles_000001.vtu");
  EXPECT_EQ(entries[0].timestep, "0");
  EXPECT_EQ(entries[1].timestep, "0.33333333333333331");
  EXPECT_EQ(std::stod(entries[1].timestep), t1);
  for (const auto& e : entries) {
    vtkNew<vtkXMLGenericDataObjectReader> generic;
    generic->SetFileName((dir_ / e.file).string().c_str());
    generic->Update();
    auto* ug = vtkUnstructuredGrid::SafeDownCast(generic->GetOutput());
    ASSERT_NE(ug, nullptr) << e.file;
    EXPECT_EQ(ug->GetNumberOfPoints(), 10);
  }
}

// Arrays held outside the registry (the contact pass's friction memory, expanded per particle)
// are written after the fields like one, with their unit; one of the wrong length is refused.
TEST_F(OutputWriters, ParticleFramesCarryExtraArrays) {
  FieldRegistry reg = make_registry();
  fill(reg, 0.0);
  io::ParticleSeriesWriter writer(dir_);
  io::ParticleArray extra{"friction_history_die", 3, "N", std::vector<double>(3 * kParticles, 0.0)};
  extra.values[3 * 6 + 2] = -2.5;
  writer.write(0, 0.0, reg, kParticles, {extra});
  auto grid = read_vtu(dir_ / "particles_000000.vtu");
  vtkPointData* pd = grid->GetPointData();
  EXPECT_EQ(pd->GetNumberOfArrays(), 5);  // the four fields and the extra array
  vtkDataArray* h = pd->GetArray("friction_history_die");
  ASSERT_NE(h, nullptr);
  EXPECT_EQ(h->GetNumberOfComponents(), 3);
  EXPECT_EQ(h->GetComponent(6, 2), -2.5);
  EXPECT_EQ(h->GetComponent(5, 2), 0.0);
  auto* units = vtkStringArray::SafeDownCast(grid->GetFieldData()->GetAbstractArray("units"));
  ASSERT_NE(units, nullptr);
  EXPECT_NE(units->LookupValue("friction_history_die=N"), -1);
  extra.values.pop_back();
  EXPECT_THROW(writer.write(1, 1.0, reg, kParticles, {extra}), std::logic_error);
}

TEST_F(OutputWriters, ParticleSubsetRewriteAndEmptyFrame) {
  FieldRegistry reg = make_registry();
  fill(reg, 0.0);
  io::ParticleSeriesWriter writer(dir_ / "sub" / "dir");  // created on demand
  writer.write(3, 0.5, reg, 4);
  EXPECT_EQ(read_vtu(dir_ / "sub/dir/particles_000003.vtu")->GetNumberOfPoints(), 4);
  writer.write(3, 0.75, reg, 6);  // same frame again: replaced, not listed twice
  EXPECT_EQ(read_vtu(dir_ / "sub/dir/particles_000003.vtu")->GetNumberOfPoints(), 6);
  writer.write(4, 1.0, reg, 0);
  EXPECT_EQ(read_vtu(dir_ / "sub/dir/particles_000004.vtu")->GetNumberOfPoints(), 0);

  const auto entries = read_pvd(dir_ / "sub/dir/particles.pvd");
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[0].timestep, "0.75");
  EXPECT_EQ(entries[1].file, "particles_000004.vtu");
}

TEST_F(OutputWriters, ParticleWriterErrors) {
  FieldRegistry no_position;
  no_position.declare({field::pressure, 1, "Pa", FieldType::Float64, true}, "test");
  no_position.allocate(3);
  io::ParticleSeriesWriter writer(dir_);
  EXPECT_THROW(writer.write(0, 0.0, no_position, 3), std::logic_error);

  FieldRegistry reg = make_registry();
  EXPECT_THROW(writer.write(0, 0.0, reg, kParticles + 1), std::logic_error);

  const fs::path bad = uncreatable(dir_, "out");
  expect_runtime_error_naming([&] { io::ParticleSeriesWriter w(bad); }, bad.string());

  // The directory vanishes after construction: VTK's writer fails, reported with the path.
  fill(reg, 0.0);
  io::ParticleSeriesWriter late(dir_ / "gone");
  fs::remove_all(dir_ / "gone");
  std::ofstream(dir_ / "gone") << "x";
  vtkObject::GlobalWarningDisplayOff();  // VTK's own message on stderr is expected here
  expect_runtime_error_naming([&] { late.write(0, 0.0, reg, kParticles); }, "particles_000000.vtu");
  vtkObject::GlobalWarningDisplayOn();
}

TEST_F(OutputWriters, ToolSurfaceOfRevolution) {
  // Barrel wall walked upwards, then the top face inwards to the axis.
  std::vector<RigidTool> tools;
  tools.emplace_back("die", std::vector<Eigen::Vector2d>{{0.01, 0.0}, {0.01, 0.02}, {0.0, 0.02}});
  tools.emplace_back("ram/top", std::vector<Eigen::Vector2d>{{0.005, 0.03}, {0.0, 0.03}});
  tools[0].axial_offset_m = 0.5;
  tools[0].angle_rad = std::numbers::pi / 2;

  const int segments = 8;
  io::ToolSeriesWriter writer(dir_, segments);
  writer.write(0, 0.0, tools);
  tools[0].axial_offset_m = 0.25;
  writer.write(1, 0.125, tools);

  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName((dir_ / "tools_000001_die.vtp").string().c_str());
  reader->Update();
  vtkPolyData* poly = reader->GetOutput();
  ASSERT_EQ(poly->GetNumberOfPoints(), 3 * segments);
  ASSERT_EQ(poly->GetNumberOfPolys(), 2 * segments);

  // Point j*segments + k is profile point j at angle angle_rad + 2 pi k / segments.
  double p[3];
  poly->GetPoint(0, p);  // (r=0.01, z=0) at 90 degrees, shifted by 0.25
  EXPECT_NEAR(p[0], 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(p[1], 0.01);
  EXPECT_DOUBLE_EQ(p[2], 0.25);
  poly->GetPoint(1 * segments + 2, p);  // (0.01, 0.02) at 90 + 90 degrees
  EXPECT_DOUBLE_EQ(p[0], -0.01);
  EXPECT_NEAR(p[1], 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(p[2], 0.27);
  poly->GetPoint(2 * segments + 5, p);  // on the axis
  EXPECT_NEAR(std::hypot(p[0], p[1]), 0.0, 1e-15);

  // The first wall quad faces the workpiece, i.e. inwards (-r) for a barrel walked upwards.
  vtkIdType npts;
  const vtkIdType* ids;
  poly->GetPolys()->GetCellAtId(0, npts, ids);
  ASSERT_EQ(npts, 4);
  double a[3], b[3], d[3];
  poly->GetPoint(ids[0], a);
  poly->GetPoint(ids[1], b);
  poly->GetPoint(ids[3], d);
  const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double e2[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
  const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                       e1[0] * e2[1] - e1[1] * e2[0]};
  EXPECT_LT(n[0] * a[0] + n[1] * a[1], 0.0);

  // The second tool: 2 points x 8, name made file-safe.
  vtkNew<vtkXMLPolyDataReader> reader2;
  reader2->SetFileName((dir_ / "tools_000000_ram_top.vtp").string().c_str());
  reader2->Update();
  EXPECT_EQ(reader2->GetOutput()->GetNumberOfPoints(), 2 * segments);

  const auto entries = read_pvd(dir_ / "tools.pvd");
  ASSERT_EQ(entries.size(), 4u);
  EXPECT_EQ(entries[0].file, "tools_000000_die.vtp");
  EXPECT_EQ(entries[1].part, "1");
  EXPECT_EQ(entries[3].file, "tools_000001_ram_top.vtp");
  EXPECT_EQ(entries[3].timestep, "0.125");
  EXPECT_EQ(entries[3].part, "1");

  EXPECT_THROW(io::ToolSeriesWriter(dir_, 2), std::invalid_argument);
}

TEST_F(OutputWriters, PvdEscapesAndReplacesAtomically) {
  const fs::path pvd = dir_ / "x.pvd";
  io::write_pvd(pvd, {{0.1, 0, "a&b.vtu"}, {2.5e-7, 3, "c\"d.vtu"}});
  const auto entries = read_pvd(pvd);
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[0].file, "a&b.vtu");
  EXPECT_EQ(entries[0].timestep, "0.10000000000000001");
  EXPECT_EQ(entries[1].file, "c\"d.vtu");
  EXPECT_EQ(entries[1].timestep, "2.4999999999999999e-07");
  EXPECT_EQ(entries[1].part, "3");
  EXPECT_FALSE(fs::exists(dir_ / "x.pvd.tmp"));
  const fs::path bad = uncreatable(dir_, "y.pvd");
  expect_runtime_error_naming([&] { io::write_pvd(bad, {}); }, bad.string());
}

TEST_F(OutputWriters, HistoryCsvFullPrecision) {
  const fs::path file = dir_ / "history.csv";
  {
    io::HistoryWriter history(file, {"time_s", "force_N", "a,b"});
    history.append({0.1, 1.0 / 3.0, -2.0});
    history.append({1e-300, 12345678.0, 0.0});
    history.flush();
    EXPECT_EQ(slurp(file),
              "time_s,force_N,\"a,b\"\n"
              "0.10000000000000001,0.33333333333333331,-2\n"
              "1e-300,12345678,0\n");
    EXPECT_THROW(history.append({1.0, 2.0}), std::logic_error);
    EXPECT_THROW(history.append({1.0, 2.0, 3.0, 4.0}), std::logic_error);
  }
  // A rejected row wrote nothing.
  const std::string text = slurp(file);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 3);
  const fs::path bad = uncreatable(dir_, "history.csv");
  expect_runtime_error_naming([&] { io::HistoryWriter h(bad, {"t"}); }, bad.string());
}

// A restart copies the earlier history's rows up to the checkpoint's time; the earlier file may have
// been rewritten by another tool with CR LF line ends (Python's csv module writes them).
TEST_F(OutputWriters, HistoryRowsCopiedUpToATimeFromLfAndCrLfFiles) {
  const std::vector<std::string> columns{"time_s", "force_N"};
  for (const std::string eol : {"\n", "\r\n"}) {
    const fs::path earlier = dir_ / "earlier.csv";
    {
      std::ofstream out(earlier, std::ios::binary);
      out << "time_s,force_N" << eol << "0,1" << eol << "0.5,2" << eol << "1,3" << eol << "1.5,4" << eol;
    }
    const fs::path file = dir_ / "history.csv";
    {
      io::HistoryWriter history(file, columns);
      EXPECT_EQ(io::copy_history_rows(earlier, columns, 1.0, history), 3u);
      history.flush();
    }
    EXPECT_EQ(slurp(file), "time_s,force_N\n0,1\n0.5,2\n1,3\n");
    // Other columns: nothing copied.
    io::HistoryWriter other(dir_ / "other.csv", {"time_s", "torque_Nm"});
    EXPECT_EQ(io::copy_history_rows(earlier, {"time_s", "torque_Nm"}, 1.0, other), 0u);
  }
}

TEST_F(OutputWriters, SummaryJsonRoundTrip) {
  const fs::path file = dir_ / "summary.json";
  const nlohmann::json summary = {{"status", "completed"},
                                  {"steps", 1234},
                                  {"final_time_s", 1.0 / 3.0},
                                  {"tools", {{{"name", "ram"}, {"peak_force_N", 2.5e5}}}}};
  io::write_summary(file, summary);
  const std::string text = slurp(file);
  EXPECT_EQ(nlohmann::json::parse(text), summary);
  EXPECT_EQ(nlohmann::json::parse(text)["final_time_s"].get<double>(), 1.0 / 3.0);
  EXPECT_EQ(text.rfind("{\n  \"", 0), 0u) << text;  // indent 2
  EXPECT_FALSE(fs::exists(dir_ / "summary.json.tmp"));

  io::write_summary(file, {{"status", "replaced"}});  // overwrites the existing file
  EXPECT_EQ(nlohmann::json::parse(slurp(file))["status"], "replaced");

  const fs::path bad = uncreatable(dir_, "summary.json");
  expect_runtime_error_naming([&] { io::write_summary(bad, summary); }, bad.string());
}
