# The system tests: every test that runs the programs or the scripts end to end, in one table
# grouped by what it checks. Each row is one mpmdem_test() (tests/CMakeLists.txt: registered
# on every machine; NEEDS = a dependency whose absence reports the test skipped, never passed;
# no_asan = normal pass only, each such test's C++ is covered under ASan by the units or
# another test named in its comment). Every script stops the processes it starts by PID.
# The first group checks the docs and the sources, not the programs' runs.
set(_it ${CMAKE_CURRENT_LIST_DIR})

# ---- The docs and the sources ------------------------------------------------------------
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
# One figure, one place: every figure the README and the docs quote from docs/results.md
# equals the value there (links, anchors and reachability: docs_links_and_commands, above).
add_test(NAME docs_figures_match
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_LIST_DIR}/docs_figures.py ${PROJECT_SOURCE_DIR})
set_tests_properties(docs_figures_match PROPERTIES LABELS unit)

# ---- The coupling: handshake, exchange, faults, the protocol as documented ----------------
# Two-process coupling tests (issue 2, item 8): ompi-server, dem_app and a client through
# coupling_tests.sh; rve_test_client is a stand-in for mpm_app that checks every reply
# against the elastic law.
add_executable(rve_test_client ${_it}/rve_test_client.cpp)
target_link_libraries(rve_test_client PRIVATE dem_server)
foreach(_case
    client_elastic_1rank client_elastic_2ranks client_checkpoint_restore client_abort client_backend_error killed_client
    hash_mismatch version_mismatch no_server_client no_client_server
    mpm_no_server mpm_hash_mismatch swap_sides)
  mpmdem_test(NAME coupling_${_case} COMMAND bash ${_it}/coupling_tests.sh ${_case} SERIAL)
endforeach()
set_tests_properties(coupling_swap_sides PROPERTIES TIMEOUT 300)
# A Python client written from docs/protocol.md alone drives dem_app --backend elastic
# (issue 37, item 8), so that the doc and the code cannot drift apart.
mpmdem_test(NAME protocol_reference_client NEEDS mpi4py SERIAL TIMEOUT 120
            COMMAND bash ${_it}/reference_client.sh)
# Peer faults (issue 6, item 5): a DEM rank killed mid-run is named, a fault checkpoint is
# written, exit 4 within a bound, nothing left running, and --resume reaches the same end
# state. Normal pass only: the C++ fault path runs under ASan in the PeerWatch units and
# coupling_killed_client.
mpmdem_test(NAME fault_killed_dem_rank COMMAND bash ${_it}/fault.sh elastic
            TIMEOUT 180 LABELS integration no_asan SERIAL)
# Resume on another DEM rank count (issue 16, item 2): written with 2 ranks, resumed with 1
# and with 3, bitwise equal to the uninterrupted run. The YADE case runs as part of
# concurrent_runs_yade; `bash tests/integration/resume_ranks.sh yade` runs it in full by hand.
mpmdem_test(NAME resume_ranks_elastic COMMAND bash ${_it}/resume_ranks.sh elastic
            TIMEOUT 120 LABELS integration no_asan SERIAL)
# Lazy RVE evaluation (issue 6, item 2) on the tiny YADE column, with an exact resume.
mpmdem_test(NAME lazy_yade_column NEEDS yade COMMAND bash ${_it}/lazy.sh
            TIMEOUT 600 LABELS integration no_asan SERIAL)
# Load balance with RVE migration (issue 5, item 4) and node-partition hostfiles (item 5).
mpmdem_test(NAME load_balance_elastic COMMAND bash ${_it}/load_balance.sh elastic TIMEOUT 300 SERIAL)
mpmdem_test(NAME load_balance_yade NEEDS yade COMMAND bash ${_it}/load_balance.sh yade
            TIMEOUT 600 LABELS integration no_asan SERIAL)
# Many runs at once (issue 16, item 4): two scripts/run of one scene started together from
# one checkout both finish, without port or run-directory collisions; the YADE case builds
# its packing library once.
mpmdem_test(NAME concurrent_runs_elastic COMMAND bash ${_it}/concurrent.sh elastic
            TIMEOUT 120 LABELS integration no_asan SERIAL)
mpmdem_test(NAME concurrent_runs_yade NEEDS yade COMMAND bash ${_it}/concurrent.sh yade
            TIMEOUT 180 LABELS integration no_asan SERIAL)

