// element_test: the MPM-side stand-in. Drives K RVEs of a real dem_app (any backend) along a
// prescribed path through the real protocol and writes the stress-strain response.
//
//   element_test --scene FILE --run-dir DIR
//                --test isotropic|oedometric|triaxial|constant_volume|simple_shear|df_file
//                --rves K --strain S --steps N [--pressure P] [--dt DT] [--out CSV]
//                [--df-file FILE]
//
// Every RVE starts from the isotropic stress -P (RveInit), then gets N equal increments:
//   isotropic     dF = s I,                        s = (1 - S)^(1/N)
//   oedometric    dF = diag(1, 1, s)               (uniaxial strain along z)
//   triaxial      dF = diag(exp e_x, exp e_y, s)   e_x, e_y by mixed control (velocity form):
//                 e_i(n) = e_i(n-1) + g (-P - sigma_ii(n) - dsigma_ii(n)) / M, dsigma_ii(n) the
//                 last step's change, M the reply's stiffness estimate (if 0: the secant
//                 |dsigma_zz / d eps_zz| of the last step); the lateral stresses are held at
//                 -P (drained triaxial compression); gain g = kGain
//   constant_volume  dF = diag(s^-1/2, s^-1/2, s): constant-volume (undrained) triaxial
//                 compression, det dF = 1 (to round-off)
//   simple_shear  dF = I + (S/N) e_x e_z: simple shear at constant volume (height and
//                 lateral sides held, det dF = 1 exactly), shear strain gamma = n S/N
//   df_file       dF of step n = row n of --df-file (9 numbers per line, row-major; blank
//                 lines and lines starting with # skipped), the same for every RVE; --steps
//                 must not exceed the rows; --strain is ignored
// The CSV has one row per step and RVE: step, rve, Hencky strain eps_ij of the accumulated
// F (log V), Cauchy stress sigma_ij (tension positive), p = -tr(sigma)/3, q = sqrt(3/2 s:s),
// the mobilised friction angle asin((s1 - s3)/(s1 + s3)) of the compressive principal
// stresses [deg], the reply's stiffness estimate, porosity and coordination (0 unless the
// scene's coupling.outputs asks for them), status. The summary printed at the end uses the
// RVE-mean stress. Exit codes: 0 done (statuses may still be non-zero: see the summary), 2 bad
// command line/scene, 3 handshake refused, 4 peer/MPI error.
#include <mpi.h>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "coupling_rules.hpp"
#include "coupling_schema.hpp"
#include "mpmdem/config_hash.hpp"
#include "mpmdem/connection.hpp"
#include "mpmdem/errors.hpp"
#include "mpmdem/exchange.hpp"

