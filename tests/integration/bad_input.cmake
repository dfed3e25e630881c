# Bad input, nothing lost (issue 6, item 4): broken scenes through scripts/run and mpm_app.
add_test(NAME bad_input_nothing_lost
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_LIST_DIR}/bad_input.py ${PROJECT_BINARY_DIR} ${PROJECT_SOURCE_DIR})
set_tests_properties(bad_input_nothing_lost PROPERTIES TIMEOUT 300 LABELS integration RUN_SERIAL TRUE)

# Validation is complete before anything runs (issue 35, item 3): a corpus of shipped scenes
# with one change each, every one breaking a different rule of either program, refused by
# scripts/run's check (exit 2, key, file and line; nothing written, nothing started). No MPI.
add_test(NAME bad_scenes_refused_up_front
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_LIST_DIR}/bad_scenes.py ${PROJECT_BINARY_DIR} ${PROJECT_SOURCE_DIR})
set_tests_properties(bad_scenes_refused_up_front PROPERTIES TIMEOUT 120 LABELS integration)
