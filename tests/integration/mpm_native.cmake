# mpm_app against 2 native server ranks on a tiny scene (issue 15, item 5).
add_test(NAME mpm_native_block_2ranks COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/mpm_block.sh native)
set_tests_properties(mpm_native_block_2ranks PROPERTIES TIMEOUT 120 LABELS "integration;no_asan"
  ENVIRONMENT "MPMDEM_BIN=${PROJECT_BINARY_DIR};MPMDEM_SRC=${PROJECT_SOURCE_DIR}"
  RUN_SERIAL TRUE)