namespace {

using RowMajor3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
using Mat3 = Eigen::Matrix3d;
constexpr double kPi = 3.14159265358979323846;
// Gain of the triaxial mixed control. With the true lateral stiffness K = g M (both lateral
// axes move together: g = 1 + nu/(1 - nu) for an elastic solid) the error decays by
// sqrt(1 - kGain g) per step while kGain g < 1; kGain g = 4/3 (gain 1, nu = 1/4) oscillates.
constexpr double kGain = 0.5;

struct Options {
  std::string scene, run_dir, test, out, df_file;
  std::size_t rves = 1;
  double strain = 0.0, pressure = 1.0e4, dt = 1.0e-3;
  int steps = 0;
};

[[noreturn]] void usage_error(const std::string& what) {
  throw std::invalid_argument(what +
                              "\nusage: element_test --scene FILE --run-dir DIR --test "
                              "isotropic|oedometric|triaxial|constant_volume|simple_shear|df_file "
                              "--rves K --strain S --steps N [--pressure P] [--dt DT] [--out CSV] "
                              "[--df-file FILE]");
}

double to_number(const std::string& key, const std::string& v) {
  char* end = nullptr;
  const double x = std::strtod(v.c_str(), &end);
  if (v.empty() || *end != '\0' || !std::isfinite(x)) usage_error(key + ": not a number: " + v);
  return x;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; i += 2) {
    const std::string k = argv[i];
    if (i + 1 >= argc) usage_error(k + ": missing value");
    const std::string v = argv[i + 1];
    if (k == "--scene") {
      o.scene = v;
    } else if (k == "--run-dir") {
      o.run_dir = v;
    } else if (k == "--test") {
      o.test = v;
    } else if (k == "--out") {
      o.out = v;
    } else if (k == "--df-file") {
      o.df_file = v;
    } else if (k == "--rves") {
      o.rves = static_cast<std::size_t>(to_number(k, v));
    } else if (k == "--strain") {
      o.strain = to_number(k, v);
    } else if (k == "--steps") {
      o.steps = static_cast<int>(to_number(k, v));
    } else if (k == "--pressure") {
      o.pressure = to_number(k, v);
    } else if (k == "--dt") {
      o.dt = to_number(k, v);
    } else {
      usage_error("unknown option " + k);
    }
  }
  if (o.scene.empty() || o.run_dir.empty()) usage_error("--scene and --run-dir are required");
  if (o.test != "isotropic" && o.test != "oedometric" && o.test != "triaxial" &&
      o.test != "constant_volume" && o.test != "simple_shear" && o.test != "df_file")
    usage_error("--test: unknown test '" + o.test + "'");
  if ((o.test == "df_file") != !o.df_file.empty())
    usage_error("--df-file goes with --test df_file (and only with it)");
  if (o.rves < 1) usage_error("--rves must be >= 1");
  if (o.steps < 1) usage_error("--steps must be >= 1");
  if (o.test != "simple_shear" && o.test != "df_file" && !(o.strain < 1.0))
    usage_error("--strain must be < 1");
  if (!(o.dt > 0.0)) usage_error("--dt must be > 0");
  return o;
}

// Hencky strain log(V) of F (V^2 = F F^T).
Mat3 hencky(const Mat3& F) {
  Eigen::SelfAdjointEigenSolver<Mat3> es(F * F.transpose());
  const Eigen::Vector3d l = es.eigenvalues().array().log() * 0.5;
  return es.eigenvectors() * l.asDiagonal() * es.eigenvectors().transpose();
}

// Rows of a dF file: 9 numbers (row-major) per non-blank line not starting with '#'.
std::vector<Mat3> read_df_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) usage_error("--df-file: cannot read " + path);
  std::vector<Mat3> rows;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream ls(line);
    RowMajor3 m;
    for (int i = 0; i < 9; ++i) {
      if (!(ls >> m(i / 3, i % 3)) || !std::isfinite(m(i / 3, i % 3)))
        usage_error(path + ":" + std::to_string(line_no) +
                    ": expected 9 finite numbers (dF row-major)");
    }
    std::string rest;
    if (ls >> rest) usage_error(path + ":" + std::to_string(line_no) + ": more than 9 numbers");
    if (!(m.determinant() > 0.0))
      usage_error(path + ":" + std::to_string(line_no) + ": det dF must be > 0");
    rows.push_back(m);
  }
  return rows;
}

struct Invariants {
  double p, q, phi_deg;
};

Invariants invariants(const Mat3& sigma_in) {
  const Mat3 sigma = 0.5 * (sigma_in + sigma_in.transpose());
  Invariants r{};
  r.p = 0.0 - sigma.trace() / 3.0;  // no "-0" for a stress-free RVE
  const Mat3 s = sigma + r.p * Mat3::Identity();
  r.q = std::sqrt(1.5 * s.cwiseProduct(s).sum());
  const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Mat3>(sigma).eigenvalues();
  const double s1 = -ev(0), s3 = -ev(2);  // compressive principal stresses, s1 >= s3
  r.phi_deg =
      (s1 + s3 > 0.0) ? std::asin(std::clamp((s1 - s3) / (s1 + s3), -1.0, 1.0)) * 180.0 / kPi : 0.0;
  return r;
}

