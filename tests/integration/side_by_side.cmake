# Side by side (issue 3, item 7): dem_app --backend yade over MPI (2 ranks, driven by
# element_test --test df_file) against a standalone one-process YADE script on the same
# 40-sphere packing and dF sequence: equal stresses to <= 1e-10 relative. Registered only when
# the YADE backend is built.
if(MPMDEM_WITH_YADE AND EXISTS /usr/bin/yade AND EXISTS /usr/bin/python3.11-config)
  add_test(NAME side_by_side_yade_standalone COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/side_by_side.sh)
  set_tests_properties(side_by_side_yade_standalone PROPERTIES TIMEOUT 180 LABELS "integration;no_asan"
    ENVIRONMENT "MPMDEM_BIN=${PROJECT_BINARY_DIR};MPMDEM_SRC=${PROJECT_SOURCE_DIR}"
    RUN_SERIAL TRUE)
endif()
