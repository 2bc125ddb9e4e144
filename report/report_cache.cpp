#include "report/report_cache.hpp"

#include <dlfcn.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <mutex>

#include "report/interpolation.hpp"

namespace cmr::report {

// ------------------------------------------------------------ SHA-256

namespace {

constexpr std::array<std::uint32_t, 64> kK = {
    0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4, 0xab1c5ed5,
    0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe, 0x9bdc06a7, 0xc19bf174,
    0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f, 0x4a7484aa, 0x5cb0a9dc, 0x76f988da,
    0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7, 0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967,
    0x27b70a85, 0x2e1b2138, 0x4d2c6dfc, 0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85,
    0xa2bfe8a1, 0xa81a664b, 0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070,
    0x19a4c116, 0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
    0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7, 0xc67178f2};

constexpr std::uint32_t rotr(std::uint32_t x, int n) { return (x >> n) | (x << (32 - n)); }

}  // namespace

KeyHasher::KeyHasher()
    : h_{0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a, 0x510e527f, 0x9b05688c, 0x1f83d9ab, 0x5be0cd19} {}

void KeyHasher::block(const std::uint8_t* p) {
  std::uint32_t w[64];
  for (int i = 0; i < 16; ++i)
    w[i] = std::uint32_t{p[4 * i]} << 24 | std::uint32_t{p[4 * i + 1]} << 16 | std::uint32_t{p[4 * i + 2]} << 8 |
           std::uint32_t{p[4 * i + 3]};
  for (int i = 16; i < 64; ++i) {
    const std::uint32_t s0 = rotr(w[i - 15], 7) ^ rotr(w[i - 15], 18) ^ (w[i - 15] >> 3);
    const std::uint32_t s1 = rotr(w[i - 2], 17) ^ rotr(w[i - 2], 19) ^ (w[i - 2] >> 10);
    w[i] = w[i - 16] + s0 + w[i - 7] + s1;
  }
  std::uint32_t a = h_[0], b = h_[1], c = h_[2], d = h_[3], e = h_[4], f = h_[5], g = h_[6], h = h_[7];
  for (int i = 0; i < 64; ++i) {
    const std::uint32_t t1 = h + (rotr(e, 6) ^ rotr(e, 11) ^ rotr(e, 25)) + ((e & f) ^ (~e & g)) + kK[i] + w[i];
    const std::uint32_t t2 = (rotr(a, 2) ^ rotr(a, 13) ^ rotr(a, 22)) + ((a & b) ^ (a & c) ^ (b & c));
    h = g;
    g = f;
    f = e;
    e = d + t1;
    d = c;
    c = b;
    b = a;
    a = t1 + t2;
  }
  h_[0] += a, h_[1] += b, h_[2] += c, h_[3] += d, h_[4] += e, h_[5] += f, h_[6] += g, h_[7] += h;
}

KeyHasher& KeyHasher::bytes(const void* data, std::size_t n) {
  const auto* p = static_cast<const std::uint8_t*>(data);
  total_ += n;
  if (used_ > 0) {
    const std::size_t take = std::min(n, buf_.size() - used_);
    std::memcpy(buf_.data() + used_, p, take);
    used_ += take, p += take, n -= take;
    if (used_ < buf_.size()) return *this;
    block(buf_.data());
    used_ = 0;
  }
  for (; n >= 64; p += 64, n -= 64) block(p);
  std::memcpy(buf_.data(), p, n);
  used_ = n;
  return *this;
}

KeyHasher& KeyHasher::add(std::uint64_t v) {
  std::uint8_t b[8];
  for (int i = 0; i < 8; ++i) b[i] = static_cast<std::uint8_t>(v >> (8 * i));
  return bytes(b, 8);
}

KeyHasher& KeyHasher::add(std::string_view s) {
  add(static_cast<std::uint64_t>(s.size()));
  return bytes(s.data(), s.size());
}

KeyHasher& KeyHasher::add(double v) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &v, sizeof bits);
  return add(bits);
}

