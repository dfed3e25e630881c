// YADE backend: embeds Python, imports mpmdem_rve, forwards each exchange as one call.
#include "yade_backend.hpp"

#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <omp.h>

#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "coupling_rules.hpp"

namespace mpmdem::dem {
namespace {

constexpr int kReplyWidth = 19;  // doubles per RVE from mpmdem_rve.REPLY_WIDTH
bool g_python_used = false;      // Python cannot be re-initialised with YADE loaded

// The pending Python error as text ("Type: message"), cleared.
std::string python_error() {
  PyObject *type = nullptr, *value = nullptr, *trace = nullptr;
  PyErr_Fetch(&type, &value, &trace);
  std::string text = "unknown Python error";
  if (value != nullptr) {
    PyObject* s = PyObject_Str(value);
    if (s != nullptr && PyUnicode_Check(s)) text = PyUnicode_AsUTF8(s);
    Py_XDECREF(s);
  }
  if (type != nullptr)
    text = std::string(reinterpret_cast<PyTypeObject*>(type)->tp_name) + ": " + text;
  Py_XDECREF(type);
  Py_XDECREF(value);
  Py_XDECREF(trace);
  return text;
}

PyObject* checked(PyObject* o, const char* what) {
  if (o == nullptr)
    throw std::runtime_error(std::string("yade backend: ") + what + ": " + python_error());
  return o;
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// coupling.yade.packing_dir; a relative one is relative to the scene file's folder.
std::string packing_dir(const config::Config& cfg) {
  const std::string d = cfg.string("coupling.yade.packing_dir");
  if (d.empty() || std::filesystem::path(d).is_absolute()) return d;
  return (std::filesystem::path(cfg.file()).parent_path() / d).lexically_normal().string();
}

class YadeBackend final : public RveBackend {
 public:
  YadeBackend(const config::Config& cfg, const BackendContext& ctx) : ctx_(ctx) {
    check_rve_backend(cfg, "yade");
    std::ostringstream p;
    p.precision(17);
    p << "{\"packing_dir\": " << json_string(packing_dir(cfg)) << ", \"packings\": [";
    const auto names = cfg.strings("coupling.yade.packings");
    for (std::size_t i = 0; i < names.size(); ++i) p << (i ? ", " : "") << json_string(names[i]);
    p << "], \"seed\": " << cfg.integer("coupling.yade.seed")
      << ", \"inline_packing\": {\"n_spheres\": " << cfg.integer("coupling.yade.inline_spheres")
      << ", \"porosity_init\": 0.65, \"max_strain_rate\": 10.0}"
      << ", \"ns_rule\": " << json_string(cfg.string("coupling.yade.ns_rule"))
      << ", \"ns\": " << cfg.integer("coupling.yade.ns")
      << ", \"ns_factor\": " << cfg.number("coupling.yade.ns_factor")
      << ", \"ns_min\": " << cfg.integer("coupling.yade.ns_min")
      << ", \"ns_max\": " << cfg.integer("coupling.yade.ns_max")
      << ", \"damping\": " << cfg.number("coupling.yade.damping")
      << ", \"time_step_scale\": " << cfg.number("coupling.yade.time_step_scale")
      << ", \"ke_threshold\": " << cfg.number("coupling.yade.ke_threshold")
      << ", \"stiffness\": " << json_string(cfg.string("coupling.yade.stiffness"))
      << ", \"consolidation_tol\": " << cfg.number("coupling.yade.consolidation_tol")
      << ", \"consolidation_unbalanced\": " << cfg.number("coupling.yade.consolidation_unbalanced")
      << ", \"consolidation_max_steps\": " << cfg.integer("coupling.yade.consolidation_max_steps");
    // The law, and FrictViscoMat.betan as the native backend computes it (17 digits: the
    // same double on both sides).
    const native::ContactLaw law = contact_law(cfg, "yade");
    p << ", \"contact_law\": " << json_string(native::contact_law_name(law.kind))
      << ", \"restitution_normal\": " << law.restitution_n << ", \"beta_n\": " << law.beta_n;
    params_ = p.str();
  }

  ~YadeBackend() override {
    if (!Py_IsInitialized()) return;
    Py_XDECREF(set_);
    Py_FinalizeEx();  // before MPI_Finalize (the server destroys its backend first)
  }

  std::string name() const override { return "yade"; }

  void setup(const BackendContext& ctx) override {
    ctx_ = ctx;
    if (g_python_used) {
      throw std::logic_error("yade backend: Python was already finalized in this process");
    }
    g_python_used = true;
    // One thread per RVE is fastest; ranks parallelise. The environment reaches YADE's
    // OpenMP only if libgomp is not loaded yet; dem_app links it (native backend), so the
    // calling thread's thread count is set too (YADE steps in this thread: O.step()).
    setenv("OMP_NUM_THREADS", "1", 1);
    omp_set_num_threads(1);
    struct sigaction old_int {};
    sigaction(SIGINT, nullptr, &old_int);
    Py_InitializeEx(0);  // 0: Python installs no signal handlers of its own
    PyObject* sys_path = PySys_GetObject("path");  // borrowed
    PyObject* dir = checked(PyUnicode_FromString(MPMDEM_PYTHON_DIR), "python dir");
    PyList_Insert(sys_path, 0, dir);
    Py_DECREF(dir);
    PyObject* mod = checked(PyImport_ImportModule("mpmdem_rve"), "import mpmdem_rve");
    std::ostringstream p;
    p << params_ << ", \"first_rve\": " << ctx_.first_rve << ", \"n_rve\": " << ctx_.n_rve
      << ", \"outputs\": " << ctx_.outputs << "}";
    set_ = PyObject_CallMethod(mod, "make", "s", p.str().c_str());
    Py_DECREF(mod);
    checked(set_, "mpmdem_rve.make");
    // Importing YADE installs a SIGINT handler: give the host its own back.
    sigaction(SIGINT, &old_int, nullptr);
  }

  void initialise(const protocol::RveInit* init, protocol::RveReply* reply) override {
    std::vector<double> s(9 * ctx_.n_rve);
    std::vector<std::uint64_t> point(ctx_.n_rve);
    for (std::size_t k = 0; k < ctx_.n_rve; ++k) {
      std::memcpy(&s[9 * k], init[k].stress, 9 * sizeof(double));
      point[k] = init[k].point;
    }
    PyObject* r =
        PyObject_CallMethod(set_, "initialise", "y#y#", reinterpret_cast<const char*>(s.data()),
                            static_cast<Py_ssize_t>(s.size() * sizeof(double)),
                            reinterpret_cast<const char*>(point.data()),
                            static_cast<Py_ssize_t>(point.size() * sizeof(std::uint64_t)));
    unpack(checked(r, "initialise"), reply);
  }

  void step(const protocol::ControlHeader& header, const protocol::RveRequest* req,
            protocol::RveReply* reply) override {
    dF_.resize(9 * ctx_.n_rve);
    flags_.resize(ctx_.n_rve);
    dt_.resize(ctx_.n_rve);
    for (std::size_t k = 0; k < ctx_.n_rve; ++k) {
      std::memcpy(&dF_[9 * k], req[k].dF, 9 * sizeof(double));
      flags_[k] = req[k].flags;
      dt_[k] = req[k].dt;
    }
    PyObject* r = PyObject_CallMethod(
        set_, "step", "y#y#Ly#", reinterpret_cast<const char*>(dF_.data()),
        static_cast<Py_ssize_t>(dF_.size() * sizeof(double)),
        reinterpret_cast<const char*>(flags_.data()),
        static_cast<Py_ssize_t>(flags_.size() * sizeof(std::uint32_t)),
        static_cast<long long>(header.step), reinterpret_cast<const char*>(dt_.data()),
        static_cast<Py_ssize_t>(dt_.size() * sizeof(double)));
    unpack(checked(r, "step"), reply);
  }

  void checkpoint(const std::filesystem::path& dir) override { call_dir("checkpoint", dir); }
  void restore(const std::filesystem::path& dir) override { call_dir("restore", dir); }

  std::string last_fault_message() const override { return fault_; }

  std::string export_rve(std::uint64_t gid) override {
    PyObject* r = checked(
        PyObject_CallMethod(set_, "export", "K", static_cast<unsigned long long>(gid)), "export");
    char* data = nullptr;
    Py_ssize_t size = 0;
    if (!PyBytes_Check(r) || PyBytes_AsStringAndSize(r, &data, &size) != 0) {
      Py_DECREF(r);
      throw std::runtime_error("yade backend: mpmdem_rve.export did not return bytes");
    }
    std::string blob(data, static_cast<std::size_t>(size));
    Py_DECREF(r);
    return blob;
  }

  void adopt(std::uint64_t first_rve, std::uint64_t n_rve,
             std::map<std::uint64_t, std::string> incoming) override {
    PyObject* dict = checked(PyDict_New(), "adopt");
    for (const auto& [gid, blob] : incoming) {
      PyObject* key = PyLong_FromUnsignedLongLong(gid);
      PyObject* value =
          PyBytes_FromStringAndSize(blob.data(), static_cast<Py_ssize_t>(blob.size()));
      const int rc = (key && value) ? PyDict_SetItem(dict, key, value) : -1;
      Py_XDECREF(key);
      Py_XDECREF(value);
      if (rc != 0) {
        Py_DECREF(dict);
        checked(nullptr, "adopt");
      }
    }
    PyObject* r =
        PyObject_CallMethod(set_, "adopt", "KKO", static_cast<unsigned long long>(first_rve),
                            static_cast<unsigned long long>(n_rve), dict);
    Py_DECREF(dict);
    Py_DECREF(checked(r, "adopt"));
    ctx_.first_rve = first_rve;
    ctx_.n_rve = n_rve;
  }

 private:
  // Checkpoints are per RVE (dir/rve_<id>.*, whichever rank wrote them), so that any rank
  // count restores them (older ones: dir/rank_<r>/rve_<id>.*, still read).
  void call_dir(const char* method, const std::filesystem::path& dir) {
    PyObject* r = PyObject_CallMethod(set_, method, "s", dir.string().c_str());
    Py_DECREF(checked(r, method));
  }

  // (bytes, [fault messages]) -> replies and fault_.
  void unpack(PyObject* result, protocol::RveReply* reply) {
    PyObject* bytes = PyTuple_GetItem(result, 0);
    PyObject* faults = PyTuple_GetItem(result, 1);
    if (bytes == nullptr || !PyBytes_Check(bytes) ||
        PyBytes_Size(bytes) != static_cast<Py_ssize_t>(kReplyWidth * sizeof(double) * ctx_.n_rve)) {
      Py_DECREF(result);
      throw std::runtime_error("yade backend: mpmdem_rve returned a reply of the wrong size");
    }
    const auto* v = reinterpret_cast<const double*>(PyBytes_AsString(bytes));
    for (std::size_t k = 0; k < ctx_.n_rve; ++k) {
      const double* r = v + kReplyWidth * k;
      protocol::RveReply& out = reply[k];
      std::memcpy(out.stress, r, 9 * sizeof(double));
      std::memcpy(out.rotation, r + 9, 3 * sizeof(double));
      out.porosity = r[12];
      out.coordination = r[13];
      out.unbalanced_force = r[14];
      out.stiffness = r[15];
      out.status = static_cast<std::int32_t>(r[16]);
      out.n_substeps = static_cast<std::int32_t>(r[17]);
      out.cost_s = r[18];
    }
    fault_.clear();
    for (Py_ssize_t i = 0; faults != nullptr && i < PyList_Size(faults); ++i) {
      const char* msg = PyUnicode_AsUTF8(PyList_GetItem(faults, i));
      if (msg != nullptr) fault_ += (fault_.empty() ? "" : "; ") + std::string(msg);
    }
    Py_DECREF(result);
  }

  BackendContext ctx_;
  std::string params_;
  PyObject* set_ = nullptr;
  std::vector<double> dF_;
  std::vector<std::uint32_t> flags_;
  std::vector<double> dt_;  // each update's dt (ns_rule rate)
  std::string fault_;
};

}  // namespace

std::unique_ptr<RveBackend> make_yade_backend(const config::Config& cfg,
                                              const BackendContext& ctx) {
  return std::make_unique<YadeBackend>(cfg, ctx);
}

}  // namespace mpmdem::dem
