// The elastic stub backend: each RVE is a point of linear-elastic continuum with the same
// objective update as mpm_app's local `linear_elastic` model (mpmdem::elastic::ElasticLaw),
// so swapping the local model for `remote` + this backend gives the same stresses. It lets
// the coupling (and the MPM) be verified before YADE enters.
//
// Optional outputs: none. Rotation, porosity, coordination and unbalanced force are not
// defined for a continuum point, so the server advertises no output capability
// (dem::backend_outputs, coupling_rules.hpp), a scene that asks for them is refused when it
// is loaded, and those reply fields stay zero.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "backend.hpp"
#include "mpmdem/config/schema.hpp"

namespace mpmdem::dem {

struct ElasticParams {
  double youngs_modulus = 1e7;  // coupling.elastic.youngs_modulus [Pa]
  double poisson_ratio = 0.3;   // coupling.elastic.poisson_ratio [-]
};

class ElasticBackend : public RveBackend {
 public:
  explicit ElasticBackend(const ElasticParams& params);
  std::string name() const override { return "elastic"; }
  void setup(const BackendContext& ctx) override;
  void initialise(const protocol::RveInit* init, protocol::RveReply* reply) override;
  void step(const protocol::ControlHeader& header, const protocol::RveRequest* req,
            protocol::RveReply* reply) override;
  // One binary file per rank: <dir>/elastic_rank<r>.bin (first RVE, count, stresses).
  void checkpoint(const std::filesystem::path& dir) override;
  void restore(const std::filesystem::path& dir) override;
  std::string export_rve(std::uint64_t gid) override;
  void adopt(std::uint64_t first_rve, std::uint64_t n_rve,
             std::map<std::uint64_t, std::string> incoming) override;

 private:
  void fill_reply(std::size_t i, protocol::RveReply& reply) const;
  std::filesystem::path checkpoint_file(const std::filesystem::path& dir) const;

  ElasticParams params_;
  BackendContext ctx_;
  std::vector<Eigen::Matrix3d> sigma_;  // Cauchy stress per owned RVE [Pa]
};

std::unique_ptr<RveBackend> make_elastic_backend(const config::Config& cfg);

}  // namespace mpmdem::dem