# ---- Several hosts and clusters ----------------------------------------------------------
# MPM and DEM on different hosts (issue 16, item 3): hosts A, B, C as network namespaces;
# A | B bitwise equal to the single-host run; B's link cut mid-run, then resumed on A | C.
# Needs root: otherwise skipped (multihost.sh exits 77).
mpmdem_test(NAME multihost_netns COMMAND bash ${_it}/multihost.sh
            TIMEOUT 180 LABELS integration no_asan SERIAL)
# DEM on several nodes (issue 36): hosts A-D as network namespaces, one dem_app job per DEM
# host joined by mpm_app into one partition (root needed, else skipped):
#   multinode_netns: A | B, C, D (2 ranks each) bitwise equal to 6 ranks on one host, each
#     host ran its ranks, --mpm-hosts checked (items 1-2);
#   multinode_heal_netns: --on-fault resume; C's link cut after the first complete
#     checkpoint: the run continues on B and D by itself, bitwise equal to an uninterrupted
#     run, the fault in summary.json (item 3);
#   multinode_local_jobs: the same join with the jobs on this machine (no root needed): 2 jobs
#     bitwise equal to 1, a job that never comes, jobs started for another count.
mpmdem_test(NAME multinode_netns COMMAND bash ${_it}/multinode.sh
            TIMEOUT 120 LABELS integration no_asan SERIAL)
mpmdem_test(NAME multinode_heal_netns COMMAND bash ${_it}/multinode_heal.sh
            TIMEOUT 120 LABELS integration no_asan SERIAL)
mpmdem_test(NAME multinode_local_jobs COMMAND bash ${_it}/multinode_local.sh
            TIMEOUT 90 LABELS integration no_asan SERIAL)
# The SLURM batch script: bash -n and a dry run in a fake 3-node allocation (no SLURM needed).
mpmdem_test(NAME slurm_batch_dry_run COMMAND bash ${_it}/slurm_dry_run.sh
            TIMEOUT 30 LABELS integration no_asan)

# ---- Scenes end to end -------------------------------------------------------------------
# Results bit for bit unchanged (tests/golden/golden.sh): each scene's physics hashed against
# tests/golden/hashes.txt, recorded before changes that must not change results.
foreach(_scene default elastic local apic xpic)
  mpmdem_test(NAME golden_${_scene}_bitwise
              COMMAND bash ${PROJECT_SOURCE_DIR}/tests/golden/golden.sh ${_scene}
              TIMEOUT 240 LABELS integration no_asan SERIAL)
endforeach()
mpmdem_test(NAME golden_yade_bitwise NEEDS yade
            COMMAND bash ${PROJECT_SOURCE_DIR}/tests/golden/golden.sh yade
            TIMEOUT 240 LABELS integration no_asan SERIAL)
# mpm_app against 2 server ranks on a tiny scene: native (issue 15, item 5), YADE (issue 3,
# item 9; its C++ under ASan in the YadeBackend units and the coupling_client_* tests), the
# GPU backend's host batch path (the same bits as native; device: gpu without a GPU refused;
# issue 39).
mpmdem_test(NAME mpm_native_block_2ranks COMMAND bash ${_it}/mpm_block.sh native
            TIMEOUT 120 LABELS integration no_asan SERIAL)
mpmdem_test(NAME mpm_yade_block_2ranks NEEDS yade COMMAND bash ${_it}/mpm_block.sh yade
            TIMEOUT 300 LABELS integration no_asan SERIAL)
mpmdem_test(NAME mpm_cuda_host_block COMMAND bash ${_it}/mpm_cuda.sh
            TIMEOUT 180 LABELS integration no_asan SERIAL)
# A minimal multiscale column collapse and its exact resume from a checkpoint (issue 4,
# items 6-7).
mpmdem_test(NAME column_yade_tiny_resume NEEDS yade COMMAND bash ${_it}/column_yade.sh
            TIMEOUT 600 LABELS integration no_asan SERIAL)
# Consolidation once per (packing, stress), and its cache on disk reused by a second run with
# the same results (issue 36, item 5).
mpmdem_test(NAME consolidation_cache COMMAND bash ${_it}/consolidation_cache.sh
            TIMEOUT 120 LABELS integration no_asan SERIAL)
# A native scene builds and exports its packings from coupling.native.packing_spec (issue 15);
# YADE builds the packings.
mpmdem_test(NAME native_packing_spec NEEDS yade COMMAND bash ${_it}/native_packing_spec.sh
            TIMEOUT 180 LABELS integration no_asan SERIAL)
