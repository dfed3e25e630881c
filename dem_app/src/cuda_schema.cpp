// Keys of `coupling.cuda.*`: see cuda_schema.hpp. Read by backends/batch/cuda_backend.cpp.
#include "cuda_schema.hpp"

namespace mpmdem {

using config::key;
using config::Type;

void add_cuda_keys(config::Schema& s) {
  s.add(key("coupling.cuda", Type::kMap, "",
            "settings of the GPU backend (backend: cuda; its physics, packings and substep "
            "rule are coupling.native.*, docs/dem_backend.md)"));
  s.add(key("coupling.cuda.device", Type::kEnum, "",
            "gpu: each dem_app rank steps its RVEs on one GPU (refused at start where none is "
            "visible or dem_app was built without CUDA); host: the same batch code on the "
            "CPU (for machines without a GPU, and CI)")
            .def("gpu")
            .one_of({"gpu", "host"}));
  s.add(key("coupling.cuda.gpu", Type::kInt, "",
            "CUDA device index of each rank; -1: the rank's number modulo the visible devices")
            .def("-1")
            .ge(-1));
  s.add(key("coupling.cuda.threads_per_block", Type::kInt, "",
            "threads of the thread block that steps one RVE")
            .def("128")
            .ge(32)
            .le(1024));
  s.add(key("coupling.cuda.contacts_per_sphere", Type::kDouble, "-",
            "contact slots per sphere in the batch (at least 128 per RVE; an RVE that needs "
            "more stops the run naming this key)")
            .def("4")
            .gt(0));
  s.add(key("coupling.cuda.pairs_per_sphere", Type::kDouble, "-",
            "Verlet pair slots per sphere in the batch (an RVE that needs more stops the run "
            "naming this key)")
            .def("12")
            .gt(0));
}

}  // namespace mpmdem