int run(const Options& o) {
  const auto cfg = mpmdem::config::Config::load(o.scene, mpmdem::coupling_schema(), "coupling");
  mpmdem::check_coupling(cfg);
  mpmdem::ConnectOptions opts;
  opts.service_name = cfg.string("coupling.service_name");
  opts.port_file = std::filesystem::path(o.run_dir) / cfg.string("coupling.port_file");
  opts.timeout_s = cfg.number("coupling.connect_timeout_s");
  opts.config_file = o.scene;
  mpmdem::HelloFields hello;
  hello.program = "element_test";
  hello.backend = cfg.string("coupling.backend");
  hello.n_rve = o.rves;
  hello.outputs = mpmdem::coupling_output_bits(cfg);
  hello.config_hash = mpmdem::fnv1a64(mpmdem::coupling_canonical_text(cfg));

  std::vector<Mat3> df_rows;
  if (o.test == "df_file") {
    df_rows = read_df_file(o.df_file);
    if (df_rows.size() < static_cast<std::size_t>(o.steps))
      usage_error("--df-file " + o.df_file + " has " + std::to_string(df_rows.size()) +
                  " rows, fewer than --steps " + std::to_string(o.steps));
  }
  mpmdem::RveClient client;
  client.connect(opts, hello);
  std::cout << "element_test: " << o.test << " on " << o.rves << " RVE(s), "
            << client.server_ranks() << " server rank(s), backend '" << hello.backend << "'"
            << std::endl;

  const std::size_t K = o.rves;
  std::vector<mpmdem::protocol::RveInit> init(K);
  for (std::size_t k = 0; k < K; ++k) {
    std::memset(&init[k], 0, sizeof init[k]);
    init[k].stress[0] = init[k].stress[4] = init[k].stress[8] = -o.pressure;
    init[k].point = k;
  }
  std::vector<mpmdem::protocol::RveReply> replies = client.initialise(init);

  std::ofstream csv;
  if (!o.out.empty()) {
    csv.open(o.out);
    if (!csv) throw std::runtime_error("cannot write " + o.out);
    csv << "step,rve";
    for (const char* c : {"xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz"})
      csv << ",eps_" << c;
    for (const char* c : {"xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz"})
      csv << ",sigma_" << c;
    csv << ",p,q,phi_deg,stiffness,porosity,coordination,status\n";
    csv << std::setprecision(17);
  }
  std::vector<Mat3> F(K, Mat3::Identity());
  int bad_statuses = 0;
  auto record = [&](int step) {
    Mat3 mean = Mat3::Zero();
    for (std::size_t k = 0; k < K; ++k) {
      const Mat3 sigma = Eigen::Map<const RowMajor3>(replies[k].stress);
      mean += sigma / static_cast<double>(K);
      if (replies[k].status != 0) ++bad_statuses;
      if (!csv.is_open()) continue;
      const Mat3 eps = hencky(F[k]);
      const Invariants inv = invariants(sigma);
      csv << step << ',' << k;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) csv << ',' << eps(i, j);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) csv << ',' << sigma(i, j);
      csv << ',' << inv.p << ',' << inv.q << ',' << inv.phi_deg << ',' << replies[k].stiffness
          << ',' << replies[k].porosity << ',' << replies[k].coordination << ','
          << replies[k].status << '\n';
    }
    return mean;
  };
  const Invariants inv0 = invariants(record(0));
  std::cout << std::setprecision(10) << "element_test: after initialise p = " << inv0.p
            << " Pa, q = " << inv0.q << " Pa" << std::endl;

  const double stretch = std::pow(1.0 - o.strain, 1.0 / o.steps);  // per-step axial stretch
  double phi_peak = 0.0, phi_final = 0.0;
  Mat3 mean = Mat3::Zero();
  std::vector<mpmdem::protocol::RveRequest> req(K);
  // Triaxial control state per RVE: last lateral strain increments and stress changes.
  std::vector<std::array<double, 2>> e_lat(K, {0.0, 0.0}), ds_lat(K, {0.0, 0.0});
  std::vector<double> ds_axial(K, 0.0);
  for (int n = 1; n <= o.steps; ++n) {
    for (std::size_t k = 0; k < K; ++k) {
      Mat3 dF = Mat3::Identity();
      if (o.test == "isotropic") {
        dF *= stretch;
      } else if (o.test == "oedometric") {
        dF(2, 2) = stretch;
      } else if (o.test == "triaxial") {
        dF(2, 2) = stretch;
        // Velocity-form mixed control: the next lateral stress is predicted as the current
        // one plus the last step's change plus M times the change of lateral strain rate.
        const double de_z = std::log(stretch);
        double M = replies[k].stiffness;
        if (!(M > 0.0) && n > 1) M = std::abs(ds_axial[k] / de_z);  // secant fallback
        for (int i = 0; i < 2; ++i) {
          double e = 0.0;
          if (M > 0.0) {
            const double s_now = replies[k].stress[4 * i];
            e = e_lat[k][i] + kGain * (-o.pressure - s_now - ds_lat[k][i]) / M;
            e = std::clamp(e, -2.0 * std::abs(de_z), 2.0 * std::abs(de_z));
          }
          e_lat[k][i] = e;
          dF(i, i) = std::exp(e);
        }
      } else if (o.test == "constant_volume") {
        dF(2, 2) = stretch;
        dF(0, 0) = dF(1, 1) = 1.0 / std::sqrt(stretch);
      } else if (o.test == "simple_shear") {
        dF(0, 2) = o.strain / o.steps;
      } else {  // df_file
        dF = df_rows[static_cast<std::size_t>(n - 1)];
      }
      std::memset(&req[k], 0, sizeof req[k]);
      Eigen::Map<RowMajor3>(req[k].dF) = dF;
      req[k].dt = o.dt;
      F[k] = dF * F[k];
    }
    mpmdem::protocol::ControlHeader h{};
    h.step = n;
    h.dt = o.dt;
    h.time = o.dt * n;
    std::vector<mpmdem::protocol::RveReply> before = replies;
    client.step(h, req, replies);
    for (std::size_t k = 0; k < K; ++k) {
      for (int i = 0; i < 2; ++i) ds_lat[k][i] = replies[k].stress[4 * i] - before[k].stress[4 * i];
      ds_axial[k] = replies[k].stress[8] - before[k].stress[8];
    }
    mean = record(n);
    const Invariants inv = invariants(mean);
    phi_peak = std::max(phi_peak, inv.phi_deg);
    phi_final = inv.phi_deg;
  }
  client.shutdown();
  const Invariants fin = invariants(mean);
  std::cout << std::setprecision(17) << "element_test: final mean stress diag = " << mean(0, 0)
            << " " << mean(1, 1) << " " << mean(2, 2) << " Pa\n"
            << "element_test: final p = " << fin.p << " Pa, q = " << fin.q << " Pa\n"
            << std::setprecision(6) << "element_test: phi_peak_deg = " << phi_peak << "\n"
            << "element_test: phi_final_deg = " << phi_final << "\n"
            << "element_test: non-zero statuses: " << bad_statuses << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  mpmdem::MpiSession mpi(&argc, &argv);
  try {
    return run(parse(argc, argv));
  } catch (const mpmdem::HandshakeError& e) {
    std::cerr << "element_test: error: " << e.what() << "\n";
    return mpmdem::kExitHandshakeError;
  } catch (const mpmdem::PeerError& e) {
    std::cerr << "element_test: error: " << e.what() << "\n";
    return mpmdem::kExitPeerError;
  } catch (const std::exception& e) {
    std::cerr << "element_test: error: " << e.what() << "\n";
    return mpmdem::kExitConfigError;
  }
}
