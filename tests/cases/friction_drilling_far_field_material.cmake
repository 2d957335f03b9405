# CTest (label `integration`): the friction_drilling sheet beyond the disc (theory eq. 121b) takes its
# conductivity and rho c from the sheet's material plugin (ProcessContext::materials), so the case states
# them once: a run of the quick case for 40 microseconds (a few hundred steps) records in summary.json the
# values its far field uses, and changing the material's conductivity and specific heat changes them.
# Invoked as: cmake -DSPHFORGE=... -DCASES=<source>/cases/friction_drilling -DOUT=<dir> -P friction_drilling_far_field_material.cmake

function(far_field_values k_var rc_var label)
  execute_process(COMMAND "${SPHFORGE}" run "${CASES}/hx220_m4_quick.json" --out "${OUT}/${label}" --force --quiet
                          --set "run.end_time=4e-5 s" ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "sphforge run (${label}): exit ${rc}\n${out}${err}")
  endif()
  file(READ "${OUT}/${label}/summary.json" summary)
  string(JSON k GET "${summary}" metrics far_field_conductivity_W_per_m_K)
  string(JSON c GET "${summary}" metrics far_field_heat_capacity_J_per_m3_K)
  set(${k_var} ${k} PARENT_SCOPE)
  set(${rc_var} ${c} PARENT_SCOPE)
endfunction()

# Exact comparison: the expected values are integers, and so are the products the plugin forms
# (7850 x 500, 7850 x 450), exactly representable in a double; nlohmann writes them as "50.0", "3925000.0".
function(expect_value label value expected)
  string(REGEX REPLACE "\\.0+$" "" trimmed "${value}")
  if(NOT trimmed STREQUAL expected)
    message(FATAL_ERROR "${label}: ${value}, expected ${expected}")
  endif()
endfunction()

far_field_values(k0 rc0 as_bundled)
far_field_values(k1 rc1 other_material --set "material.conductivity=40 W/(m*K)" --set "material.specific_heat=450 J/(kg*K)")
message(STATUS "far field k, rho c: bundled ${k0} W/(m K), ${rc0} J/(m^3 K); other material ${k1}, ${rc1}")
# HX220 as bundled: k = 50 W/(m K), rho c = 7850 x 500; the other: 40 and 7850 x 450.
expect_value("bundled k" "${k0}" "50")
expect_value("bundled rho c" "${rc0}" "3925000")
expect_value("other k" "${k1}" "40")
expect_value("other rho c" "${rc1}" "3532500")
