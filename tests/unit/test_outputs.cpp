// Outputs of a run: VTK frames and .pvd series, HDF5 final state, energies.csv,
// summary.json, and the run-directory rules (no overwrite without --force, nothing created
// on a config error). Files are parsed back, not just checked for existence.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "output/energy_log.hpp"
#include "output/hdf5_writer.hpp"
#include "output/run_directory.hpp"
#include "output/summary_json.hpp"
#include "output/vtk_writer.hpp"
#include "progress.hpp"
#include "run_driver.hpp"
#include "scene_builder.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace mpmdem::mpm;
using test_fixture::quiet_options;
using test_fixture::SceneBuilder;
using test_support::read_file;
using test_support::TempDir;

namespace {

// Five points with distinct, recognisable values.
Particles sample_particles(std::size_t n = 5) {
  Particles p;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = static_cast<double>(i);
    p.id.push_back(static_cast<std::int64_t>(100 + i));
    p.region.push_back(0);
    p.m.push_back(0.5 + a);
    p.V.push_back(1e-3 * (1.0 + a));
    p.V0.push_back(1e-3);
    p.x0.push_back(Vec3(a, 2.0 * a, 3.0 * a));
    p.x.push_back(Vec3(a + 0.1, 2.0 * a - 0.2, 3.0 * a + 0.3));
    p.v.push_back(Vec3(-a, 0.5, a * a));
    Mat3 F = Mat3::Identity();
    F(0, 1) = 0.01 * a;
    p.F.push_back(F);
    p.dF.push_back(Mat3::Identity());
    Mat3 sigma;
    sigma << 1, 2, 3, 4, 5, 6, 7, 8, 9;
    p.sigma.push_back(-1000.0 * (a + 1.0) * sigma);
    p.stiffness.push_back(1e7);
    p.strain_energy.push_back(0.0);
  }
  return p;
}

// A parsed .vtu: counts, and each appended array as doubles (any numeric type).
struct Vtu {
  std::size_t points = 0, cells = 0;
  std::map<std::string, int> components;
  std::map<std::string, std::vector<double>> arrays;
};

Vtu parse_vtu(const fs::path& file) {
  const std::string text = read_file(file);
  Vtu vtu;
  const std::size_t appended = text.find("<AppendedData encoding=\"raw\">");
  EXPECT_NE(appended, std::string::npos) << file;
  if (appended == std::string::npos) return vtu;
  const std::string head = text.substr(0, appended);
  EXPECT_NE(head.find("type=\"UnstructuredGrid\""), std::string::npos);
  EXPECT_NE(head.find("header_type=\"UInt64\""), std::string::npos);
  std::smatch m;
  const std::regex piece("NumberOfPoints=\"(\\d+)\" NumberOfCells=\"(\\d+)\"");
  EXPECT_TRUE(std::regex_search(head, m, piece));
  vtu.points = std::stoul(m[1]);
  vtu.cells = std::stoul(m[2]);
  const std::size_t data = text.find('_', appended) + 1;
  const std::regex decl(
      "<DataArray type=\"(\\w+)\" Name=\"(\\w+)\"(?: NumberOfComponents=\"(\\d+)\")? "
      "format=\"appended\" offset=\"(\\d+)\"/>");
  for (auto it = std::sregex_iterator(head.begin(), head.end(), decl); it != std::sregex_iterator();
       ++it) {
    const std::string type = (*it)[1], name = (*it)[2];
    const int comps = (*it)[3].matched ? std::stoi((*it)[3]) : 1;
    const std::size_t offset = std::stoul((*it)[4]);
    std::uint64_t nbytes = 0;
    std::memcpy(&nbytes, text.data() + data + offset, sizeof nbytes);
    const char* bytes = text.data() + data + offset + sizeof nbytes;
    EXPECT_LE(data + offset + sizeof nbytes + nbytes, text.size()) << name;
    std::vector<double> values;
    auto take = [&](auto zero) {
      using T = decltype(zero);
      EXPECT_EQ(nbytes % sizeof(T), 0u) << name;
      for (std::size_t k = 0; k < nbytes / sizeof(T); ++k) {
        T v;
        std::memcpy(&v, bytes + k * sizeof(T), sizeof(T));
        values.push_back(static_cast<double>(v));
      }
    };
    if (type == "Float64")
      take(double{});
    else if (type == "Int64")
      take(std::int64_t{});
    else if (type == "Int32")
      take(std::int32_t{});
    else if (type == "UInt8")
      take(std::uint8_t{});
    else
      ADD_FAILURE() << "unexpected type " << type;
    vtu.components[name] = comps;
    vtu.arrays[name] = std::move(values);
  }
  EXPECT_NE(text.rfind("</VTKFile>"), std::string::npos);
  return vtu;
}

