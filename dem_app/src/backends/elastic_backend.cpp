// The elastic stub backend: see elastic_backend.hpp.
#include "backends/elastic_backend.hpp"

#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>

#include "mpmdem/laws/elastic_law.hpp"

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
  using Clock = std::chrono::steady_clock;
  for (std::size_t i = 0; i < sigma_.size(); ++i) {
    const auto t0 = Clock::now();
    if (!(req[i].flags & (protocol::kFlagQueryOnly | protocol::kFlagSkip))) {
      const Eigen::Matrix3d dF = Eigen::Map<const RowMajor3>(req[i].dF);
      sigma_[i] = law.update(sigma_[i], dF);
    }
    fill_reply(i, reply[i]);
    reply[i].cost_s = std::chrono::duration<double>(Clock::now() - t0).count();
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
  // Any partition of the same RVEs may have written the files (load balance moves RVEs):
  // read them all and keep the RVEs of this rank's range.
  std::vector<bool> found(ctx_.n_rve, false);
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("elastic_rank", 0) != 0 || entry.path().extension() != ".bin") continue;
    const auto file = entry.path();
    std::ifstream in(file, std::ios::binary);
    char magic[sizeof kFileMagic] = {};
    std::uint64_t header[2] = {0, 0};
    in.read(magic, sizeof magic);
    in.read(reinterpret_cast<char*>(header), sizeof header);
    if (!in || std::memcmp(magic, kFileMagic, sizeof magic) != 0) {
      throw std::runtime_error(file.string() + " is not an elastic-backend checkpoint");
    }
    for (std::uint64_t k = 0; k < header[1]; ++k) {
      RowMajor3 row;
      in.read(reinterpret_cast<char*>(row.data()), 9 * sizeof(double));
      if (!in) throw std::runtime_error(file.string() + " is truncated");
      const std::uint64_t gid = header[0] + k;
      if (gid >= ctx_.first_rve && gid < ctx_.first_rve + ctx_.n_rve) {
        sigma_[gid - ctx_.first_rve] = row;
        found[gid - ctx_.first_rve] = true;
      }
    }
  }
  for (std::size_t i = 0; i < found.size(); ++i) {
    if (!found[i]) {
      throw std::runtime_error("no elastic checkpoint in " + dir.string() + " holds RVE " +
                               std::to_string(ctx_.first_rve + i) +
                               ": restore with the same RVE count");
    }
  }
}

std::string ElasticBackend::export_rve(std::uint64_t gid) {
  if (gid < ctx_.first_rve || gid >= ctx_.first_rve + ctx_.n_rve) {
    throw std::logic_error("elastic backend: export of RVE " + std::to_string(gid) +
                           " that this rank does not own");
  }
  const RowMajor3 row = sigma_[gid - ctx_.first_rve];
  return std::string(reinterpret_cast<const char*>(row.data()), 9 * sizeof(double));
}

void ElasticBackend::adopt(std::uint64_t first_rve, std::uint64_t n_rve,
                           std::map<std::uint64_t, std::string> incoming) {
  std::vector<Eigen::Matrix3d> next(n_rve);
  for (std::uint64_t k = 0; k < n_rve; ++k) {
    const std::uint64_t gid = first_rve + k;
    if (gid >= ctx_.first_rve && gid < ctx_.first_rve + ctx_.n_rve) {
      next[k] = sigma_[gid - ctx_.first_rve];
      continue;
    }
    const auto it = incoming.find(gid);
    if (it == incoming.end() || it->second.size() != 9 * sizeof(double)) {
      throw std::runtime_error("elastic backend: no valid state received for RVE " +
                               std::to_string(gid));
    }
    RowMajor3 row;
    std::memcpy(row.data(), it->second.data(), 9 * sizeof(double));
    next[k] = row;
  }
  sigma_ = std::move(next);
  ctx_.first_rve = first_rve;
  ctx_.n_rve = n_rve;
}

std::unique_ptr<RveBackend> make_elastic_backend(const config::Config& cfg) {
  ElasticParams p;
  p.youngs_modulus = cfg.number("coupling.elastic.youngs_modulus");
  p.poisson_ratio = cfg.number("coupling.elastic.poisson_ratio");
  return std::make_unique<ElasticBackend>(p);
}

}  // namespace mpmdem::dem
