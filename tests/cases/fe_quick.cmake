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
case_metric(v_min steady_die_velocity_min_m_s)
message(STATUS "status ${status}, steady force ${force} N, settling ${settle} s, interface ${t_if} K, "
               "die thermocouple ${t_die} K, friction heat ${q_f} W, min steady die velocity ${v_min} m/s, max kinetic/work ${ratio}, wall ${wall} s")
expect_status(completed "the run reaches run.end_time")
# The paper's quasi-static criterion for its mass and velocity scaling: kinetic energy below 1.4 %.
if(ratio GREATER 0.014)
  message(FATAL_ERROR "kinetic/work ratio ${ratio} > 0.014 (the paper's 1.4 % criterion)")
endif()
# Force control: the force error enters the +/-15 % band (Table D.1's settling definition) and stays.
if(NOT settled STREQUAL "ON" AND NOT settled STREQUAL "true")
  message(FATAL_ERROR "the extrusion force never settled within +/-15 % of 300 kN")
endif()
# The sampled force loop is stable (docs/theory.md eq. 109a: contact.stiffness_factor 0.05 is below the
# limit, about 0.23 at 4 mm). An unstable loop runs a period-2 cycle whose every other command is clipped
# at the lower limit -0.04 mm/s, so the steady samples reach it (measured at stiffness_factor 1: min
# -0.04 mm/s; at 0.05: -0.018 mm/s). The bound sits 0.0001 mm/s inside the limit for the printed digits.
if(v_min LESS_EQUAL -3.99e-05)
  message(FATAL_ERROR "steady die velocity reached the lower command limit (${v_min} m/s): the sampled "
                      "PID loop chatters (docs/theory.md eq. 109a)")
endif()
# Physical bounds (run_case.cmake): the Johnson-Cook melting temperature is 750.15 K, the room
# 295.15 K; friction_heat_to_workpiece = 1, so the die is heated only through the billet.
expect_interface_and_tool_temperatures(${t_if} ${t_die} 295.15 750.15)
# Regression against the stored reference (reference/quick_metrics.json).
expect_reference_ranges("${reference}" steady_mean_force_N final_interface_temperature_K final_die_thermocouple_K)
