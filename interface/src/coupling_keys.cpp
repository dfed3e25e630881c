// The generic keys of the shared `coupling:` section and their canonical text: see
// mpmdem/coupling_keys.hpp.
#include "mpmdem/coupling_keys.hpp"

#include "mpmdem/protocol.hpp"

namespace mpmdem {

using config::key;
using config::Type;

namespace {
// Output names in the order of their protocol::OutputBits.
const char* const kOutputNames[] = {"rotation", "porosity", "coordination", "unbalanced_force"};
static_assert(sizeof(kOutputNames) / sizeof(kOutputNames[0]) == 4);
}  // namespace

void add_generic_coupling_keys(config::Schema& s, const std::vector<std::string>& backends) {
  auto section = key("coupling", Type::kMap, "",
                     "settings shared by mpm_app and dem_app (needed by constitutive.model "
                     "remote); both programs hash this section (docs/protocol.md) and refuse "
                     "to couple when the hashes differ");
  if (backends.empty()) {
    section.open_sections(
        "the section of a DEM backend (elastic, yade, native, cuda), validated by dem_app "
        "(`dem_app --check-config`; its keys: docs/config_reference_dem.md)");
  }
  s.add(section);
  if (backends.empty()) {
    s.add(key("coupling.backend", Type::kString, "",
              "RVE backend the DEM server must run (the server checks that it has it: "
              "`dem_app --list-backends`)")
              .def("elastic")
              .not_empty());
  } else {
    s.add(key("coupling.backend", Type::kEnum, "", "RVE backend the DEM server must run")
              .def("elastic")
              .one_of(backends));
  }
  s.add(key("coupling.outputs", Type::kStringList, "",
            "per-RVE outputs the server computes and returns (only these; only outputs the "
            "backend computes: none for elastic)")
            .def("[]")
            .one_of({kOutputNames[0], kOutputNames[1], kOutputNames[2], kOutputNames[3]}));
  s.add(key("coupling.service_name", Type::kString, "",
            "name the server publishes its MPI port under (ompi-server)")
            .def("mpmdem")
            .not_empty());
  s.add(key("coupling.connect_timeout_s", Type::kDouble, "s",
            "how long mpm_app waits for the server before giving up")
            .def("60")
            .gt(0));
  s.add(key("coupling.peer_timeout_s", Type::kDouble, "s",
            "longest mpm_app waits for one exchange with the DEM server before it gives up "
            "naming the server ranks it cannot probe (a rank on another host that died, hangs "
            "or was cut off: detected after this long); ranks on mpm_app's host are probed "
            "every 0.25 s and a dead one ends the wait at once. Raise it above the slowest "
            "legitimate exchange (kInitialise of a rank's RVEs, a checkpoint). 0: no limit")
            .def("300")
            .ge(0));
  s.add(key("coupling.port_file", Type::kString, "",
            "file holding the server's MPI port name, relative to the run directory; "
            "removed when the server closes")
            .def("dem_port.txt")
            .not_empty());
  s.add(key("coupling.lazy_tolerance", Type::kDouble, "-",
            "lazy RVE evaluation: an RVE whose accumulated dF since its last evaluation "
            "differs from the identity by at most this (largest |dF_acc - I| component) is "
            "not run; its stress is held and the accumulated dF applied when it next runs. "
            "0: every RVE runs every step")
            .def("0")
            .ge(0)
            .lt(1));
  s.add(key("coupling.rve_order", Type::kEnum, "",
            "order of the RVEs on the wire, and so which material points each DEM rank owns "
            "(docs/protocol.md, Partitions): interleaved spreads every rank's RVEs over the "
            "whole body, contiguous gives each rank one region (RVE costs follow the local "
            "strain rate, so regions differ). Results do not depend on it")
            .def("interleaved")
            .one_of({"interleaved", "contiguous"}));
  s.add(key("coupling.load_balance", Type::kMap, "",
            "cost-aware load balance of the RVEs over the server ranks (docs/protocol.md)"));
  s.add(key("coupling.load_balance.threshold", Type::kDouble, "-",
            "rebalance when the slowest rank's smoothed RVE cost exceeds the mean rank's by "
            "more than this fraction (0.1: 10 %); 0 turns load balancing off. Moving a YADE "
            "RVE reloads its scene, which changes its summation order (~1e-11 relative), and "
            "the moves follow measured times: runs with it on are not bitwise repeatable")
            .def("0")
            .ge(0));
  s.add(key("coupling.load_balance.min_interval_steps", Type::kInt, "steps",
            "at least this many coupling steps between two rebalances (and before the first)")
            .def("50")
            .ge(1));
  s.add(key("coupling.load_balance.smoothing", Type::kDouble, "-",
            "weight of the newest cost in the exponentially smoothed per-RVE cost (1: only "
            "the last step)")
            .def("0.2")
            .gt(0)
            .le(1));
}

std::string coupling_canonical_text(const config::Config& cfg) {
  static const config::Schema generic = [] {
    config::Schema s;
    add_generic_coupling_keys(s, {});
    return s;
  }();
  return config::canonical_section_text(generic, cfg.root()["coupling"], "coupling");
}

std::uint32_t coupling_output_bit(const std::string& name) {
  for (std::uint32_t i = 0; i < 4; ++i) {
    if (name == kOutputNames[i]) return 1u << i;
  }
  return 0;
}

std::string coupling_output_names(std::uint32_t bits) {
  std::string names;
  for (std::uint32_t i = 0; i < 4; ++i) {
    if (bits & (1u << i)) names += (names.empty() ? "" : ", ") + std::string(kOutputNames[i]);
  }
  return names.empty() ? "none" : names;
}

std::uint32_t coupling_output_bits(const config::Config& cfg) {
  std::uint32_t bits = 0;
  for (const std::string& name : cfg.strings("coupling.outputs")) bits |= coupling_output_bit(name);
  static_assert(protocol::kOutputRotation == 1u << 0 && protocol::kOutputPorosity == 1u << 1 &&
                protocol::kOutputCoordination == 1u << 2 &&
                protocol::kOutputUnbalancedForce == 1u << 3 && protocol::kKnownOutputs == 0xFu);
  return bits;
}

}  // namespace mpmdem
