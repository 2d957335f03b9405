// Verification 10 (docs/verification.md section 10): one flat wall, four tool shapes, and a
// commanded tool
// (cases/verification/tool_shapes.json, 256 particles, ~570 steps per run).
//
// The wall z = s(t) is given as a plane tool, as a flat profile face, as a filleted punch face
// (its fillet far from the block) and as the top face of an STL cube lowered by half its side.
// For a particle above the face every shape returns the distance z - s(t) and the normal +z up
// to round-off (docs/theory.md eqs. 40-44): ~1e-19 m out of contact gaps of ~1e-6 m, i.e. ~1e-13
// of the penalty force per step. Tolerance on the force histories: 1e-9 of the peak force, room
// for that round-off to grow over ~570 steps of an elastic block and still three orders below
// any physical difference (a 1 % difference in a contact distance changes the force by ~1 %).
// Pose: the schedule's velocity is its exact mean over each step (eq. 45), so the position
// equals the integral of the schedule at the run's end time to the round-off of ~570 sums
// (tolerance 1e-15 m, ~1e-12 of the 0.5 mm travelled); the angle is omega t likewise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include "run_helpers.hpp"

namespace {

using namespace sphforge_verification;

const std::string kMotion = R"("axial_schedule":[["0 ms","0 m/s"],["1 ms","0.2 m/s"]],"angular_velocity":"100 rad/s")";

/// Exact integral of the schedule 0 -> 0.2 m/s over 1 ms, then 0.2 m/s.
double schedule_integral(double t) { return t <= 1e-3 ? 0.5 * 0.2 / 1e-3 * t * t : 1e-4 + 0.2 * (t - 1e-3); }

TEST(ToolShapes, FourShapesOfOneWallGiveOneHistory) {
  const RunResult plane = run_case("tool_shapes.json", "tool_shapes_plane", {});
  ASSERT_EQ(plane.code, 0) << plane.err;
  const RunResult profile = run_case(
      "tool_shapes.json", "tool_shapes_profile",
      {R"(process.tools.0={"name":"wall","shape":"profile","points":[[0,0],["10 mm",0]],)" + kMotion + "}"});
  ASSERT_EQ(profile.code, 0) << profile.err;
  const RunResult fillet = run_case("tool_shapes.json", "tool_shapes_fillet",
                                    {R"(process.tools.0={"name":"wall","shape":"profile",)"
                                     R"("points":[[0,0],["8 mm",0],["8 mm","-3 mm"]],"fillet_radius":"1 mm",)" +
                                     kMotion + "}"});
  ASSERT_EQ(fillet.code, 0) << fillet.err;
  const RunResult stl = run_case("tool_shapes.json", "tool_shapes_stl",
                                 {R"(process.tools.0={"name":"wall","shape":"stl","file":"tools/box_10mm.stl",)"
                                  R"("scale":0.001,"position":"-5 mm",)" +
                                  kMotion + "}"});
  ASSERT_EQ(stl.code, 0) << stl.err;

  const History h0 = read_history(plane.out / "history.csv");
  const auto& f0 = h0["wall_force_z_N"];
  const double fmax = std::abs(*std::max_element(f0.begin(), f0.end(), [](double a, double b) { return std::abs(a) < std::abs(b); }));
  ASSERT_GT(fmax, 0.0);  // the wall does push the block
  ASSERT_GT(h0["momentum_z_kg_m_s"].back(), 0.0);

  // The pose follows the schedule: s(t) and omega t at every history row.
  const auto& t = h0["time_s"];
  double dpos = 0.0, dangle = 0.0;
  for (std::size_t k = 0; k < h0.rows; ++k) {
    dpos = std::max(dpos, std::abs(h0["wall_position_m"][k] - schedule_integral(t[k])));
    dangle = std::max(dangle, std::abs(h0["wall_angle_rad"][k] - 100.0 * t[k]));
  }
  EXPECT_LT(dpos, 1e-15);
  EXPECT_LT(dangle, 1e-12);  // 100 rad/s x 3 ms = 0.3 rad; ~570 sums of round-off

  const std::vector<std::pair<std::string, fs::path>> others = {
      {"profile", profile.out}, {"fillet", fillet.out}, {"stl", stl.out}};
  for (const auto& [name, dir] : others) {
    const History h = read_history(dir / "history.csv");
    ASSERT_EQ(h.rows, h0.rows) << name;
    double df = 0.0, dside = 0.0;
    for (std::size_t k = 0; k < h.rows; ++k) {
      df = std::max(df, std::abs(h["wall_force_z_N"][k] - f0[k]));
      dside = std::max(dside, std::hypot(h["wall_force_x_N"][k], h["wall_force_y_N"][k]));
    }
    char line[300];
    std::snprintf(line, sizeof line,
                  "tool shapes: %s vs plane: max |dF_z| %.3e of the peak %.4e N; lateral force %.3e of the peak\n",
                  name.c_str(), df / fmax, fmax, dside / fmax);
    std::printf("%s", line);
    record("verification_results.txt", line);
    EXPECT_LT(df, 1e-9 * fmax) << line;
    EXPECT_LT(dside, 1e-9 * fmax) << line;  // a flat frictionless wall pushes along z only
  }

  // tools.pvd: the STL cube drawn in its last pose, top face at z = s(t_end), turned by omega t_end.
  const History hs = read_history(stl.out / "history.csv");
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName((stl.out / "tools_000003_wall.vtp").string().c_str());
  reader->Update();
  vtkPolyData* poly = reader->GetOutput();
  ASSERT_EQ(poly->GetNumberOfPolys(), 12);
  const double s_end = hs["wall_position_m"].back() + 5e-3, angle = hs["wall_angle_rad"].back();
  const double cx = 5e-3 * (std::cos(angle) - std::sin(angle)), cy = 5e-3 * (std::sin(angle) + std::cos(angle));
  bool corner = false;
  for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i) {
    double p[3];
    poly->GetPoint(i, p);
    // Round-off of the stored coordinates (VTK writes doubles): 1e-15 m.
    corner = corner || (std::abs(p[0] - cx) < 1e-15 && std::abs(p[1] - cy) < 1e-15 && std::abs(p[2] - s_end) < 1e-15);
  }
  EXPECT_TRUE(corner) << "no corner of the cube at the rotated (5, 5, 5) mm in the last frame";
}

}  // namespace

