# element_test (dem_app/element_test) against a real dem_app: an oedometric test on the
# elastic backend checked against the closed-form Hencky answer, a triaxial test whose
# mixed control must hold the lateral stress of the elastic backend, and (when the YADE backend
# is built) scripts/element_test on configs/element_test/quick.yaml (the four paths through
# the real YADE server on a 40-sphere packing; outputs checked for physics) and the same
# script with --backend native (isotropic and drained triaxial paths). Included from
# tests/CMakeLists.txt; tests/integration/element_test.sh kills every process it starts.
set(_et ${CMAKE_CURRENT_LIST_DIR}/element_test.sh)
set(_et_env "MPMDEM_BIN=${PROJECT_BINARY_DIR}" "MPMDEM_SRC=${PROJECT_SOURCE_DIR}")
set(_et_cases elastic_oedometric elastic_triaxial)
if(MPMDEM_WITH_YADE AND EXISTS /usr/bin/yade AND EXISTS /usr/bin/python3.11-config)
  # native_script: the YADE packing is exported to the native format (needs YADE too)
  list(APPEND _et_cases yade_script native_script)
endif()
foreach(_case ${_et_cases})
  add_test(NAME element_test_${_case} COMMAND bash ${_et} ${_case})
  set_tests_properties(element_test_${_case} PROPERTIES TIMEOUT 240 LABELS integration
                       ENVIRONMENT "${_et_env}" RUN_SERIAL TRUE)
endforeach()
# The native case tests the script's wiring (export, lock, scene); the native C++ is covered
# by ASan unit tests: normal pass only.
# So does the YADE case (CI time): the driver's C++ runs under ASan in the elastic cases, the
# YADE backend's in the YadeBackend units.
foreach(_case native_script yade_script)
  if(TEST element_test_${_case})
    set_tests_properties(element_test_${_case} PROPERTIES LABELS "integration;no_asan")
  endif()
endforeach()
# scripts/element_seed_study's config and statistics steps (no DEM run): fast, normal pass only
# (Python only).
add_test(NAME element_seed_study_steps COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/element_seeds.sh)
set_tests_properties(element_seed_study_steps PROPERTIES TIMEOUT 60 LABELS "integration;no_asan"
                     ENVIRONMENT "${_et_env}")
# scripts/rve_mu_i_study: its config and fit steps (no DEM run; Python only), and the study end
# to end on 4 of the column's RVEs at three inertial numbers (YADE builds the packings; the
# friction must rise with I). Normal pass only: the native C++ is covered by ASan units.
add_test(NAME rve_mu_i_study_steps COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/rve_mu_i.sh steps)
set_tests_properties(rve_mu_i_study_steps PROPERTIES TIMEOUT 60 LABELS "integration;no_asan"
                     ENVIRONMENT "${_et_env}")
if(MPMDEM_WITH_YADE AND EXISTS /usr/bin/yade AND EXISTS /usr/bin/python3.11-config)
  add_test(NAME rve_mu_i_study_run COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/rve_mu_i.sh run)
  set_tests_properties(rve_mu_i_study_run PROPERTIES TIMEOUT 300 LABELS "integration;no_asan"
                       ENVIRONMENT "${_et_env}" RUN_SERIAL TRUE)
endif()