CacheKey KeyHasher::finish() {
  const std::uint64_t bits = total_ * 8;
  const std::uint8_t one = 0x80, zero = 0;
  bytes(&one, 1);
  while (used_ != 56) bytes(&zero, 1);
  std::uint8_t len[8];
  for (int i = 0; i < 8; ++i) len[i] = static_cast<std::uint8_t>(bits >> (8 * (7 - i)));
  bytes(len, 8);
  CacheKey k{};
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 4; ++j) k[4 * i + j] = static_cast<std::uint8_t>(h_[i] >> (8 * (3 - j)));
  return k;
}

std::string hex(const CacheKey& k) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string s;
  for (std::uint8_t b : k) s += kDigits[b >> 4], s += kDigits[b & 15];
  return s;
}

// ------------------------------------------------------------ build id

namespace {

std::string hash_file(const char* path) {
  const int fd = ::open(path, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return {};
  KeyHasher h;
  char buf[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      ::close(fd);
      return {};
    }
    if (n == 0) break;
    h.bytes(buf, static_cast<std::size_t>(n));
  }
  ::close(fd);
  return hex(h.finish());
}

}  // namespace

const std::string& build_id() {
  static const std::string id = [] {
    // The file holding this function: the cmr executable, or the Python
    // module that links the report library.
    Dl_info info{};
    if (::dladdr(reinterpret_cast<void*>(&build_id), &info) != 0 && info.dli_fname != nullptr &&
        info.dli_fname[0] == '/') {
      std::string h = hash_file(info.dli_fname);
      if (!h.empty()) return h;
    }
    return hash_file("/proc/self/exe");
  }();
  return id;
}

// ------------------------------------------------------------ payloads

namespace {

struct Out {
  std::string s;
  void u64(std::uint64_t v) {
    for (int i = 0; i < 8; ++i) s += static_cast<char>(v >> (8 * i));
  }
  void str(std::string_view v) {
    u64(v.size());
    s.append(v);
  }
  void f64(double v) {
    std::uint64_t b = 0;
    std::memcpy(&b, &v, sizeof b);
    u64(b);
  }
};

struct In {
  std::string_view s;
  bool ok = true;
  std::uint64_t u64() {
    if (s.size() < 8) return ok = false, 0;
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= std::uint64_t{static_cast<unsigned char>(s[i])} << (8 * i);
    s.remove_prefix(8);
    return v;
  }
  std::string str() {
    const std::uint64_t n = u64();
    if (!ok || n > s.size()) return ok = false, std::string();
    std::string v(s.substr(0, n));
    s.remove_prefix(n);
    return v;
  }
  double f64() {
    const std::uint64_t b = u64();
    double v = 0;
    std::memcpy(&v, &b, sizeof v);
    return v;
  }
  /// A count of things each at least `least` bytes long: no more than the bytes left allow.
  std::uint64_t count(std::size_t least) {
    const std::uint64_t n = u64();
    if (!ok || n > s.size() / least) return ok = false, 0;
    return n;
  }
};

}  // namespace

std::string encode(const CachedGlyph& g) {
  Out o;
  o.str("glyph");
  o.str(g.html.row);
  o.str(g.html.details);
  o.u64(g.html.pass ? 1 : 0);
  o.u64(static_cast<std::uint64_t>(g.html.contours));
  o.u64(static_cast<std::uint64_t>(g.html.contours_fail));
  o.u64(g.items.size());
  for (const CachedItem& it : g.items) {
    o.str(it.json);
    o.str(it.error);
    o.u64(it.pass ? 1 : 0);
    o.u64(it.gate_pass.size());
    for (bool b : it.gate_pass) o.u64(b ? 1 : 0);
    o.u64(it.findings.size());
    for (const Finding& f : it.findings) {
      o.str(f.file);
      o.str(f.glyph);
      o.u64(static_cast<std::uint64_t>(static_cast<std::int64_t>(f.contour)));
      o.str(f.node);
      o.str(f.gate);
      o.str(f.message);
      o.str(f.source);
      o.u64(static_cast<std::uint64_t>(static_cast<std::int64_t>(f.line)));
      o.f64(f.severity);
      o.u64(f.info ? 1 : 0);
    }
  }
  return std::move(o.s);
}

