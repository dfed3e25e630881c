# Lazy RVE evaluation (issue 6, item 2) on the tiny YADE column, with an exact resume.
if(MPMDEM_WITH_YADE AND EXISTS /usr/bin/yade AND EXISTS /usr/bin/python3.11-config)
  add_test(NAME lazy_yade_column COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/lazy.sh)
  set_tests_properties(lazy_yade_column PROPERTIES TIMEOUT 600 LABELS "integration;no_asan"
    ENVIRONMENT "MPMDEM_BIN=${PROJECT_BINARY_DIR};MPMDEM_SRC=${PROJECT_SOURCE_DIR}"
    RUN_SERIAL TRUE)
endif()
