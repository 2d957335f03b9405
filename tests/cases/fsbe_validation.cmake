# Validation (label `validation`, not in CI): the bundled FSBE case (cases/fsbe/brass_wire.json, 1 mm,
# 90 deg sector, 10 mm plunge) against issue 8 item 6: the peak interface temperature under the tool
# lies within 60-90 % of the melting temperature. The paper gives T_m in degC (916 C), so the band is
# taken in degC: 549.6-824.4 C = 822.75-1097.55 K. Strain at the wire's periphery against its centre
# and the wire's continuity need the particle cloud: docs/validation/friction_extrusion.md (FSBE).
include(${CMAKE_CURRENT_LIST_DIR}/run_case.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/validation_check.cmake)
case_metric(t_peak peak_interface_temperature_K)
check_between("peak interface temperature (K), 60-90 % of 916 C" t_peak 822.75 1097.55)
finish_validation()
