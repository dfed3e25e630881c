# The GPU backend's device kernel (dem_app/src/backends/batch/batch_device.cu): the same
# physics headers as the host batch path, compiled for MPMDEM_CUDA_ARCHITECTURES (default 90,
# Hopper) with --fmad=false (no FMA contraction, as the host's -ffp-contract=off: the device
# gives the host's bits) and the CUDA runtime linked statically (a dem_app that runs on a GPU
# host without the toolkit).
if(NOT MPMDEM_WITH_CUDA)
  return()
endif()
add_library(dem_cuda STATIC src/backends/batch/batch_device.cu)
target_include_directories(dem_cuda PRIVATE src ${PROJECT_SOURCE_DIR}/interface/include)
target_link_libraries(dem_cuda PRIVATE Eigen3::Eigen)
target_compile_options(dem_cuda PRIVATE $<$<COMPILE_LANGUAGE:CUDA>:--fmad=false -Xcompiler=-fno-math-errno>)
set_target_properties(dem_cuda PROPERTIES CUDA_RUNTIME_LIBRARY Static
                                          POSITION_INDEPENDENT_CODE ON)
target_link_libraries(dem_server PUBLIC dem_cuda CUDA::cudart_static)
target_compile_definitions(dem_server PRIVATE MPMDEM_HAVE_CUDA)
target_compile_options(dem_cuda PRIVATE $<$<COMPILE_LANGUAGE:CUDA>:-Xcompiler=-Wall,-Wextra>)
if(MPMDEM_WERROR)
  target_compile_options(dem_cuda PRIVATE $<$<COMPILE_LANGUAGE:CUDA>:--Werror=all-warnings>)
endif()
