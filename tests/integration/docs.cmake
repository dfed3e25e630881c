# docs/config_reference.md (mpm_app: the scene) and docs/config_reference_dem.md (dem_app:
# the coupling section with every backend's keys) are generated from the schemas: fail when
# one is out of date.
add_test(NAME docs_config_reference_current
  COMMAND sh -c "\"$1\" --print-config-reference > config_reference.tmp && tail -n +6 \"$2\" | diff -u - config_reference.tmp"
          sh $<TARGET_FILE:mpm_app> ${PROJECT_SOURCE_DIR}/docs/config_reference.md
  WORKING_DIRECTORY ${PROJECT_BINARY_DIR})
set_tests_properties(docs_config_reference_current PROPERTIES LABELS unit)
add_test(NAME docs_config_reference_dem_current
  COMMAND sh -c "\"$1\" --print-config-reference > config_reference_dem.tmp && tail -n +6 \"$2\" | diff -u - config_reference_dem.tmp"
          sh $<TARGET_FILE:dem_app> ${PROJECT_SOURCE_DIR}/docs/config_reference_dem.md
  WORKING_DIRECTORY ${PROJECT_BINARY_DIR})
set_tests_properties(docs_config_reference_dem_current PROPERTIES LABELS unit)

# Every C++ file follows the checked-in .clang-format (skipped where clang-format is missing;
# scripts/setup installs it and CI requires it: MPMDEM_REQUIRE_TEST_DEPS).
mpmdem_test(NAME clang_format_clean NEEDS clang-format
  COMMAND sh -c "find interface laws mpm_app dem_app tests -name '*.cpp' -o -name '*.hpp' | xargs clang-format --dry-run -Werror"
  LABELS unit)
set_tests_properties(clang_format_clean PROPERTIES WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})

# mpm_app and dem_app never depend on each other, only on interface/ and laws/ (includes and
# CMake links, read from the sources: tests/integration/architecture_edges.py).
mpmdem_test(NAME architecture_no_cross_edges
  COMMAND /usr/bin/python3 ${PROJECT_SOURCE_DIR}/tests/integration/architecture_edges.py
          ${PROJECT_SOURCE_DIR}
  LABELS unit)

# The docs can be followed: every docs page (docs/**/*.md) is reachable by links from README.md
# and the index docs/README.md, every relative link and anchor lands, and every repository path
# a quoted command names (scripts/, tests/, configs/, build/ executables) exists
# (tests/integration/docs_links.py says exactly what it reads as a quoted command).
mpmdem_test(NAME docs_links_and_commands
  COMMAND /usr/bin/python3 ${PROJECT_SOURCE_DIR}/tests/integration/docs_links.py
          ${PROJECT_SOURCE_DIR}
  LABELS unit)
