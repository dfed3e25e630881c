// The elastic stub backend: see elastic_backend.hpp.
#include "backends/elastic_backend.hpp"

#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>

#include "elastic_law.hpp"

namespace mpmdem::dem {

namespace {

using RowMajor3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
constexpr char kFileMagic[8] = {'M', 'P', 'M', 'D', 'E', 'L', 'A', '1'};

}  // namespace

ElasticBackend::ElasticBackend(const ElasticParams& params) : params_(params) {}

void ElasticBackend::setup(const BackendContext& ctx) {
  ctx_ = ctx;
  sigma_.assign(ctx.n_rve, Eigen::Matrix3d::Zero());
}

void ElasticBackend::fill_reply(std::size_t i, protocol::RveReply& reply) const {
  std::memset(&reply, 0, sizeof reply);
  Eigen::Map<RowMajor3>(reply.stress) = sigma_[i];
  const elastic::ElasticLaw law{params_.youngs_modulus, params_.poisson_ratio};
  reply.stiffness = law.constrained_modulus();
  reply.status = static_cast<std::int32_t>(sigma_[i].allFinite() ? protocol::RveStatus::kOk
                                                                 : protocol::RveStatus::kNonFinite);
}

void ElasticBackend::initialise(const protocol::RveInit* init, protocol::RveReply* reply) {
  for (std::size_t i = 0; i < sigma_.size(); ++i) {
    sigma_[i] = Eigen::Map<const RowMajor3>(init[i].stress);
    fill_reply(i, reply[i]);
  }
}

void ElasticBackend::step(const protocol::ControlHeader& /*header*/,
                          const protocol::RveRequest* req, protocol::RveReply* reply) {
  const elastic::ElasticLaw law{params_.youngs_modulus, params_.poisson_ratio};
  for (std::size_t i = 0; i < sigma_.size(); ++i) {
    if (!(req[i].flags & protocol::kFlagQueryOnly)) {
      const Eigen::Matrix3d dF = Eigen::Map<const RowMajor3>(req[i].dF);
      sigma_[i] = law.update(sigma_[i], dF);
    }
    fill_reply(i, reply[i]);
  }
}

std::filesystem::path ElasticBackend::checkpoint_file(const std::filesystem::path& dir) const {
  return dir / ("elastic_rank" + std::to_string(ctx_.rank) + ".bin");
}

void ElasticBackend::checkpoint(const std::filesystem::path& dir) {
  const auto file = checkpoint_file(dir);
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error("cannot write elastic checkpoint " + file.string());
  const std::uint64_t header[2] = {ctx_.first_rve, ctx_.n_rve};
  out.write(kFileMagic, sizeof kFileMagic);
  out.write(reinterpret_cast<const char*>(header), sizeof header);
  for (const auto& s : sigma_) {
    const RowMajor3 row = s;
    out.write(reinterpret_cast<const char*>(row.data()), 9 * sizeof(double));
  }
  if (!out) throw std::runtime_error("error while writing elastic checkpoint " + file.string());
}

void ElasticBackend::restore(const std::filesystem::path& dir) {
  const auto file = checkpoint_file(dir);
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    throw std::runtime_error("no elastic checkpoint " + file.string() +
                             " (was it written by a server with the same number of ranks?)");
  }
  char magic[sizeof kFileMagic] = {};
  std::uint64_t header[2] = {0, 0};
  in.read(magic, sizeof magic);
  in.read(reinterpret_cast<char*>(header), sizeof header);
  if (!in || std::memcmp(magic, kFileMagic, sizeof magic) != 0) {
    throw std::runtime_error(file.string() + " is not an elastic-backend checkpoint");
  }
  if (header[0] != ctx_.first_rve || header[1] != ctx_.n_rve) {
    throw std::runtime_error(file.string() + " holds RVEs [" + std::to_string(header[0]) + ", " +
                             std::to_string(header[0] + header[1]) + ") but this rank owns [" +
                             std::to_string(ctx_.first_rve) + ", " +
                             std::to_string(ctx_.first_rve + ctx_.n_rve) +
                             "): restore with the same RVE count and server ranks");
  }
  for (auto& s : sigma_) {
    RowMajor3 row;
    in.read(reinterpret_cast<char*>(row.data()), 9 * sizeof(double));
    s = row;
  }
  if (!in) throw std::runtime_error(file.string() + " is truncated");
}

std::unique_ptr<RveBackend> make_elastic_backend(const config::Config& cfg) {
  ElasticParams p;
  p.youngs_modulus = cfg.number("coupling.elastic.youngs_modulus");
  p.poisson_ratio = cfg.number("coupling.elastic.poisson_ratio");
  return std::make_unique<ElasticBackend>(p);
}

}  // namespace mpmdem::dem