bool decode(std::string_view bytes, CachedGlyph& g) {
  In in{bytes};
  if (in.str() != "glyph") return false;
  g = CachedGlyph{};
  g.html.row = in.str();
  g.html.details = in.str();
  g.html.pass = in.u64() != 0;
  g.html.contours = static_cast<int>(in.u64());
  g.html.contours_fail = static_cast<int>(in.u64());
  const std::uint64_t items = in.count(40);
  for (std::uint64_t i = 0; in.ok && i < items; ++i) {
    CachedItem it;
    it.json = in.str();
    it.error = in.str();
    it.pass = in.u64() != 0;
    const std::uint64_t gates = in.count(8);
    for (std::uint64_t k = 0; in.ok && k < gates; ++k) it.gate_pass.push_back(in.u64() != 0);
    const std::uint64_t findings = in.count(96);
    for (std::uint64_t k = 0; in.ok && k < findings; ++k) {
      Finding f;
      f.file = in.str();
      f.glyph = in.str();
      f.contour = static_cast<int>(static_cast<std::int64_t>(in.u64()));
      f.node = in.str();
      f.gate = in.str();
      f.message = in.str();
      f.source = in.str();
      f.line = static_cast<int>(static_cast<std::int64_t>(in.u64()));
      f.severity = in.f64();
      f.info = in.u64() != 0;
      it.findings.push_back(std::move(f));
    }
    if (it.json.find("\"s0\"") == std::string::npos) return false;  // every spline object carries its id
    g.items.push_back(std::move(it));
  }
  return in.ok && in.s.empty() && static_cast<int>(g.items.size()) == g.html.contours;
}

// ------------------------------------------------------------ the file

namespace {

constexpr std::string_view kMagic = "cmr report cache 1\n";
constexpr std::size_t kRecordHead = 32 + 8 + 32;

bool read_at(int fd, std::uint64_t offset, char* to, std::size_t n) {
  while (n > 0) {
    const ssize_t got = ::pread(fd, to, n, static_cast<off_t>(offset));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) return false;
    to += got, n -= static_cast<std::size_t>(got), offset += static_cast<std::uint64_t>(got);
  }
  return true;
}

}  // namespace

std::string cache_header() { return std::string(kMagic) + build_id() + "\n"; }

std::string cache_record(const CacheKey& key, const CachedGlyph& g) {
  const std::string payload = encode(g);
  KeyHasher h;
  h.bytes(payload.data(), payload.size());
  const CacheKey sum = h.finish();
  std::string r(reinterpret_cast<const char*>(key.data()), key.size());
  for (int i = 0; i < 8; ++i) r += static_cast<char>(static_cast<std::uint64_t>(payload.size()) >> (8 * i));
  r.append(reinterpret_cast<const char*>(sum.data()), sum.size());
  return r + payload;
}

std::size_t ReportCache::KeyHash::operator()(const CacheKey& k) const {
  std::size_t v = 0;
  std::memcpy(&v, k.data(), sizeof v);
  return v;
}

ReportCache::~ReportCache() {
  if (fd_ >= 0) ::close(fd_);
}