// Reads a dataset of doubles/int64 and its dimensions through the HDF5 C API.
template <typename T>
std::vector<T> read_h5(hid_t file, const char* name, hid_t type, std::vector<hsize_t>& dims) {
  const hid_t set = H5Dopen2(file, name, H5P_DEFAULT);
  EXPECT_GE(set, 0) << name;
  if (set < 0) return {};
  const hid_t space = H5Dget_space(set);
  dims.assign(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)), 0);
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  hsize_t total = 1;
  for (hsize_t d : dims) total *= d;
  std::vector<T> values(total);
  EXPECT_GE(H5Dread(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
  H5Sclose(space);
  H5Dclose(set);
  return values;
}

std::vector<std::vector<std::string>> read_csv(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

std::string source(const std::string& rel) {
  return std::string(MPMDEM_SOURCE_DIR) + "/" + rel;
}

// The elastic column scene cut to a few steps: enough to exercise every output.
SceneBuilder short_column() {
  return SceneBuilder::config("configs/elastic_column.yaml").with([](Scene& s) {
    s.solver.end_time = 20.0 * std::min(s.solver.dt_max, 1e-4);
    s.output.interval = s.solver.end_time / 2.0;
    s.output.energy_interval = 0.0;
    s.output.vtk = true;
    s.output.hdf5 = true;
    s.output.progress_interval_s = 0.0;
  });
}

}  // namespace

TEST(VtkWriter, FramesParseBackWithTheValuesWritten) {
  TempDir dir("vtk", TempDir::kCreate);
  const Particles p = sample_particles();
  VtkSeries series(dir.str());
  EXPECT_EQ(series.write_frame(p, 0.0), "frame_00000.vtu");
  EXPECT_EQ(series.write_frame(p, 0.25), "frame_00001.vtu");

  const Vtu vtu = parse_vtu(dir.path() / "frame_00001.vtu");
  EXPECT_EQ(vtu.points, p.size());
  EXPECT_EQ(vtu.cells, p.size());
  for (const char* name : {"position", "velocity", "displacement", "stress", "mass", "volume", "id",
                           "Points", "connectivity", "offsets", "types"}) {
    ASSERT_TRUE(vtu.arrays.count(name)) << name;
    EXPECT_EQ(vtu.arrays.at(name).size(), p.size() * vtu.components.at(name)) << name;
  }
  EXPECT_EQ(vtu.components.at("stress"), 9);
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(vtu.arrays.at("Points")[3 * i + k], p.x[i][k]);
      EXPECT_EQ(vtu.arrays.at("displacement")[3 * i + k], p.x[i][k] - p.x0[i][k]);
      EXPECT_EQ(vtu.arrays.at("velocity")[3 * i + k], p.v[i][k]);
    }
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(vtu.arrays.at("stress")[9 * i + 3 * r + c], p.sigma[i](r, c));  // row-major
    EXPECT_EQ(vtu.arrays.at("mass")[i], p.m[i]);
    EXPECT_EQ(vtu.arrays.at("id")[i], static_cast<double>(p.id[i]));
    EXPECT_EQ(vtu.arrays.at("types")[i], 1.0);  // VTK_VERTEX
    EXPECT_EQ(vtu.arrays.at("offsets")[i], static_cast<double>(i + 1));
  }
  // No RVE outputs were filled, so none are written.
  EXPECT_FALSE(vtu.arrays.count("porosity"));

  // The series lists both frames with their times, and no temporary file is left.
  const std::string pvd = read_file(series.pvd_path());
  EXPECT_NE(pvd.find("type=\"Collection\""), std::string::npos);
  EXPECT_NE(pvd.find("timestep=\"0\" group=\"\" part=\"0\" file=\"frame_00000.vtu\""),
            std::string::npos);
  EXPECT_NE(pvd.find("timestep=\"0.25\" group=\"\" part=\"0\" file=\"frame_00001.vtu\""),
            std::string::npos);
  for (const auto& e : fs::directory_iterator(dir.path()))
    EXPECT_NE(e.path().extension(), ".tmp") << e.path();
}

