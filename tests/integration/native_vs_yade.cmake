# Native vs YADE backend on one packing and one seeded dF sequence (issue 15, item 2):
# initial stress to 1e-9, the first 10 coupling steps to 1e-6 relative. Needs Debian's yade
# (the YADE side runs as a Python module, no YADE backend build needed); SKIPPED without it.
add_test(NAME native_vs_yade
  COMMAND bash -c "test -x /usr/bin/yade || { echo 'SKIPPED: /usr/bin/yade missing'; exit 77; }; exec bash ${CMAKE_CURRENT_LIST_DIR}/native_vs_yade.sh")
set_tests_properties(native_vs_yade PROPERTIES TIMEOUT 120 LABELS "integration;no_asan" SKIP_RETURN_CODE 77
  ENVIRONMENT "MPMDEM_BIN=${PROJECT_BINARY_DIR};MPMDEM_SRC=${PROJECT_SOURCE_DIR}")