void ReportCache::open(const std::filesystem::path& file, std::string& note) {
  file_ = file;
  const auto ignored = [&](const std::string& why) {
    note = file.string() + ": ignored, every glyph judged again: " + why;
    index_.clear();
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  };
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
  if (fd < 0) {
    if (errno == ENOENT) return;
    if (errno == ELOOP) return ignored("a symbolic link (a cache is only read from cmr's own file)");
    return ignored(std::strerror(errno));
  }
  fd_ = fd;
  struct stat st {};
  if (::fstat(fd, &st) != 0) return ignored(std::strerror(errno));
  if (!S_ISREG(st.st_mode)) return ignored("not a regular file");
  if (st.st_uid != ::geteuid()) return ignored("not this user's own file");
  const std::uint64_t size = static_cast<std::uint64_t>(st.st_size);
  const std::string header = cache_header();
  std::string head(header.size(), '\0');
  if (size < header.size() || !read_at(fd, 0, head.data(), head.size()) || head.compare(0, kMagic.size(), kMagic) != 0)
    return ignored("not a cmr report cache");
  if (build_id().empty()) return ignored("this build of cmr cannot read its own executable to name its build");
  if (head != header) return ignored("written by another build of cmr");
  for (std::uint64_t at = header.size(); at < size;) {
    char rec[kRecordHead];
    if (size - at < kRecordHead || !read_at(fd, at, rec, kRecordHead))
      return ignored("cut short at byte " + std::to_string(at));
    CacheKey key{};
    std::memcpy(key.data(), rec, 32);
    std::uint64_t length = 0;
    for (int i = 0; i < 8; ++i) length |= std::uint64_t{static_cast<unsigned char>(rec[32 + i])} << (8 * i);
    Record r;
    r.offset = at + kRecordHead;
    r.length = length;
    std::memcpy(r.checksum.data(), rec + 40, 32);
    if (length > size - r.offset) return ignored("cut short at byte " + std::to_string(at));
    index_[key] = r;
    at = r.offset + length;
  }
}

std::optional<CachedGlyph> ReportCache::find(const CacheKey& key) const {
  if (fd_ < 0) return std::nullopt;
  const auto it = index_.find(key);
  if (it == index_.end()) return std::nullopt;
  std::string payload(it->second.length, '\0');
  KeyHasher h;
  CachedGlyph g;
  if (!read_at(fd_, it->second.offset, payload.data(), payload.size()) ||
      h.bytes(payload.data(), payload.size()).finish() != it->second.checksum || !decode(payload, g)) {
    ++damaged_;
    return std::nullopt;
  }
  return g;
}

std::string ReportCache::damage_note() const {
  const int n = damaged_.load();
  if (n == 0) return {};
  return file_.string() + ": " + std::to_string(n) + (n == 1 ? " record" : " records") +
         " did not match its checksum; judged again";
}

// ------------------------------------------------------------ keys

namespace {

void add_spline(KeyHasher& h, const BSpline& s) {
  h.add(s.name()).add_int(s.degree()).add_int(s.closed() ? 1 : 0);
  h.add(static_cast<std::uint64_t>(s.knots().size()));
  for (double k : s.knots()) h.add(k);
  h.add(static_cast<std::uint64_t>(s.points().size()));
  for (const Vec2& p : s.points()) h.add(p.x).add(p.y);
  h.add(static_cast<std::uint64_t>(s.weights().size()));
  for (double w : s.weights()) h.add(w);
}

template <class T, class F>
void add_list(KeyHasher& h, const std::vector<T>& v, F each) {
  h.add(static_cast<std::uint64_t>(v.size()));
  for (const T& x : v) each(x);
}

}  // namespace