TEST(VtkWriter, RveOutputsAppearWhenFilled) {
  TempDir dir("vtk_rve", TempDir::kCreate);
  Particles p = sample_particles(3);
  p.porosity = {0.4, 0.41, 0.42};
  p.coordination = {4.0, 4.5, 5.0};
  p.rotation = {Vec3(0.1, 0, 0), Vec3(0, 0.2, 0), Vec3(0, 0, 0.3)};
  p.state = {PointState::kOk, PointState::kNoContacts, PointState::kOk};
  write_vtu((dir.path() / "a.vtu").string(), p);
  const Vtu vtu = parse_vtu(dir.path() / "a.vtu");
  EXPECT_EQ(vtu.arrays.at("porosity"), std::vector<double>({0.4, 0.41, 0.42}));
  EXPECT_EQ(vtu.arrays.at("coordination"), std::vector<double>({4.0, 4.5, 5.0}));
  EXPECT_EQ(vtu.arrays.at("status"), std::vector<double>({0, 1, 0}));
  EXPECT_EQ(vtu.components.at("rotation"), 3);
  EXPECT_EQ(vtu.arrays.at("rotation")[4], 0.2);
}

// The files store a point's state as the enum's value (0 ok, 1 no contacts); a checkpoint
// gives back only states a point keeps.
TEST(PointStateCodes, StoredAsTheEnumValuesAndReadBackOnlyForKeptStates) {
  EXPECT_EQ(state_codes({PointState::kOk, PointState::kNoContacts}),
            std::vector<std::int32_t>({0, 1}));
  EXPECT_EQ(states_from_codes({1, 0}),
            std::vector<PointState>({PointState::kNoContacts, PointState::kOk}));
  EXPECT_THROW(states_from_codes({0, static_cast<std::int32_t>(PointState::kFatal)}),
               std::runtime_error);
  EXPECT_THROW(states_from_codes({7}), std::runtime_error);
}

