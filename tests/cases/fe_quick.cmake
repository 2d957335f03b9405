# CTest (label `cases`): the friction-extrusion CI case (cases/friction_extrusion/aa7075_pid_300kN_quick.json,
# 4 mm spacing, 3 s of process) runs to its end and its metrics match the stored reference
# (cases/friction_extrusion/reference/quick_metrics.json). docs/validation/friction_extrusion.md.
include(${CMAKE_CURRENT_LIST_DIR}/run_case.cmake)
get_filename_component(case_dir "${CASE}" DIRECTORY)
file(READ "${case_dir}/reference/quick_metrics.json" reference)
case_metric(force steady_mean_force_N)
case_metric(settled settled)
case_metric(settle settling_time_s)
case_metric(t_if final_interface_temperature_K)
case_metric(t_die final_die_thermocouple_K)
case_metric(q_f final_friction_heat_rate_W)
message(STATUS "status ${status}, steady force ${force} N, settling ${settle} s, interface ${t_if} K, "
               "die thermocouple ${t_die} K, friction heat ${q_f} W, max kinetic/work ${ratio}, wall ${wall} s")
expect_status(completed "the run reaches run.end_time")
# The paper's quasi-static criterion for its mass and velocity scaling: kinetic energy below 1.4 %.
if(ratio GREATER 0.014)
  message(FATAL_ERROR "kinetic/work ratio ${ratio} > 0.014 (the paper's 1.4 % criterion)")
endif()
# Force control: the force error enters the +/-15 % band (Table D.1's settling definition) and stays.
if(NOT settled STREQUAL "ON" AND NOT settled STREQUAL "true")
  message(FATAL_ERROR "the extrusion force never settled within +/-15 % of 300 kN")
endif()
# Physical bounds: the interface is heated by friction above room temperature (295.15 K) and stays
# below the Johnson-Cook melting temperature 750.15 K (the material has no strength there, so the
# Tresca friction heat vanishes); heat reaches the die thermocouple only by conduction from the
# billet (friction_heat_to_workpiece = 1), so it is colder than the mean interface.
if(NOT (t_if GREATER 300 AND t_if LESS 750.15))
  message(FATAL_ERROR "interface temperature ${t_if} K outside (300 K, 750.15 K)")
endif()
if(NOT (t_die GREATER 295.15 AND t_die LESS t_if))
  message(FATAL_ERROR "die thermocouple ${t_die} K not between room temperature and the interface ${t_if} K")
endif()
# Regression against the stored reference: each metric inside [min, max] of
# reference/quick_metrics.json, whose `why` states the reason for the width (CMake compares floats but
# has no float arithmetic, so the bounds are stored, not computed).
foreach(key steady_mean_force_N final_interface_temperature_K final_die_thermocouple_K)
  case_metric(value ${key})
  string(JSON lo GET "${reference}" metrics ${key} min)
  string(JSON hi GET "${reference}" metrics ${key} max)
  string(JSON why GET "${reference}" metrics ${key} why)
  message(STATUS "${key} = ${value}, reference range [${lo}, ${hi}] (${why})")
  if(value LESS lo OR value GREATER hi)
    message(FATAL_ERROR "${key} = ${value} outside the reference range [${lo}, ${hi}]")
  endif()
endforeach()
