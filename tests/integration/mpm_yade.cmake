# mpm_app against 2 YADE server ranks on a tiny scene (issue 3, item 9). Registered only when
# the YADE backend is built.
if(MPMDEM_WITH_YADE AND EXISTS /usr/bin/yade AND EXISTS /usr/bin/python3.11-config)
  add_test(NAME mpm_yade_block_2ranks COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/mpm_block.sh yade)
  # Normal pass only (CI time): the YADE backend C++ runs under ASan in the YadeBackend units,
  # the remote provider in the coupling_client_* tests.
  set_tests_properties(mpm_yade_block_2ranks PROPERTIES TIMEOUT 300 LABELS "integration;no_asan"
    ENVIRONMENT "MPMDEM_BIN=${PROJECT_BINARY_DIR};MPMDEM_SRC=${PROJECT_SOURCE_DIR}"
    RUN_SERIAL TRUE)
endif()
