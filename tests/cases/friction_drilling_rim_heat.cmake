# CTest (label `integration`): the two heat paths at the friction_drilling disc's rim.
# 1. `clamp_temperature` (theory eq. 121a) holds the clamped rim at its temperature. The quick case starts
#    at 400 K everywhere (thermal.initial_temperature) and runs 40 microseconds of simulated time (4 ms of
#    process time; the drill touches nothing yet): with the rim held at 293.15 K the coldest particle is at
#    293.15 K (to 1e-6 K: the relaxation is exact within a step), without the option it stays at 400 K (only
#    convection, 5 W/m2K over microseconds, cools the sheet: by far less than 0.01 K). The quick case's sheet
#    beyond the disc (eq. 121b) is switched off for the held rim (the two exclude each other); in the free
#    run it stays on and starts at the sheet's 400 K, so it takes no heat either.
# 2. The sheet beyond the disc (eq. 121b) takes its conductivity and rho c from the sheet's material plugin
#    (ProcessContext::materials), so the case states them once: summary.json records the values it used,
#    the material's as bundled, and others when the material's conductivity and specific heat change.
# Invoked as: cmake -DSPHFORGE=... -DCASES=<source>/cases/friction_drilling -DOUT=<dir> -P friction_drilling_rim_heat.cmake

function(coldest out_var label)
  execute_process(COMMAND "${SPHFORGE}" run "${CASES}/hx220_m4_quick.json" --out "${OUT}/${label}" --force --quiet
                          --set "thermal.initial_temperature=400 K" --set "run.end_time=4e-5 s"
                          --set "run.history_interval=1e-5 s" ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "sphforge run (${label}): exit ${rc}\n${out}${err}")
  endif()
  file(STRINGS "${OUT}/${label}/history.csv" lines)
  list(GET lines 0 header)
  list(GET lines -1 last)
  string(REPLACE "," ";" header "${header}")
  string(REPLACE "," ";" last "${last}")
  list(FIND header temperature_min_K column)
  if(column LESS 0)
    message(FATAL_ERROR "history.csv has no temperature_min_K")
  endif()
  list(GET last ${column} value)
  set(${out_var} ${value} PARENT_SCOPE)
endfunction()

coldest(held held --set "process.clamp_temperature=293.15 K" --set "process.sheet_far_field_radius=0 m")
coldest(free free)
message(STATUS "coldest particle: rim held at 293.15 K: ${held} K; rim free: ${free} K")
if(held LESS 293.149999 OR held GREATER 293.150001)
  message(FATAL_ERROR "with clamp_temperature 293.15 K the coldest particle is at ${held} K")
endif()
if(free LESS 399.99)
  message(FATAL_ERROR "without clamp_temperature the coldest particle cooled to ${free} K")
endif()

# Exact comparison: the expected values are integers, and so are the products the plugin forms
# (7850 x 500, 7850 x 450), exactly representable in a double; nlohmann writes them as "50.0", "3925000.0".
function(expect_far_field label conductivity heat_capacity)
  file(READ "${OUT}/${label}/summary.json" summary)
  string(JSON k GET "${summary}" metrics far_field_conductivity_W_per_m_K)
  string(JSON c GET "${summary}" metrics far_field_heat_capacity_J_per_m3_K)
  message(STATUS "far field (${label}): k = ${k} W/(m K), rho c = ${c} J/(m^3 K)")
  string(REGEX REPLACE "\\.0+$" "" k "${k}")
  string(REGEX REPLACE "\\.0+$" "" c "${c}")
  if(NOT k STREQUAL conductivity OR NOT c STREQUAL heat_capacity)
    message(FATAL_ERROR "far field (${label}): k ${k}, rho c ${c}; expected the material's ${conductivity}, ${heat_capacity}")
  endif()
endfunction()

# HX220 as bundled: k = 50 W/(m K), rho c = 7850 x 500; another sheet material: 40 and 7850 x 450.
expect_far_field(free 50 3925000)
coldest(other_material other_material --set "material.conductivity=40 W/(m*K)" --set "material.specific_heat=450 J/(kg*K)")
expect_far_field(other_material 40 3532500)
