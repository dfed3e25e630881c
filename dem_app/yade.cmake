# YADE backend (issue 3): embeds Debian's Python 3.11 (the interpreter YADE runs in) into
# dem_server. Included from dem_app/CMakeLists.txt when MPMDEM_WITH_YADE=ON. Use
# /usr/bin/python3.11-config explicitly: the one first on PATH may belong to pyenv.
set(MPMDEM_PYTHON_CONFIG /usr/bin/python3.11-config CACHE FILEPATH
    "python-config of the interpreter YADE runs in")
if(NOT EXISTS ${MPMDEM_PYTHON_CONFIG} OR NOT EXISTS /usr/bin/yade)
  if(MPMDEM_REQUIRE_TEST_DEPS)
    message(FATAL_ERROR "YADE backend: need ${MPMDEM_PYTHON_CONFIG} (apt-get install "
                        "python3.11-dev) and /usr/bin/yade (apt-get install yade); "
                        "MPMDEM_REQUIRE_TEST_DEPS (CI) runs every YADE test")
  endif()
  message(WARNING "YADE backend skipped: need ${MPMDEM_PYTHON_CONFIG} (apt-get install "
                  "python3.11-dev) and /usr/bin/yade (apt-get install yade)")
  return()
endif()
execute_process(COMMAND ${MPMDEM_PYTHON_CONFIG} --includes OUTPUT_VARIABLE _py_inc
                OUTPUT_STRIP_TRAILING_WHITESPACE)
execute_process(COMMAND ${MPMDEM_PYTHON_CONFIG} --ldflags --embed OUTPUT_VARIABLE _py_ld
                OUTPUT_STRIP_TRAILING_WHITESPACE)
separate_arguments(_py_inc UNIX_COMMAND "${_py_inc}")
separate_arguments(_py_ld UNIX_COMMAND "${_py_ld}")
set(_py_dirs "")
foreach(f ${_py_inc})
  string(REGEX REPLACE "^-I" "" d "${f}")
  list(APPEND _py_dirs "${d}")
endforeach()
list(REMOVE_DUPLICATES _py_dirs)
message(STATUS "YADE backend: Python includes ${_py_dirs}; link ${_py_ld}")

file(GLOB YADE_BACKEND_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/backends/yade*.cpp)
target_sources(dem_server PRIVATE ${YADE_BACKEND_SOURCES})
# Python's headers are not ours: no warnings from them.
target_include_directories(dem_server SYSTEM PUBLIC ${_py_dirs})
target_link_libraries(dem_server PUBLIC ${_py_ld})
target_compile_definitions(dem_server PUBLIC MPMDEM_HAVE_YADE
                           MPMDEM_PYTHON_DIR="${CMAKE_CURRENT_SOURCE_DIR}/python")

# The YADE unit tests are registered by tests/CMakeLists.txt's glob (tests/unit/test_yade_*.cpp
# registers the same tests without MPMDEM_HAVE_YADE, each skipped); the YADE integration tests
# are always registered and skip at run time (tests/integration/needs.sh).
