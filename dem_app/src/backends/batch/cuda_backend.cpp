// The GPU RVE backend: see cuda_backend.hpp.
#include "backends/batch/cuda_backend.hpp"

#include <chrono>
#include <cstring>
#include <iostream>
#include <stdexcept>

#include "backends/batch/batch_host.hpp"
#include "backends/native/cell_regularisation.hpp"
#include "backends/native/rve_reply.hpp"
#include "coupling_rules.hpp"

namespace mpmdem::dem {

CudaBackend::CudaBackend(const CudaParams& p)
    : p_(p), host_(p.native), driver_(p.native.substeps, p.native.ke_threshold) {
  threads_ = host_.threads();
}

CudaBackend::~CudaBackend() {
  if (rve_steps_ == 0) return;
  std::cerr << "dem_app rank " << ctx_.rank << ": cuda backend on "
            << (device_ ? device_->name() : std::string("the host (coupling.cuda.device: host)"))
            << ": " << rve_steps_ << " RVE updates, batch time " << batch_s_ << " s";
  if (device_) {
    const batch::TransferTally& t = device_->tally();
    std::cerr << " (kernels " << t.kernel_s << " s); host-device copies per step "
              << (t.steps ? static_cast<double>(t.copies) / static_cast<double>(t.steps) : 0.0)
              << " (" << t.copies << " copies, " << t.bytes << " bytes in " << t.steps
              << " steps), whole-state copies " << t.state_copies << " (" << t.state_bytes
              << " bytes)";
  }
  std::cerr << std::endl;
}

void CudaBackend::setup(const BackendContext& ctx) {
  ctx_ = ctx;
  host_.setup(ctx);
  driver_.forget();
  if (p_.on_gpu && !device_) {
    device_ = batch::DeviceBatch::create(p_.gpu, ctx.rank, p_.threads_per_block);
  }
}

void CudaBackend::pack() {
  batch_.pack(
      ctx_.n_rve, [&](std::size_t k) -> const native::RveRecord& { return host_.rve(k); },
      p_.capacity);
  if (device_) device_->upload(batch_);
  host_current_ = true;
}

void CudaBackend::sync_to_host() {
  if (host_current_) return;
  if (device_) device_->download(batch_);
  for (int r = 0; r < batch_.n_rve(); ++r) batch_.unpack(r, host_.rve(static_cast<std::size_t>(r)));
  host_current_ = true;
}

native::RveRecord CudaBackend::rve(std::size_t k) {
  sync_to_host();
  return host_.rve(k);
}

void CudaBackend::initialise(const protocol::RveInit* init, protocol::RveReply* reply) {
  host_.initialise(init, reply);
  driver_.initialised(reply, ctx_.n_rve, ctx_.first_rve);
  pack();
}

void CudaBackend::step(const protocol::ControlHeader& header, const protocol::RveRequest* req,
                       protocol::RveReply* reply) {
  driver_.step(header, req, reply, ctx_.n_rve, ctx_.first_rve, *this);
}

void CudaBackend::step_batch(const protocol::ControlHeader& header,
                             const std::vector<BatchUpdate>& updates, protocol::RveReply* reply,
                             double* kinetic) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const std::size_t n = ctx_.n_rve;
  std::vector<batch::StepIn>& in = batch_.in();
  std::int64_t active = 0;
  for (std::size_t k = 0; k < n; ++k) {
    batch::StepIn& s = in[k];
    std::memset(&s, 0, sizeof s);
    if (!updates[k].active) continue;
    s.flags = batch::kStepActive | (header.step % 10 == 0 ? batch::kStepTileCheck : 0);
    s.ns = updates[k].ns;
    if (updates[k].dF) std::memcpy(s.dF, updates[k].dF, sizeof s.dF);
    ++active;
  }
  const batch::BatchParams bp{p_.native.damping, p_.native.ke_threshold, p_.native.verlet_skin,
                              p_.native.stiffness ? 1 : 0, ctx_.outputs};
  if (device_) {
    device_->step(batch_, bp);
  } else {
    step_batch_host(batch_.view(), bp, threads_);
  }
  host_current_ = false;
  batch_s_ += std::chrono::duration<double>(Clock::now() - t0).count();
  rve_steps_ += active;
  bool repack = false;
  const std::vector<batch::StepOut>& out = batch_.out();
  for (std::size_t k = 0; k < n; ++k) {
    if (!(in[k].flags & batch::kStepActive)) continue;
    const batch::StepOut& o = out[k];
    if (o.error != batch::kErrNone) {
      const bool contacts = o.error == batch::kErrContacts;
      throw std::runtime_error("cuda backend: RVE " + std::to_string(ctx_.first_rve + k) +
                               " step " + std::to_string(header.step) + " needs more " +
                               (contacts ? "contact" : "Verlet pair") +
                               " slots than the batch holds; raise coupling.cuda." +
                               (contacts ? "contacts_per_sphere" : "pairs_per_sphere") + " (now " +
                               std::to_string(contacts ? p_.capacity.contacts_per_sphere
                                                       : p_.capacity.pairs_per_sphere) +
                               ")");
    }
    protocol::RveReply& rp = reply[k];
    kinetic[k] = o.kinetic;
    if (o.tile) {  // tiled on the host (native tile_if_thin), replied from its state
      sync_to_host();
      native::RveRecord& rec = host_.rve(k);
      native::NeighbourList unused(p_.native.verlet_skin);
      if (native::tile_if_thin(rec.state, unused) >= 0) ++rec.tilings;
      native::reply_from_state(rec, o.status, in[k].ns, ctx_.outputs, p_.native.stiffness, rp);
      repack = true;
    } else {
      std::memset(&rp, 0, sizeof rp);
      std::memcpy(rp.stress, o.stress, sizeof rp.stress);
      std::memcpy(rp.rotation, o.rotation, sizeof rp.rotation);
      rp.porosity = o.porosity;
      rp.coordination = o.coordination;
      rp.unbalanced_force = o.unbalanced;
      rp.stiffness = o.stiffness;
      rp.status = o.status;
      rp.n_substeps = in[k].ns;
    }
  }
  if (repack) pack();
}

