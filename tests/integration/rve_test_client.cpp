// A stand-in for mpm_app (MUSCLE3's MuscleTester, preCICE's solverdummies): drives a real
// dem_app through the full protocol with known deformation gradients and checks every
// reply against the same elastic law applied locally. Each RVE gets a different dF, so a
// wrong partition or ordering shows up as a mismatch.
//
//   rve_test_client --scene FILE --run-dir DIR [--n N] [--steps S] [--checkpoint-at K]
//                   [--resume K] [--abort-after K] [--timeout S]
//
//   --checkpoint-at K  ask the servers to checkpoint into DIR/ckpt after step K
//   --resume K         the server was started with --restore: skip kInitialise and
//                      continue from step K (the reference replays steps 1..K locally)
//   --abort-after K    send Abort after step K and exit 0 (the server must exit non-zero)
// Exit codes: 0 all replies match, 1 mismatch, 3 handshake refused, 4 peer/MPI error.
#include <mpi.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "coupling_schema.hpp"
#include "mpmdem/config_hash.hpp"
#include "mpmdem/connection.hpp"
#include "mpmdem/errors.hpp"
#include "mpmdem/exchange.hpp"
#include "mpmdem/laws/elastic_law.hpp"

namespace {

using RowMajor3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
using Mat3 = Eigen::Matrix3d;

// Deterministic, distinct per RVE and step; non-symmetric so it carries rotation.
Mat3 dF_of(std::size_t p, int step) {
  Mat3 A;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      A(i, j) = std::sin(0.7 * static_cast<double>(p) + 1.3 * i + 0.4 * j + 0.1 * step);
  return Mat3::Identity() + 1e-4 * A;
}

Mat3 initial_stress(std::size_t p) {
  Mat3 s = Mat3::Zero();
  s.diagonal() << -1000.0 * static_cast<double>(p + 1), -500.0, -700.0;
  s(0, 1) = s(1, 0) = 10.0 * static_cast<double>(p % 5);
  return s;
}

// Step 2 asks for kFlagQueryOnly: the server must apply nothing.
bool query_only(int step) {
  return step == 2;
}

int arg_int(const std::string& v) {
  return std::atoi(v.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  mpmdem::MpiSession mpi(&argc, &argv);
  std::string scene, run_dir;
  std::size_t n = 10;
  int steps = 5, checkpoint_at = -1, resume = 0, abort_after = -1;
  double timeout = -1.0;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--scene")
      scene = v;
    else if (k == "--run-dir")
      run_dir = v;
    else if (k == "--n")
      n = static_cast<std::size_t>(arg_int(v));
    else if (k == "--steps")
      steps = arg_int(v);
    else if (k == "--checkpoint-at")
      checkpoint_at = arg_int(v);
    else if (k == "--resume")
      resume = arg_int(v);
    else if (k == "--abort-after")
      abort_after = arg_int(v);
    else if (k == "--timeout")
      timeout = std::atof(v.c_str());
    else {
      std::cerr << "rve_test_client: unknown option " << k << "\n";
      return 2;
    }
  }
  try {
    const auto cfg = mpmdem::config::Config::load(scene, mpmdem::coupling_schema(), "coupling");
    const mpmdem::elastic::ElasticLaw law{cfg.number("coupling.elastic.youngs_modulus"),
                                          cfg.number("coupling.elastic.poisson_ratio")};
    mpmdem::ConnectOptions opts;
    opts.service_name = cfg.string("coupling.service_name");
    opts.port_file = std::filesystem::path(run_dir) / cfg.string("coupling.port_file");
    opts.timeout_s = timeout > 0 ? timeout : cfg.number("coupling.connect_timeout_s");
    opts.config_file = scene;
    mpmdem::HelloFields hello;
    hello.program = "rve_test_client";
    hello.backend = cfg.string("coupling.backend");
    hello.n_rve = n;
    hello.outputs = mpmdem::coupling_output_bits(cfg);
    hello.config_hash = mpmdem::fnv1a64(mpmdem::coupling_canonical_text(cfg));

    mpmdem::RveClient client;
    client.connect(opts, hello);
    std::cout << "rve_test_client: connected to " << client.server_ranks() << " server rank(s)"
              << std::endl;

    std::vector<Mat3> sigma(n);
    for (std::size_t p = 0; p < n; ++p) sigma[p] = initial_stress(p);
    double worst = 0.0;
    auto compare = [&](const std::vector<mpmdem::protocol::RveReply>& replies, const char* what) {
      if (replies.size() != n) {
        std::cerr << what << ": " << replies.size() << " replies for " << n << " RVEs\n";
        worst = 1.0;
        return;
      }
      for (std::size_t p = 0; p < n; ++p) {
        const Mat3 got = Eigen::Map<const RowMajor3>(replies[p].stress);
        const double err = (got - sigma[p]).norm() / sigma[p].norm();
        if (err > worst) worst = err;
        if (err > 1e-12 || replies[p].status != 0 ||
            replies[p].stiffness != law.constrained_modulus()) {
          std::cerr << what << ": RVE " << p << " stress rel. error " << err << ", status "
                    << replies[p].status << ", stiffness " << replies[p].stiffness << "\n";
          worst = std::max(worst, 1.0);
        }
      }
    };

    if (resume > 0) {
      for (int s = 1; s <= resume; ++s)
        for (std::size_t p = 0; p < n && !query_only(s); ++p)
          sigma[p] = law.update(sigma[p], dF_of(p, s));
    } else {
      std::vector<mpmdem::protocol::RveInit> init(n);
      for (std::size_t p = 0; p < n; ++p) {
        Eigen::Map<RowMajor3>(init[p].stress) = sigma[p];
        init[p].point = p;
      }
      compare(client.initialise(init), "initialise");
    }

    std::vector<mpmdem::protocol::RveRequest> req(n);
    for (int s = resume + 1; s <= steps; ++s) {
      for (std::size_t p = 0; p < n; ++p) {
        std::memset(&req[p], 0, sizeof req[p]);
        Eigen::Map<RowMajor3>(req[p].dF) = dF_of(p, s);
        req[p].dt = 1e-3;
        req[p].flags = query_only(s) ? mpmdem::protocol::kFlagQueryOnly : 0u;
        if (!query_only(s)) sigma[p] = law.update(sigma[p], dF_of(p, s));
      }
      mpmdem::protocol::ControlHeader h{};
      h.step = s;
      h.time = 1e-3 * s;
      h.dt = 1e-3;
      compare(client.step(h, req), "step");
      if (s == checkpoint_at) {
        const auto dir = std::filesystem::absolute(std::filesystem::path(run_dir) / "ckpt");
        client.checkpoint(dir.string(), s);
        for (int r = 0; r < client.server_ranks(); ++r) {
          const auto f = dir / ("elastic_rank" + std::to_string(r) + ".bin");
          if (!std::filesystem::exists(f)) {
            std::cerr << "checkpoint: missing " << f << "\n";
            worst = std::max(worst, 1.0);
          }
        }
      }
      if (s == abort_after) {
        client.abort("rve_test_client: test abort");
        std::cout << "rve_test_client: aborted after step " << s << std::endl;
        return 0;
      }
    }
    client.shutdown();
    std::cout << "rve_test_client: " << n << " RVEs, steps " << resume + 1 << ".." << steps
              << ", worst relative stress error " << worst << std::endl;
    return worst <= 1e-12 ? 0 : 1;
  } catch (const mpmdem::HandshakeError& e) {
    std::cerr << "rve_test_client: error: " << e.what() << "\n";
    return mpmdem::kExitHandshakeError;
  } catch (const mpmdem::PeerError& e) {
    std::cerr << "rve_test_client: error: " << e.what() << "\n";
    return mpmdem::kExitPeerError;
  } catch (const std::exception& e) {
    std::cerr << "rve_test_client: error: " << e.what() << "\n";
    return 2;
  }
}