namespace {

using namespace sphforge_verification;

// The same wall commanded by a controller (`prescribed`, 0.15 m/s and -40 rad/s through the
// signals wall_axial_velocity and wall_angular_velocity): the pose is v t and omega t at every
// history row. Tolerance 1e-15 m and 1e-13 rad: round-off of ~570 sums of v dt (the command is
// constant, so nothing but round-off can differ).
TEST(ToolShapes, CommandedToolFollowsTheController) {
  const RunResult r = run_case(
      "tool_shapes.json", "tool_shapes_commanded",
      {R"(process.tools.0={"name":"wall","shape":"plane","point":[0,0,0],"normal":[0,0,1],"half_size":"10 mm","command":true})",
       R"(controllers=[{"plugin":"prescribed","command":"wall_axial_velocity","value":"0.15 m/s"},)"
       R"({"plugin":"prescribed","command":"wall_angular_velocity","value":"-40 rad/s"}])"});
  ASSERT_EQ(r.code, 0) << r.err;
  const History h = read_history(r.out / "history.csv");
  ASSERT_GT(h.rows, 10u);
  double dpos = 0.0, dangle = 0.0;
  for (std::size_t k = 0; k < h.rows; ++k) {
    dpos = std::max(dpos, std::abs(h["wall_position_m"][k] - 0.15 * h["time_s"][k]));
    dangle = std::max(dangle, std::abs(h["wall_angle_rad"][k] + 40.0 * h["time_s"][k]));
  }
  EXPECT_LT(dpos, 1e-15);
  EXPECT_LT(dangle, 1e-13);
  EXPECT_GT(h["wall_position_m"].back(), 4e-4);  // 0.15 m/s x 3 ms: it did move
  // Without `command: true` the signal does not exist: an input error naming the known commands.
  const RunResult bad = run_case("tool_shapes.json", "tool_shapes_uncommanded",
                                 {R"(controllers=[{"plugin":"prescribed","command":"wall_axial_velocity","value":"1 m/s"}])"});
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("/controllers/0/command"), std::string::npos) << bad.err;
}

}  // namespace

namespace {

using namespace sphforge_verification;

// User errors in the tools array: exit code 2, one message naming the file and the JSON pointer.
TEST(ToolShapes, InputErrorsNameTheToolsPointer) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"(process.tools.0={"name":"wall","shape":"stl","file":"tools/missing.stl"})", "/process/tools/0/file"},
      {R"(process.tools.0={"name":"wall","shape":"profile","points":[[0,0],["1 mm",0],["1 mm","1 mm"]],"fillet_radius":"2 mm"})",
       "/process/tools/0/fillet_radius"},
      {R"(process.tools.0={"name":"wall","shape":"profile","points":[[0,0],["1 kg",0]]})", "/process/tools/0/points"},
      {R"(process.tools.0.axial_schedule=[["2 ms",0],["1 ms",1]])", "/process/tools/0/axial_schedule"},
      {R"(process.tools.0.normal=[0,0,0])", "/process/tools/0/normal"},
      {R"(process.planes=[{"name":"wall","z":0}])", "/process/tools/0/name"},
  };
  int k = 0;
  for (const auto& [set, pointer] : cases) {
    const RunResult r = run_case("tool_shapes.json", "tool_shapes_error_" + std::to_string(k++), {set});
    EXPECT_EQ(r.code, 2) << set << "\n" << r.err;
    EXPECT_NE(r.err.find("tool_shapes.json"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(pointer), std::string::npos) << set << "\n" << r.err;
  }
}

}  // namespace