void CudaBackend::checkpoint(const std::filesystem::path& dir) {
  sync_to_host();
  host_.checkpoint(dir);
  driver_.forget();
}

void CudaBackend::restore(const std::filesystem::path& dir) {
  host_.restore(dir);
  driver_.forget();
  pack();
}

std::string CudaBackend::export_rve(std::uint64_t gid) {
  sync_to_host();
  return host_.export_rve(gid);
}

void CudaBackend::adopt(std::uint64_t first_rve, std::uint64_t n_rve,
                        std::map<std::uint64_t, std::string> incoming) {
  sync_to_host();
  host_.adopt(first_rve, n_rve, std::move(incoming));
  ctx_.first_rve = first_rve;
  ctx_.n_rve = n_rve;
  pack();
}

CudaParams cuda_params(const config::Config& cfg) {
  CudaParams p;
  p.native = native_params(cfg);
  if (p.native.law.viscous()) {  // also refused by check_coupling, with the file named
    throw std::runtime_error(
        "coupling.native.contact_law frict_visco: the cuda backend has the frict law only; "
        "use backend native or yade");
  }
  p.on_gpu = cfg.string("coupling.cuda.device") == "gpu";
  p.gpu = static_cast<int>(cfg.integer("coupling.cuda.gpu"));
  p.threads_per_block = static_cast<int>(cfg.integer("coupling.cuda.threads_per_block"));
  p.capacity.contacts_per_sphere = cfg.number("coupling.cuda.contacts_per_sphere");
  p.capacity.pairs_per_sphere = cfg.number("coupling.cuda.pairs_per_sphere");
  return p;
}

std::unique_ptr<RveBackend> make_cuda_backend(const config::Config& cfg) {
  return std::make_unique<CudaBackend>(cuda_params(cfg));
}

}  // namespace mpmdem::dem
