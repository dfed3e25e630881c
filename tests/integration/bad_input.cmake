# Bad input, nothing lost (issue 6, item 4): broken scenes through scripts/run and mpm_app.
add_test(NAME bad_input_nothing_lost
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_LIST_DIR}/bad_input.py ${PROJECT_BINARY_DIR} ${PROJECT_SOURCE_DIR})
set_tests_properties(bad_input_nothing_lost PROPERTIES TIMEOUT 300 LABELS integration RUN_SERIAL TRUE)
