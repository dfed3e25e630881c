# A minimal multiscale column collapse and its exact resume from a checkpoint (issue 4,
# items 6-7). Registered only when the YADE backend is built.
if(MPMDEM_WITH_YADE AND EXISTS /usr/bin/yade AND EXISTS /usr/bin/python3.11-config)
  add_test(NAME column_yade_tiny_resume COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/column_yade.sh)
  set_tests_properties(column_yade_tiny_resume PROPERTIES TIMEOUT 600 LABELS "integration;no_asan"
    ENVIRONMENT "MPMDEM_BIN=${PROJECT_BINARY_DIR};MPMDEM_SRC=${PROJECT_SOURCE_DIR}"
    RUN_SERIAL TRUE)
endif()
