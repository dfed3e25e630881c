# mpm_app against the GPU backend's host batch path (coupling.cuda.device: host) on 2 server
# ranks: the same bits as the native backend; device: gpu without a GPU refused (issue 39).
mpmdem_test(NAME mpm_cuda_host_block COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/mpm_cuda.sh
            TIMEOUT 180 LABELS integration no_asan SERIAL)
