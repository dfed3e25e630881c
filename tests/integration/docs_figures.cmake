# One figure, one place: every figure the README and the docs quote from docs/results.md
# equals the value there (links, anchors and reachability: docs_links_and_commands, docs.cmake).
add_test(NAME docs_figures_match
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_LIST_DIR}/docs_figures.py ${PROJECT_SOURCE_DIR})
set_tests_properties(docs_figures_match PROPERTIES LABELS unit)
