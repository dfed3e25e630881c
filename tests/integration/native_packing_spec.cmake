# A native scene builds and exports its packings from coupling.native.packing_spec (issue 15).
if(MPMDEM_WITH_YADE AND EXISTS /usr/bin/yade AND EXISTS /usr/bin/python3.11-config)
  add_test(NAME native_packing_spec COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/native_packing_spec.sh)
  set_tests_properties(native_packing_spec PROPERTIES TIMEOUT 180 LABELS "integration;no_asan"
    ENVIRONMENT "MPMDEM_BIN=${PROJECT_BINARY_DIR};MPMDEM_SRC=${PROJECT_SOURCE_DIR}"
    RUN_SERIAL TRUE)
endif()