std::string run_key_prefix(const BatchOptions& options) {
  // Every field of ReportOptions that can change a glyph's output. A new
  // field must be added here (and the size below updated). show_fields (how
  // a message's marked fields read) is the program's own table, the CLI's in
  // cmr and the keywords' in the Python module: the build id in the key
  // tells the two apart.
  static_assert(sizeof(ReportOptions) == 184, "ReportOptions changed: add the new field to the resume cache's key");
  const ReportOptions& o = options.report;
  KeyHasher h;
  h.add(std::string_view("cmr report cache key 1")).add(build_id());
  h.add_int(o.require ? 1 : 0);
  if (o.require)
    h.add(to_string(*o.require)).add_int(static_cast<int>(o.require->mode)).add_int(o.require->split.value_or(-1))
        .add_int(static_cast<int>(o.require->extremum));
  h.add_int(o.max_depth).add_int(o.regions ? 1 : 0).add_int(o.region_size);
  h.add(o.backend ? o.backend->name() : std::string("none"));
  h.add(o.roots.tolerance).add(o.continuity.angle_deg).add(o.continuity.curvature_rel);
  h.add_int(o.segments ? 1 : 0).add_int(o.segments ? o.segments->first : 0).add_int(o.segments ? o.segments->last : 0);
  add_list(h, o.gates, [&](const Gate& g) {
    h.add(to_string(g)).add_int(static_cast<int>(g.kind)).add_int(g.max_extrema).add(g.tolerance).add(g.overshoot)
        .add(g.turn_degrees);
  });
  h.add_int(o.certified_fixes ? 1 : 0).add(o.constant_tolerance).add(o.min_severity).add_int(o.font_severity ? 1 : 0)
      .add_int(o.strict ? 1 : 0);
  // What the batch changes in a file's options and output.
  h.add_int(options.fixes ? 1 : 0).add_int(options.pretty ? 1 : 0);
  add_list(h, options.location, [&](const auto& axis) { h.add(axis.first).add(axis.second); });
  h.add_int(options.between ? 1 : 0);
  const auto add_location = [&](const import::Location& l) {
    add_list(h, l, [&](const auto& axis) { h.add(axis.first).add(axis.second); });
  };
  if (options.between) add_location(options.between->first), add_location(options.between->second);
  const CacheKey k = h.finish();
  return std::string(reinterpret_cast<const char*>(k.data()), k.size());
}

std::string file_key_prefix(const std::string& run_prefix, const std::string& path, const std::string& name,
                            const std::string& uri, bool uri_relative, const FontInfo& font) {
  KeyHasher h;
  h.add(run_prefix).add(path).add(name).add(uri).add_int(uri_relative ? 1 : 0);
  h.add(font.path).add(font.family).add(font.style).add_int(font.units_per_em).add_int(font.cubic ? 1 : 0);
  add_list(h, font.missing, [&](std::uint32_t c) { h.add(static_cast<std::uint64_t>(c)); });
  const CacheKey k = h.finish();
  return std::string(reinterpret_cast<const char*>(k.data()), k.size());
}

CacheKey glyph_key(const std::string& file_prefix, const FontInfo::GlyphEntry& g, const std::vector<ReportInput>& inputs) {
  KeyHasher h;
  h.add(file_prefix).add(g.name).add(static_cast<std::uint64_t>(g.codepoint)).add(g.source);
  const auto add_strings = [&](const std::vector<std::string>& v) { add_list(h, v, [&](const std::string& s) { h.add(s); }); };
  const auto add_ints = [&](const std::vector<int>& v) { add_list(h, v, [&](int x) { h.add_int(x); }); };
  add_list(h, g.joint_names, add_strings);
  add_list(h, g.point_names, add_strings);
  add_list(h, g.point_lines, add_ints);
  add_list(h, g.joint_lines, add_ints);
  add_list(h, g.items, [&](std::size_t i) {
    const ReportInput& in = inputs.at(i);
    h.add(in.file).add(in.error).add_int(in.spline ? 1 : 0);
    if (in.spline) add_spline(h, *in.spline);
    h.add_int(in.motions ? 1 : 0);
    if (!in.motions) return;
    add_list(h, *in.motions, [&](const import::ContourMotion& m) {
      h.add_int(m.piece ? 1 : 0);
      if (m.piece) {
        const import::Piece& p = *m.piece;
        h.add(p.s0).add(p.s1).add(p.from).add(p.to).add(p.master_a).add(p.master_b);
        add_list(h, p.axes, [&](const import::PieceAxis& a) {
          h.add(a.name).add(a.tag);
          add_list(h, a.at, [&](const std::pair<double, double>& x) { h.add(x.first).add(x.second); });
        });
      }
      add_spline(h, m.a);
      add_spline(h, m.b);
      add_list(h, m.smooth, [&](bool b) { h.add_int(b ? 1 : 0); });
    });
  });
  return h.finish();
}

}  // namespace cmr::report