TEST(Hdf5Writer, FinalStateReadsBackWithTheCApi) {
  TempDir dir("h5", TempDir::kCreate);
  const Particles p = sample_particles();
  const std::string path = (dir.path() / "final_state.h5").string();
  write_final_state(path, p, {1.25, 4321, "column", "configs/x.yaml"});
  EXPECT_FALSE(fs::exists(path + ".tmp"));

  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  std::vector<hsize_t> dims;
  const auto x = read_h5<double>(file, "x", H5T_NATIVE_DOUBLE, dims);
  EXPECT_EQ(dims, std::vector<hsize_t>({p.size(), 3}));
  for (std::size_t i = 0; i < p.size(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(x[3 * i + k], p.x[i][k]);
  const auto stress = read_h5<double>(file, "stress", H5T_NATIVE_DOUBLE, dims);
  EXPECT_EQ(dims, std::vector<hsize_t>({p.size(), 3, 3}));
  EXPECT_EQ(stress[9 * 2 + 3 * 1 + 2], p.sigma[2](1, 2));
  const auto F = read_h5<double>(file, "F", H5T_NATIVE_DOUBLE, dims);
  EXPECT_EQ(dims, std::vector<hsize_t>({p.size(), 3, 3}));
  EXPECT_EQ(F[9 * 3 + 1], p.F[3](0, 1));
  const auto id = read_h5<std::int64_t>(file, "id", H5T_NATIVE_INT64, dims);
  EXPECT_EQ(id, p.id);
  for (const char* name : {"x0", "v"}) {
    read_h5<double>(file, name, H5T_NATIVE_DOUBLE, dims);
    EXPECT_EQ(dims, std::vector<hsize_t>({p.size(), 3})) << name;
  }
  EXPECT_EQ(read_h5<double>(file, "mass", H5T_NATIVE_DOUBLE, dims), p.m);
  EXPECT_EQ(read_h5<double>(file, "volume", H5T_NATIVE_DOUBLE, dims), p.V);

  double time = 0.0;
  std::int64_t step = 0;
  const hid_t t_attr = H5Aopen(file, "time", H5P_DEFAULT);
  ASSERT_GE(t_attr, 0);
  H5Aread(t_attr, H5T_NATIVE_DOUBLE, &time);
  H5Aclose(t_attr);
  const hid_t s_attr = H5Aopen(file, "step", H5P_DEFAULT);
  ASSERT_GE(s_attr, 0);
  H5Aread(s_attr, H5T_NATIVE_INT64, &step);
  H5Aclose(s_attr);
  EXPECT_EQ(time, 1.25);
  EXPECT_EQ(step, 4321);
  const hid_t n_attr = H5Aopen(file, "scene", H5P_DEFAULT);
  ASSERT_GE(n_attr, 0);
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, H5T_VARIABLE);
  H5Tset_cset(type, H5T_CSET_UTF8);
  char* text = nullptr;
  ASSERT_GE(H5Aread(n_attr, type, &text), 0);
  const std::string scene = text ? text : "";
  H5free_memory(text);
  H5Tclose(type);
  H5Aclose(n_attr);
  EXPECT_EQ(scene, "column");
  H5Fclose(file);
}

TEST(EnergyLog, HeaderAndDissipatedEnergyIdentity) {
  TempDir dir("energy", TempDir::kCreate);
  const fs::path path = dir.path() / "energies.csv";
  {
    EnergyLog log(path.string());
    log.append({0.0, 0, 0.0, 10.0, 0.0, 0.0, 10.0});
    log.append({0.1, 7, 1e-3, 9.5, 0.25, 0.1, 10.0, 0.5, 0.4, 0.2, 0.05, 0.03, 0.01});
    // A non-finite value is refused and nothing is written.
    EXPECT_THROW(log.append({0.2, 8, 1e-3, std::nan(""), 0.0, 0.0, 10.0}), std::runtime_error);
    EXPECT_EQ(log.rows(), 2u);
  }
  const auto rows = read_csv(path);
  ASSERT_EQ(rows.size(), 3u);
  std::string header;
  for (std::size_t k = 0; k < rows[0].size(); ++k) header += (k ? "," : "") + rows[0][k];
  EXPECT_EQ(header,
            "time,step,dt,E_p,E_k,E_d,E_strain,E_p0,E_k0,W_int,W_damp,W_bc,E_err,W_transfer,"
            "W_transfer_walls");
  EXPECT_EQ(std::stod(rows[1][0]), 0.0);
  EXPECT_DOUBLE_EQ(std::stod(rows[2][5]), 10.0 - 9.5 - 0.25);
  EXPECT_EQ(rows[2][1], "7");
  // E_err = E_p0 + E_k0 - E_p - E_k - W_int - W_damp - W_bc
  EXPECT_DOUBLE_EQ(std::stod(rows[2][12]), 10.0 + 0.5 - 9.5 - 0.25 - 0.4 - 0.2 - 0.05);
  EXPECT_DOUBLE_EQ(std::stod(rows[2][13]), 0.03);  // W_transfer, part of E_err
  EXPECT_DOUBLE_EQ(std::stod(rows[2][14]), 0.01);  // W_transfer_walls, part of W_transfer
}

TEST(SummaryJson, NonFiniteNumbersBecomeNull) {
  RunSummary s;
  s.status = "failed";
  s.error = "stress \"NaN\" at point 3";
  s.verification_kind = "bar_vibration";
  s.verification = {{"period_s", std::numeric_limits<double>::quiet_NaN()},
                    {"period_expected_s", 0.5}};
  const std::string json = to_json(s);
  EXPECT_NE(json.find("\"status\": \"failed\""), std::string::npos);
  EXPECT_NE(json.find("\"error\": \"stress \\\"NaN\\\" at point 3\""), std::string::npos);
  EXPECT_NE(json.find("\"period_s\": null"), std::string::npos);
  EXPECT_NE(json.find("\"period_expected_s\": 0.5"), std::string::npos);
  EXPECT_EQ(json.find("nan"), std::string::npos);
}

// A run ended by a lost DEM host: summary.json's peer_fault is what scripts/run --on-fault
// resume reads (scripts/lib/faults.py): kind, step, ranks and their hosts, exact, checkpoint.
TEST(SummaryJson, PeerFaultNamesRanksHostsAndCheckpoint) {
  RunSummary s;
  s.status = "failed";
  EXPECT_EQ(to_json(s).find("peer_fault"), std::string::npos) << "only after a peer fault";
  s.peer_fault = PeerFault{
      "no_reply", 107, {2, 3}, {"node-c", "node-c"}, true, "/r/checkpoints/step_000000100", 12.5};
  const std::string json = to_json(s);
  for (const char* part : {"\"kind\": \"no_reply\"", "\"step\": 107", "\"ranks\": [2, 3]",
                           "\"hosts\": [\"node-c\", \"node-c\"]", "\"exact\": true",
                           "\"checkpoint\": \"/r/checkpoints/step_000000100\"",
                           "\"wall_time_at_checkpoint_s\": 12.5"}) {
    EXPECT_NE(json.find(part), std::string::npos) << part << " not in\n" << json;
  }
}

// The energy_budget object: released = E_p0 + E_k0 - E_p - E_k = 10 + 0.5 - 6 - 0.5 = 4 J,
// split into W_int 2.5, W_bc 0.5, W_damp 0.2 and the residual 0.8 J, of which the transfers
// removed 0.6 J (0.1 J of it at the walls) and 0.2 J is the rest.
TEST(SummaryJson, EnergyBudgetSplitsTheReleasedEnergy) {
  RunSummary s;
  s.status = "complete";
  s.E_p0_J = 10.0;
  s.E_k0_J = 0.5;
  s.E_p_J = 6.0;
  s.E_k_J = 0.5;
  s.W_int_J = 2.5;
  s.W_bc_J = 0.5;
  s.W_damp_J = 0.2;
  s.W_transfer_J = 0.6;
  s.W_transfer_walls_J = 0.1;
  const std::string json = to_json(s);
  const auto object = json.substr(json.find("\"energy_budget\": {"));
  const std::string body = object.substr(0, object.find('}'));
  for (const char* kv :
       {"\"released_J\": 4", "\"W_int_J\": 2.5", "\"W_bc_J\": 0.5", "\"W_damp_J\": 0.2",
        "\"E_err_J\": 0.8", "\"W_int_share\": 0.625", "\"W_bc_share\": 0.125",
        "\"W_damp_share\": 0.05", "\"E_err_share\": 0.2", "\"E_err_transfer_J\": 0.6",
        "\"E_err_transfer_share\": 0.15", "\"E_err_other_share\": 0.05",
        "\"E_err_transfer_walls_J\": 0.1", "\"E_err_transfer_walls_share\": 0.025"}) {
    EXPECT_NE(body.find(kv), std::string::npos) << kv << " not in " << body;
  }
}

TEST(Progress, LineHasStepTimePercentDtEtaAndEnergyRatio) {
  const ProgressState s{1200, 0.06, 0.5, 5e-5, 1.2e-3, 1.0};
  EXPECT_EQ(format_progress(s, 42.0),
            "step 1200  t=0.0600/0.5000 s (12.0%)  dt=5.0e-05 s  ETA 0:00:42  E_k/E_p0=1.2e-03");
  const ProgressState no_gravity{10, 0.25, 1.0, 1e-4, 3.5e-2, 0.0};
  EXPECT_EQ(format_progress(no_gravity, 3725.0),
            "step 10  t=0.2500/1.0000 s (25.0%)  dt=1.0e-04 s  ETA 1:02:05  E_k=3.5e-02 J");
  EXPECT_EQ(format_duration(-1.0), "?");
}

TEST(RunDirectory, RefusesAFinishedRunUnlessForced) {
  TempDir dir("rundir", TempDir::kCreate);
  const std::string run = (dir.path() / "run").string();
  EXPECT_NO_THROW(check_run_directory(run, false));  // does not exist yet
  EXPECT_FALSE(fs::exists(run));                     // and checking did not create it
  create_run_directory(run, false);
  // What the pair launcher puts there first is accepted.
  std::ofstream(run + "/dem_port.txt") << "port";
  EXPECT_NO_THROW(check_run_directory(run, false));
  write_file_atomic(run + "/summary.json", "{}\n");
  EXPECT_FALSE(fs::exists(run + "/summary.json.tmp"));
  EXPECT_THROW(check_run_directory(run, false), RunDirectoryError);
  EXPECT_NO_THROW(create_run_directory(run, true));
  EXPECT_FALSE(fs::exists(run + "/summary.json"));  // the old run's outputs are gone
  EXPECT_TRUE(fs::exists(run + "/dem_port.txt"));   // the launcher's file is kept
}

// A resumed run's energies.csv written before the log had its last columns (W_transfer_walls
// came on 2026-11-26): the rows kept up to the checkpoint get "nan" in the new columns, the
// rows after it are dropped, and a log with the current header is cut as before.
TEST(RunDirectory, ResumedLogWithFewerColumnsIsPaddedWithNan) {
  TempDir d("log_pad", TempDir::kCreate);
  const std::string path = d.str() + "/energies.csv";
  auto write = [&](const std::string& text) { std::ofstream(path) << text; };
  auto read = [&] {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  write("time,step,E\n0.0,0,1.5\n0.1,1,1.4\n0.2,2,1.3\n");
  EXPECT_EQ(keep_rows_up_to_step(path, "time,step,E,W,V", 1, 1), 2u);
  EXPECT_EQ(read(), "time,step,E,W,V\n0.0,0,1.5,nan,nan\n0.1,1,1.4,nan,nan\n");
  write("time,step,E\n0.0,0,1.5\n0.1,1,1.4\n0.2,2,1.3\n");
  EXPECT_EQ(keep_rows_up_to_step(path, "time,step,E", 1, 1), 2u);
  EXPECT_EQ(read(), "time,step,E\n0.0,0,1.5\n0.1,1,1.4\n");
  // A header that is not a prefix (a column renamed, or E a prefix of a longer name) is not
  // padded.
  write("time,step,E\n0.0,0,1.5\n");
  EXPECT_EQ(keep_rows_up_to_step(path, "time,step,Ek", 1, 1), 1u);
  EXPECT_EQ(read(), "time,step,Ek\n0.0,0,1.5\n");
}

TEST(RunOutputs, AShortRunWritesEveryOutputConsistently) {
  TempDir dir("run", TempDir::kCreate);
  const std::string run = (dir.path() / "column").string();
  // The scene's path as given on the command line.
  const Scene scene =
      short_column().with([](Scene& s) { s.source_file = "some/where/../scene.yaml"; }).build();
  std::ostringstream log;
  const RunResult r = run_scene(scene, quiet_options(run, log));
  ASSERT_EQ(r.exit_code, 0) << log.str();
  EXPECT_EQ(r.summary.status, "complete");
  EXPECT_GT(r.summary.steps, 0);
  EXPECT_NE(log.str().find("time step: dt = "), std::string::npos) << log.str();

  const std::string summary = read_file(run + "/summary.json");
  EXPECT_NE(summary.find("\"status\": \"complete\""), std::string::npos);
  // The scene's path is made absolute, so tools find it from any directory.
  const std::string config = (fs::current_path() / "some/scene.yaml").string();
  EXPECT_NE(summary.find("\"config_file\": \"" + config + "\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"n_material_points\": " + std::to_string(r.summary.n_material_points)),
            std::string::npos);

  // energies.csv: first row at t = 0, E_d = E_p0 - E_p - E_k on every row, dt logged.
  const auto rows = read_csv(run + "/energies.csv");
  ASSERT_GE(rows.size(), 3u);
  EXPECT_EQ(std::stod(rows[1][0]), 0.0);
  EXPECT_EQ(rows.size() - 1, static_cast<std::size_t>(r.summary.steps) + 1);  // every step
  for (std::size_t k = 1; k < rows.size(); ++k) {
    ASSERT_EQ(rows[k].size(), 15u);
    const double E_p = std::stod(rows[k][3]), E_k = std::stod(rows[k][4]);
    const double E_d = std::stod(rows[k][5]), E_p0 = std::stod(rows[k][7]);
    EXPECT_NEAR(E_d, E_p0 - E_p - E_k, 1e-9 * std::abs(E_p0) + 1e-12);
    if (k > 1) {
      EXPECT_GT(std::stod(rows[k][2]), 0.0);  // dt of the step
    }
  }

  // Frames: t = 0, the middle and the end; the .pvd lists exactly the files present.
  const std::string pvd = read_file(run + "/frames.pvd");
  const std::regex dataset("file=\"(frame_\\d+\\.vtu)\"");
  std::size_t frames = 0;
  for (auto it = std::sregex_iterator(pvd.begin(), pvd.end(), dataset);
       it != std::sregex_iterator(); ++it, ++frames) {
    const Vtu vtu = parse_vtu(fs::path(run) / (*it)[1].str());
    EXPECT_EQ(vtu.points, r.summary.n_material_points);
  }
  EXPECT_EQ(frames, 3u);

  // Final state: as many points as the summary says, at the final time.
  const hid_t file = H5Fopen((run + "/final_state.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  std::vector<hsize_t> dims;
  const auto m = read_h5<double>(file, "mass", H5T_NATIVE_DOUBLE, dims);
  EXPECT_EQ(m.size(), r.summary.n_material_points);
  H5Fclose(file);

  // A second run into the same directory is refused without --force, and nothing is touched.
  const auto before = fs::last_write_time(run + "/summary.json");
  std::ostringstream log2;
  const RunResult again = run_scene(scene, quiet_options(run, log2));
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_NE(log2.str().find("--force"), std::string::npos) << log2.str();
  EXPECT_EQ(fs::last_write_time(run + "/summary.json"), before);
  RunOptions forced = quiet_options(run, log2);
  forced.force = true;
  EXPECT_EQ(run_scene(scene, forced).exit_code, 0);
}

// The program itself: a config error exits 2 and creates no run directory.
TEST(RunOutputs, ConfigErrorCreatesNoDirectory) {
  const std::string app = std::string(MPMDEM_BINARY_DIR) + "/mpm_app/mpm_app";
  ASSERT_TRUE(fs::exists(app)) << "build the mpm_app target first: " << app;
  TempDir dir("cfg", TempDir::kCreate);
  const fs::path bad = dir.path() / "bad.yaml";
  std::string text = read_file(source("configs/elastic_column.yaml"));
  text += "\nno_such_key: 1\n";
  std::ofstream(bad) << text;
  const fs::path run = dir.path() / "run";
  const std::string cmd = app + " " + bad.string() + " --out " + run.string() + " > /dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);
  EXPECT_FALSE(fs::exists(run));

  const std::string check = app + " --check-config " + bad.string() + " > /dev/null 2>&1";
  const int check_status = std::system(check.c_str());
  EXPECT_EQ(WEXITSTATUS(check_status), 2);
  const std::string ok = app + " --check-config " + source("configs/elastic_column.yaml") + " > " +
                         (dir.path() / "ok.txt").string() + " 2>&1";
  EXPECT_EQ(WEXITSTATUS(std::system(ok.c_str())), 0);
  EXPECT_EQ(read_file(dir.path() / "ok.txt").rfind("OK: ", 0), 0u);
}
