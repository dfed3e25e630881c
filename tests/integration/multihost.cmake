# MPM and DEM on different hosts (issue 16, item 3): hosts A, B, C as network namespaces;
# A | B bitwise equal to the single-host run; B's link cut mid-run, then resumed on A | C.
# Needs root: otherwise skipped (exit 77).
add_test(NAME multihost_netns
         COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/multihost.sh)
set_tests_properties(multihost_netns PROPERTIES TIMEOUT 180 LABELS "integration;no_asan"
  ENVIRONMENT "MPMDEM_BIN=${PROJECT_BINARY_DIR};MPMDEM_SRC=${PROJECT_SOURCE_DIR}"
  SKIP_RETURN_CODE 77 RUN_SERIAL TRUE)
