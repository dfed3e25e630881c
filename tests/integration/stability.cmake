# scripts/stability_suite --quick (local cases: stiffness sweep 1e6/1e9/1e11 Pa, column
# a = 0.5, elastic impact at 50 m/s, the forced-unstable column) and, when the YADE backend
# is built, the free-falling multiscale block and 1e-2 dF increments into a YADE RVE; the
# table is checked by tests/integration/stability_check.py (dt ~ 1/sqrt(E) from
# c = sqrt(M/rho), the unstable case detected with its point and step, no NaN/Inf in any
# output). Every process is stopped by PID by scripts/run, scripts/element_test (pair.sh).

# stability_test(NAME CHECK_SET TIMEOUT NEEDS SUITE_ARGS...): the suite into
# test-runs/stability/CHECK_SET, then stability_check.py on its table with the suite's exit
# code; NEEDS: the dependency (needs.sh) or "none". (Newlines, not ';', separate the shell's
# commands: mpmdem_test's arguments are a CMake list.)
function(stability_test name check_set timeout needs)
  set(out ${PROJECT_BINARY_DIR}/test-runs/stability/${check_set})
  list(JOIN ARGN " " suite_args)
  set(needs_args "")
  if(NOT needs STREQUAL "none")
    set(needs_args NEEDS ${needs})
  endif()
  mpmdem_test(NAME ${name} ${needs_args}
    COMMAND sh -c "rm -rf \"$1\" && \"$2\" ${suite_args} --out \"$1\"\nrc=$?\n/usr/bin/python3 \"$3\" \"$1\" ${check_set} $rc"
            sh ${out} ${PROJECT_SOURCE_DIR}/scripts/stability_suite
            ${CMAKE_CURRENT_FUNCTION_LIST_DIR}/stability_check.py
    TIMEOUT ${timeout} LABELS integration no_asan SERIAL
    ENVIRONMENT "MPMDEM_SKIP_SETUP=1" "MPMDEM_BUILD_DIR=${PROJECT_BINARY_DIR}")
endfunction()

stability_test(stability_suite_quick quick 240 none --quick)
stability_test(stability_suite_yade yade 300 yade --only free_fall_rves,dF_1e-2)
