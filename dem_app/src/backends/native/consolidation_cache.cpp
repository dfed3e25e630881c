// Consolidated native RVE states on disk: see consolidation_cache.hpp.
#include "backends/native/consolidation_cache.hpp"

#include <unistd.h>

#include <atomic>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <system_error>
#include <type_traits>

#include "backends/native/binary_state.hpp"
#include "mpmdem/config_hash.hpp"

namespace mpmdem::dem::native {

namespace {

constexpr char kMagic[8] = {'M', 'P', 'M', 'D', 'C', 'C', '0', '1'};

template <typename T>
void put(std::string& b, const T& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  b.append(reinterpret_cast<const char*>(&v), sizeof v);
}

// Reads from a byte string; every read reports whether the bytes were there.
class Reader {
 public:
  explicit Reader(const std::string& b) : b_(b) {}
  template <typename T>
  bool get(T& v) {
    if (b_.size() - at_ < sizeof v) return false;
    std::memcpy(static_cast<void*>(&v), b_.data() + at_, sizeof v);
    at_ += sizeof v;
    return true;
  }
  bool get_bytes(std::string& s) {
    std::uint64_t n = 0;
    if (!get(n) || n > b_.size() - at_) return false;
    s.assign(b_, at_, n);
    at_ += n;
    return true;
  }
  std::size_t at() const { return at_; }

 private:
  const std::string& b_;
  std::size_t at_ = 0;
};

void put_bytes(std::string& b, const std::string& s) {
  put<std::uint64_t>(b, s.size());
  b += s;
}

}  // namespace

std::string encode_entry(const ConsolidationKey& key, const PreparedRve& p) {
  std::string body;
  put<std::int64_t>(body, p.steps);
  put<std::uint8_t>(body, p.converged ? 1 : 0);
  put(body, p.unbalanced);
  RveRecord r;
  r.state = p.state;
  body += encode(r);
  std::string out(kMagic, sizeof kMagic);
  put_bytes(out, key.bytes);
  put_bytes(out, body);
  put(out, fnv1a64(out));
  return out;
}

std::optional<PreparedRve> decode_entry(const std::string& bytes, const ConsolidationKey& key,
                                        std::string* why) {
  auto fail = [&](const char* what) {
    *why = what;
    return std::nullopt;
  };
  if (bytes.size() < sizeof kMagic + sizeof(std::uint64_t) ||
      std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) {
    return fail("not a consolidation cache entry (magic)");
  }
  Reader in(bytes);
  char magic[sizeof kMagic];
  for (char& c : magic) in.get(c);
  std::string stored_key, body;
  std::uint64_t checksum = 0;
  if (!in.get_bytes(stored_key) || !in.get_bytes(body)) return fail("truncated");
  const std::size_t summed = in.at();
  if (!in.get(checksum)) return fail("truncated (no checksum)");
  if (in.at() != bytes.size()) return fail("trailing bytes after the checksum");
  if (checksum != fnv1a64(std::string_view(bytes.data(), summed))) return fail("bad checksum");
  if (stored_key != key.bytes) return fail("holds another key (file name collision)");
  Reader b(body);
  PreparedRve p;
  std::int64_t steps = 0;
  std::uint8_t converged = 0;
  if (!b.get(steps) || !b.get(converged) || !b.get(p.unbalanced)) return fail("truncated body");
  p.steps = static_cast<long>(steps);
  p.converged = converged != 0;
  try {
    p.state = decode(body.substr(b.at())).state;
  } catch (const std::exception&) {
    return fail("the state does not decode");
  }
  return p;
}

ConsolidationCache::ConsolidationCache(std::filesystem::path dir, std::ostream& log)
    : dir_(std::move(dir)), log_(log) {
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec || !std::filesystem::is_directory(dir_)) {
    throw std::runtime_error("cannot create the consolidation cache folder " + dir_.string() +
                             " (coupling.native.consolidation_cache): " + ec.message());
  }
}

std::filesystem::path ConsolidationCache::file(const ConsolidationKey& key) const {
  return dir_ / (key.name() + ".consol");
}

std::optional<PreparedRve> ConsolidationCache::load(const ConsolidationKey& key) {
  const auto path = file(key);
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string why;
  std::optional<PreparedRve> p = decode_entry(bytes, key, &why);
  if (!p) {
    ++rejected_;
    log_ << "dem_app: WARNING: consolidation cache entry " << path.string() << " (" << bytes.size()
         << " bytes) is not used: " << why << "; consolidating again and rewriting it" << std::endl;
  }
  return p;
}

void ConsolidationCache::store(const ConsolidationKey& key, const PreparedRve& p) {
  static std::atomic<unsigned> counter{0};
  const auto path = file(key);
  // unique per process and call: several ranks (processes) and threads may write at once
  const auto tmp = dir_ / (path.filename().string() + ".tmp." + std::to_string(::getpid()) + "." +
                           std::to_string(counter++));
  const std::string bytes = encode_entry(key, p);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
      std::error_code ignored;
      std::filesystem::remove(tmp, ignored);
      throw std::runtime_error("cannot write the consolidation cache entry " + tmp.string() +
                               " (coupling.native.consolidation_cache)");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw std::runtime_error("cannot rename " + tmp.string() + " to " + path.string() + ": " +
                             ec.message());
  }
}

}  // namespace mpmdem::dem::native
