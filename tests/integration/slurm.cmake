# The SLURM batch script: bash -n and a dry run in a fake 3-node allocation (no SLURM needed).
add_test(NAME slurm_batch_dry_run
         COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/slurm_dry_run.sh)
set_tests_properties(slurm_batch_dry_run PROPERTIES TIMEOUT 30 LABELS "integration;no_asan"
  ENVIRONMENT "MPMDEM_BIN=${PROJECT_BINARY_DIR};MPMDEM_SRC=${PROJECT_SOURCE_DIR}")