# The local column with mu(I) as shipped (issue 14, item 5: E_err < 2 %) against the same
# scene without mu(I) on 0.055 m cells, side by side (~90 s on 2 cores).
mpmdem_test(NAME mu_i_column COMMAND bash ${_it}/mu_i_column.sh
            TIMEOUT 600 PROCESSORS 2 LABELS integration no_asan)
# Issue 14, item 5: the local column's energy budget closes below 2 % with the APIC blend at a
# small velocity scale and a halved-twice time step (~15 s).
mpmdem_test(NAME energy_closure COMMAND bash ${_it}/energy_closure.sh
            TIMEOUT 180 LABELS integration no_asan)
# scripts/stability_suite --quick (local cases: stiffness sweep 1e6/1e9/1e11 Pa, column
# a = 0.5, elastic impact at 50 m/s, the forced-unstable column) and, with the YADE backend,
# the free-falling multiscale block and 1e-2 dF increments into a YADE RVE; the table is
# checked by stability_check.py (dt ~ 1/sqrt(E) from c = sqrt(M/rho), the unstable case
# detected with its point and step, no NaN/Inf in any output).
# stability_test(NAME CHECK_SET TIMEOUT NEEDS SUITE_ARGS...): the suite into
# test-runs/stability/CHECK_SET, then stability_check.py on its table with the suite's exit
# code; NEEDS: the dependency (needs.sh) or "none". (Newlines, not ';', separate the shell's
# commands: mpmdem_test's arguments are a CMake list.)
function(stability_test name check_set timeout needs)
  set(out ${PROJECT_BINARY_DIR}/test-runs/stability/${check_set})
  list(JOIN ARGN " " suite_args)
  set(needs_args "")
  if(NOT needs STREQUAL "none")
    set(needs_args NEEDS ${needs})
  endif()
  mpmdem_test(NAME ${name} ${needs_args}
    COMMAND sh -c "rm -rf \"$1\" && \"$2\" ${suite_args} --out \"$1\"\nrc=$?\n/usr/bin/python3 \"$3\" \"$1\" ${check_set} $rc"
            sh ${out} ${PROJECT_SOURCE_DIR}/scripts/stability_suite
            ${CMAKE_CURRENT_FUNCTION_LIST_DIR}/stability_check.py
    TIMEOUT ${timeout} LABELS integration no_asan SERIAL
    ENVIRONMENT "MPMDEM_SKIP_SETUP=1" "MPMDEM_BUILD_DIR=${PROJECT_BINARY_DIR}")
endfunction()
stability_test(stability_suite_quick quick 240 none --quick)
stability_test(stability_suite_yade yade 300 yade --only free_fall_rves,dF_1e-2)

# ---- Bad input ---------------------------------------------------------------------------
# Bad input, nothing lost (issue 6, item 4): broken scenes through scripts/run and mpm_app.
mpmdem_test(NAME bad_input_nothing_lost
            COMMAND /usr/bin/python3 ${_it}/bad_input.py ${PROJECT_BINARY_DIR} ${PROJECT_SOURCE_DIR}
            TIMEOUT 300 SERIAL)
# Validation is complete before anything runs (issue 35, item 3): a corpus of shipped scenes
# with one change each, every one breaking a different rule of either program, refused by
# scripts/run's check (exit 2, key, file and line; nothing written, nothing started). No MPI.
mpmdem_test(NAME bad_scenes_refused_up_front
            COMMAND /usr/bin/python3 ${_it}/bad_scenes.py ${PROJECT_BINARY_DIR} ${PROJECT_SOURCE_DIR}
            TIMEOUT 120)

# ---- The DEM side on its own: backends against each other, element tests ---------------
# Native vs YADE backend on one packing and one seeded dF sequence (issue 15, item 2), frict
# and frict_visco (e_n 0.5); tolerances in native_vs_yade.py. The YADE side runs as a Python
# module: no YADE backend build needed, only Debian's yade.
mpmdem_test(NAME native_vs_yade NEEDS yade-module COMMAND bash ${_it}/native_vs_yade.sh
            TIMEOUT 120 LABELS integration no_asan)
mpmdem_test(NAME native_vs_yade_visco NEEDS yade-module COMMAND bash ${_it}/native_vs_yade.sh 0.5
            TIMEOUT 120 LABELS integration no_asan)
