# Resume on another DEM rank count (issue 16, item 2): written with 2 ranks, resumed with 1
# and with 3, end state bitwise equal to the uninterrupted run.
add_test(NAME resume_ranks_elastic COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/resume_ranks.sh elastic)
set_tests_properties(resume_ranks_elastic PROPERTIES TIMEOUT 120 LABELS integration
  ENVIRONMENT "MPMDEM_BIN=${PROJECT_BINARY_DIR};MPMDEM_SRC=${PROJECT_SOURCE_DIR}"
  RUN_SERIAL TRUE)
if(MPMDEM_WITH_YADE AND EXISTS /usr/bin/yade AND EXISTS /usr/bin/python3.11-config)
  add_test(NAME resume_ranks_yade COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/resume_ranks.sh yade)
  set_tests_properties(resume_ranks_yade PROPERTIES TIMEOUT 180 LABELS integration
    ENVIRONMENT "MPMDEM_BIN=${PROJECT_BINARY_DIR};MPMDEM_SRC=${PROJECT_SOURCE_DIR}"
    RUN_SERIAL TRUE)
endif()
