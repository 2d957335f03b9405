# CTest (label `integration`): the friction_drilling plugin's input handling through `sphforge check`
# (validation and scene building, no time steps): the force-controlled case binds a PID controller to
# the process's signals, and bad process parameters are user errors (exit 2) naming file and pointer.
# Invoked as: cmake -DSPHFORGE=... -DCASES=<source>/cases/friction_drilling -P friction_drilling_inputs.cmake

# Runs `sphforge check ARGS...`; fails unless the exit code is `code` and the output matches `regex`.
function(expect_check code regex)
  execute_process(COMMAND "${SPHFORGE}" check ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL code)
    message(FATAL_ERROR "sphforge check ${ARGN}: exit ${rc}, expected ${code}\n${out}${err}")
  endif()
  if(NOT "${out}${err}" MATCHES "${regex}")
    message(FATAL_ERROR "sphforge check ${ARGN}: output does not match '${regex}':\n${out}${err}")
  endif()
endfunction()

# PID on drill_axial_force -> drill_feed_rate (the names the process offers).
expect_check(0 "is valid: 16408 particles" "${CASES}/hx220_m4_force_controlled.json")
# A misspelt signal is an input error at the controller's parameter.
expect_check(2 "hx220_m4_force_controlled.json at /controllers/0/measured"
             "${CASES}/hx220_m4_force_controlled.json" --set "controllers.0.measured=drill_force")
# Fewer than two layers over the sheet thickness.
expect_check(2 "hx220_m4_quick.json at /process/particle_spacing: too coarse"
             "${CASES}/hx220_m4_quick.json" --set "process.particle_spacing=1 mm")
# The bushing band must stay inside the clamped rim.
expect_check(2 "hx220_m4_quick.json at /process/bushing_outer_radius"
             "${CASES}/hx220_m4_quick.json" --set "process.bushing_outer_radius=6 mm")
# The bushing's link distance must exceed the spacing, else the intact lattice has no links (eq. 127a).
expect_check(2 "hx220_m4_quick.json at /process/bushing_link_distance: must exceed particle_spacing"
             "${CASES}/hx220_m4_quick.json" --set "process.bushing_link_distance=0.3 mm")
expect_check(0 "is valid" "${CASES}/hx220_m4_quick.json" --set "process.bushing_link_distance=0.6 mm")
# A drill profile that is not a list of [r, z] pairs.
expect_check(2 "hx220_m4_quick.json at /process/drill_profile"
             "${CASES}/hx220_m4_quick.json" --set "process.drill_profile=[1, 2]")
# The sheet beyond the disc (eq. 121b): it must reach past the disc and excludes a rim held at a
# temperature (one heat path at the rim). Its k and rho c are the sheet material's, not process
# parameters (friction_drilling_rim_heat.cmake).
expect_check(2 "hx220_m4_quick.json at /process/sheet_far_field_radius: must exceed the disc radius"
             "${CASES}/hx220_m4_quick.json" --set "process.sheet_far_field_radius=4 mm")
expect_check(2 "hx220_m4_quick.json at /process/sheet_conductivity"
             "${CASES}/hx220_m4_quick.json" --set "process.sheet_conductivity=50 W/(m*K)")
expect_check(2 "hx220_m4_quick.json at /process/sheet_far_field_radius: choose one heat path"
             "${CASES}/hx220_m4_quick.json" --set "process.clamp_temperature=293.15 K")
expect_check(0 "is valid" "${CASES}/hx220_m4_quick.json" --set "process.clamp_temperature=293.15 K"
             --set "process.sheet_far_field_radius=0 m")
# The refined centre (eq. 121c): the paper's 0.4 / 0.2 mm case is valid; a fine spacing that does not
# divide the coarse one, one coarser than it, or a refined centre in a sector are input errors.
expect_check(0 "is valid: 9016 particles" "${CASES}/hx220_m4_refined.json")
expect_check(2 "hx220_m4_quick.json at /process/refined_spacing: particle_spacing must be a whole multiple"
             "${CASES}/hx220_m4_quick.json" --set "process.refined_diameter=5 mm" --set "process.refined_spacing=0.15 mm")
expect_check(2 "hx220_m4_quick.json at /process/refined_spacing: must be positive and finer"
             "${CASES}/hx220_m4_quick.json" --set "process.refined_diameter=5 mm")
expect_check(2 "hx220_m4.json at /process/refined_diameter: a refined centre needs the full disc"
             "${CASES}/hx220_m4.json" --set "process.refined_diameter=5 mm" --set "process.refined_spacing=0.1 mm")
# Past the core's own check: several spacings in a symmetry sector are refused (theory section 19).
expect_check(2 "hx220_m4_refined.json at /numerics/symmetry: a symmetry sector is not implemented for particles of several spacings"
             "${CASES}/hx220_m4_refined.json" --set "numerics.symmetry={\"sector\":{\"angle\":\"90 deg\"}}")