# dem_app --backend yade over MPI (2 ranks, driven by element_test --test df_file) against a
# standalone one-process YADE script on the same 40-sphere packing and dF sequence: equal
# stresses to <= 1e-10 relative (issue 3, item 7).
mpmdem_test(NAME side_by_side_yade_standalone NEEDS yade COMMAND bash ${_it}/side_by_side.sh
            TIMEOUT 180 LABELS integration no_asan SERIAL)
# element_test (dem_app/element_test) against a real dem_app: an oedometric test on the
# elastic backend checked against the closed-form Hencky answer, a triaxial test whose mixed
# control must hold the lateral stress of the elastic backend; with YADE, scripts/element_test
# on configs/element_test/quick.yaml (the four paths through the real YADE server on a
# 40-sphere packing; outputs checked for physics) and the same with --backend native (its
# packing exported from YADE's). Normal pass only for those two: the native C++ under ASan in
# the units, the driver's C++ by the elastic cases, the YADE backend's by the YadeBackend units.
foreach(_case elastic_oedometric elastic_triaxial)
  mpmdem_test(NAME element_test_${_case} COMMAND bash ${_it}/element_test.sh ${_case}
              TIMEOUT 240 SERIAL)
endforeach()
foreach(_case yade_script native_script)
  mpmdem_test(NAME element_test_${_case} NEEDS yade COMMAND bash ${_it}/element_test.sh ${_case}
              TIMEOUT 240 LABELS integration no_asan SERIAL)
endforeach()
# Importing YADE leaves no folder in $TMPDIR or /tmp (yade_import_tmp.py says which and why).
# (Newlines, not ';', separate the shell's commands: mpmdem_test's arguments are a CMake list.)
mpmdem_test(NAME yade_import_leaves_no_temp NEEDS yade-module
  COMMAND sh -c "t=$(mktemp -d) && TMPDIR=$t /usr/bin/python3 \"$1\" \"$2\"\nrc=$?\nrm -rf $t\nexit $rc"
          sh ${_it}/yade_import_tmp.py ${PROJECT_SOURCE_DIR}/dem_app/python
  TIMEOUT 120 LABELS integration no_asan)

# ---- The study scripts (smoke tests; the studies themselves are too slow for CI) ----------
# scripts/error_vs_runtime: error against run time (issue 6, item 1).
mpmdem_test(NAME error_vs_runtime_study COMMAND bash ${_it}/error_study.sh
            TIMEOUT 300 LABELS integration no_asan SERIAL)
# scripts/grid_convergence_study (issue 14, item 4) on the two coarsest grids (the full study
# takes ~7 min: docs/transfers.md).
mpmdem_test(NAME grid_convergence_study_smoke COMMAND bash ${_it}/grid_convergence_study.sh
            TIMEOUT 180 LABELS integration no_asan)
# scripts/aspect_ratio_study (issue 14, item 9): one tiny scene (a = 1, shipped transfer, no
# cfl check).
mpmdem_test(NAME aspect_ratio_study_smoke COMMAND bash ${_it}/aspect_ratio_study.sh
            TIMEOUT 120 LABELS integration no_asan)
# Strong-scaling study, cost model and Amdahl fit (issue 5, items 2-3).
mpmdem_test(NAME scaling_study_elastic COMMAND bash ${_it}/scaling.sh
            TIMEOUT 300 LABELS integration no_asan SERIAL)
# scripts/element_seed_study's config and statistics steps (no DEM run; Python only).
mpmdem_test(NAME element_seed_study_steps COMMAND bash ${_it}/element_seeds.sh
            TIMEOUT 60 LABELS integration no_asan)
# scripts/rve_mu_i_study: its config and fit steps (no DEM run; Python only), and the study
# end to end on 4 of the column's RVEs at three inertial numbers (YADE builds the packings;
# the friction must rise with I).
mpmdem_test(NAME rve_mu_i_study_steps COMMAND bash ${_it}/rve_mu_i.sh steps
            TIMEOUT 60 LABELS integration no_asan)
mpmdem_test(NAME rve_mu_i_study_run NEEDS yade COMMAND bash ${_it}/rve_mu_i.sh run
            TIMEOUT 300 LABELS integration no_asan SERIAL)

# ---- The programs' listings --------------------------------------------------------------
# mpm_app --list-models prints every registered local model and remote (the registry survives
# the link: mpm_core is an OBJECT library), dem_app --list-backends the backends built in.
mpmdem_test(NAME programs_list_models_and_backends
  COMMAND bash ${_it}/program_listings.sh $<TARGET_FILE:mpm_app> $<TARGET_FILE:dem_app>
  TIMEOUT 30 LABELS integration)
