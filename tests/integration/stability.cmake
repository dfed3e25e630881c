# scripts/stability_suite --quick (local cases: stiffness sweep 1e6/1e9/1e11 Pa, column
# a = 0.5, elastic impact at 50 m/s, the forced-unstable column) and, when the YADE backend
# is built, the free-falling multiscale block and 1e-2 dF increments into a YADE RVE; the
# table is checked by tests/integration/stability_check.py (dt ~ 1/sqrt(E) from
# c = sqrt(M/rho), the unstable case detected with its point and step, no NaN/Inf in any
# output). Every process is stopped by PID by scripts/run, scripts/element_test (pair.sh).
set(_stab_env "MPMDEM_SKIP_SETUP=1" "MPMDEM_BUILD_DIR=${PROJECT_BINARY_DIR}")
set(_stab_out ${PROJECT_BINARY_DIR}/test-runs/stability)
add_test(NAME stability_suite_quick
  COMMAND sh -c "rm -rf \"$1\" && \"$2\" --quick --out \"$1\"; rc=$?; /usr/bin/python3 \"$3\" \"$1\" quick $rc"
          sh ${_stab_out}/quick ${PROJECT_SOURCE_DIR}/scripts/stability_suite
          ${CMAKE_CURRENT_LIST_DIR}/stability_check.py)
set_tests_properties(stability_suite_quick PROPERTIES TIMEOUT 240 LABELS integration
                     ENVIRONMENT "${_stab_env}" RUN_SERIAL TRUE)
if(MPMDEM_WITH_YADE AND EXISTS /usr/bin/yade AND EXISTS /usr/bin/python3.11-config)
  add_test(NAME stability_suite_yade
    COMMAND sh -c "rm -rf \"$1\" && \"$2\" --only free_fall_rves,dF_1e-2 --out \"$1\"; rc=$?; /usr/bin/python3 \"$3\" \"$1\" yade $rc"
            sh ${_stab_out}/yade ${PROJECT_SOURCE_DIR}/scripts/stability_suite
            ${CMAKE_CURRENT_LIST_DIR}/stability_check.py)
  set_tests_properties(stability_suite_yade PROPERTIES TIMEOUT 300 LABELS integration
                       ENVIRONMENT "${_stab_env}" RUN_SERIAL TRUE)
endif()
