# DEM on several nodes (issue 36): hosts A-D as network namespaces; one dem_app job per DEM
# host, joined by mpm_app into one partition. Needs root: otherwise skipped (exit 77).
#   multinode_netns: A | B, C, D (2 ranks each) bitwise equal to 6 ranks on one host, each
#     host ran its ranks, --mpm-hosts checked (items 1-2).
mpmdem_test(NAME multinode_netns COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/multinode.sh
            TIMEOUT 120 LABELS integration no_asan SERIAL)
#   multinode_heal_netns: --on-fault resume; C's link cut after the first complete
#     checkpoint: the run continues on B and D by itself, bitwise equal to an uninterrupted
#     run, the fault in summary.json (item 3).
mpmdem_test(NAME multinode_heal_netns COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/multinode_heal.sh
            TIMEOUT 120 LABELS integration no_asan SERIAL)
#   multinode_local_jobs: the same join with the jobs on this machine (no root needed): 2 jobs
#     bitwise equal to 1, a job that never comes, jobs started for another count.
mpmdem_test(NAME multinode_local_jobs COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/multinode_local.sh
            TIMEOUT 90 LABELS integration no_asan SERIAL)
