# element_test (dem_app/element_test) against a real dem_app: an oedometric test on the
# elastic backend checked against the closed-form Hencky answer, a triaxial test whose
# mixed control must hold the lateral stress of the elastic backend, and (when the YADE backend
# is built) scripts/element_test on configs/element_test/quick.yaml (the four paths through
# the real YADE server on a 40-sphere packing; outputs checked for physics) and the same
# script with --backend native (isotropic and drained triaxial paths). Included from
# tests/CMakeLists.txt; tests/integration/element_test.sh kills every process it starts.
set(_et ${CMAKE_CURRENT_LIST_DIR}/element_test.sh)
foreach(_case elastic_oedometric elastic_triaxial)
  mpmdem_test(NAME element_test_${_case} COMMAND bash ${_et} ${_case} TIMEOUT 240 SERIAL)
endforeach()
# The YADE case runs the real YADE server; the native case exports the YADE packing to the
# native format (needs YADE too). Normal pass only: the native C++ is covered by ASan unit
# tests, the driver's C++ by the elastic cases, the YADE backend's by the YadeBackend units.
foreach(_case yade_script native_script)
  mpmdem_test(NAME element_test_${_case} NEEDS yade COMMAND bash ${_et} ${_case}
              TIMEOUT 240 LABELS integration no_asan SERIAL)
endforeach()
# scripts/element_seed_study's config and statistics steps (no DEM run): fast, normal pass only
# (Python only).
mpmdem_test(NAME element_seed_study_steps COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/element_seeds.sh
            TIMEOUT 60 LABELS integration no_asan)
# scripts/rve_mu_i_study: its config and fit steps (no DEM run; Python only), and the study end
# to end on 4 of the column's RVEs at three inertial numbers (YADE builds the packings; the
# friction must rise with I). Normal pass only: the native C++ is covered by ASan units.
mpmdem_test(NAME rve_mu_i_study_steps COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/rve_mu_i.sh steps
            TIMEOUT 60 LABELS integration no_asan)
mpmdem_test(NAME rve_mu_i_study_run NEEDS yade COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/rve_mu_i.sh run
            TIMEOUT 300 LABELS integration no_asan SERIAL)
