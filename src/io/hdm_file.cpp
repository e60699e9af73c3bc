// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/io/hdm_file.h>
#include <hdm/io/read_file.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <type_traits>
#include <limits>
#include <string>
#include <vector>

#include <unistd.h>

namespace hdm {
namespace {

constexpr char kMagic[4] = {'H', 'D', 'M', '\0'};
constexpr size_t kChecksumBytes = 8;

constexpr uint64_t kFnvBasis = 14695981039346656037ull;

uint64_t fnv1a64(const uint8_t* data, size_t size, uint64_t h = kFnvBasis) {
  for (size_t k = 0; k < size; ++k) h = (h ^ data[k]) * 1099511628211ull;
  return h;
}

// ---- writing: every value goes through put_bits, which stores little-endian ----

// Bytes go to the sink in pieces of about 1 MiB, hashed on the way (the file's checksum), so a
// save holds one piece of the file, not the whole of it.
class Writer {
 public:
  explicit Writer(FileSink& sink) : sink_(sink) { bytes_.reserve(kPiece + 64); }

  template <class U>
  void put_bits(U bits) {
    for (size_t k = 0; k < sizeof(U); ++k) bytes_.push_back(static_cast<uint8_t>(bits >> (8 * k)));
    if (bytes_.size() >= kPiece) flush();
  }
  // Appends @p size raw bytes.
  void put_raw(const uint8_t* p, size_t size) {
    while (size > 0) {  // the piece is below kPiece bytes between calls
      const size_t n = std::min(size, kPiece - bytes_.size());
      bytes_.insert(bytes_.end(), p, p + n);
      p += n, size -= n;
      if (bytes_.size() >= kPiece) flush();
    }
  }
  // Writes the piece, hashed.
  void flush() {
    hash_ = fnv1a64(bytes_.data(), bytes_.size(), hash_);
    sink_.write(bytes_.data(), bytes_.size());
    bytes_.clear();
  }
  // The checksum of every byte so far (FNV-1a 64), then the end of the file.
  void finish() {
    flush();
    uint8_t tail[8];
    for (size_t k = 0; k < 8; ++k) tail[k] = static_cast<uint8_t>(hash_ >> (8 * k));
    sink_.write(tail, 8);
  }
  void put(int32_t v) { put_bits(static_cast<uint32_t>(v)); }
  void put(uint32_t v) { put_bits(v); }
  void put(int64_t v) { put_bits(static_cast<uint64_t>(v)); }
  void put(uint64_t v) { put_bits(v); }
  void put(float v) { put_bits(std::bit_cast<uint32_t>(v)); }
  void put(double v) { put_bits(std::bit_cast<uint64_t>(v)); }
  void tag(const char (&t)[5], uint64_t count) {
    put_raw(reinterpret_cast<const uint8_t*>(t), 4);
    put(count);
  }

 private:
  static constexpr size_t kPiece = size_t(1) << 20;
  std::vector<uint8_t> bytes_;  // the piece not yet written
  FileSink& sink_;
  uint64_t hash_ = kFnvBasis;
};

// ---- reading: bounds-checked cursor over the file's bytes ----

class Reader {
 public:
  Reader(const std::string& path, std::span<const uint8_t> bytes) : path_(path), bytes_(bytes) {}

  /// Bytes left before the trailing checksum.
  size_t payload_left() const {
    const size_t end = bytes_.size() >= kChecksumBytes ? bytes_.size() - kChecksumBytes : 0;
    return end > pos_ ? end - pos_ : 0;
  }
  size_t position() const { return pos_; }
  /// Returns the next @p n bytes and moves past them; @p n was checked by section().
  const uint8_t* take(size_t n) {
    const uint8_t* p = bytes_.data() + pos_;
    pos_ += n;
    return p;
  }

  template <class U>
  U get_bits(const char* what) {
    if (bytes_.size() - pos_ < sizeof(U))
      throw IoError(path_ + ": truncated (file ends inside " + what + " at byte " + std::to_string(pos_) + ")");
    U bits = 0;
    for (size_t k = 0; k < sizeof(U); ++k) bits |= static_cast<U>(bytes_[pos_ + k]) << (8 * k);
    pos_ += sizeof(U);
    return bits;
  }
  void get(int32_t& v, const char* what) { v = static_cast<int32_t>(get_bits<uint32_t>(what)); }
  void get(int64_t& v, const char* what) { v = static_cast<int64_t>(get_bits<uint64_t>(what)); }
  void get(float& v, const char* what) { v = std::bit_cast<float>(get_bits<uint32_t>(what)); }
  void get(double& v, const char* what) { v = std::bit_cast<double>(get_bits<uint64_t>(what)); }

  /// Reads a section header and returns its element count, after checking that @p element_bytes
  /// times the count fits in what is left of the file (so a corrupt count never allocates).
  uint64_t section(const char (&t)[5], size_t element_bytes) {
    const size_t at = pos_;
    if (payload_left() < 12)
      throw IoError(path_ + ": truncated (file ends before section " + t + " at byte " + std::to_string(at) + ")");
    if (std::memcmp(&bytes_[pos_], t, 4) != 0)
      throw IoError(path_ + ": corrupt (expected section " + t + " at byte " + std::to_string(at) + ")");
    pos_ += 4;
    const uint64_t count = get_bits<uint64_t>(t);
    if (count > payload_left() / element_bytes)
      throw IoError(path_ + ": truncated or corrupt (section " + t + " at byte " + std::to_string(at) + " claims " +
                    std::to_string(count) + " elements of " + std::to_string(element_bytes) + " bytes, only " +
                    std::to_string(payload_left()) + " bytes remain)");
    return count;
  }
  void fixed_section(const char (&t)[5], size_t element_bytes, uint64_t expected) {
    const size_t at = pos_;
    const uint64_t count = section(t, element_bytes);
    if (count != expected)
      throw IoError(path_ + ": corrupt (section " + t + " at byte " + std::to_string(at) + " has " +
                    std::to_string(count) + " elements, expected " + std::to_string(expected) + ")");
  }

 private:
  const std::string& path_;
  std::span<const uint8_t> bytes_;
  size_t pos_ = 0;
};

template <class T>
void put_scalars(Writer& w, const char (&t)[5], const std::vector<T>& v) {
  w.tag(t, v.size());
  for (const T& x : v) w.put(x);
}
template <class V>
void put_vectors(Writer& w, const char (&t)[5], const std::vector<V>& v) {
  w.tag(t, v.size());
  for (const V& x : v)
    for (int k = 0; k < 3; ++k) w.put(x[k]);
}
template <class T>
void get_scalars(Reader& r, const char (&t)[5], std::vector<T>& v) {
  v.resize(r.section(t, sizeof(T)));
  for (T& x : v) r.get(x, t);
}
// A 16-bit field as its codes (version 5): 2 bytes per sample, the model's codes bit for bit.
uint16_t code_of(Unorm16 x) { return x.code; }
uint16_t code_of(Half16 x) { return x.bits(); }
template <class T>
void put_codes(Writer& w, const char (&t)[5], const std::vector<T>& v) {
  w.tag(t, v.size());
  for (const T& x : v) w.put_bits(code_of(x));
}
template <class T>
void get_codes(Reader& r, const char (&t)[5], std::vector<T>& v, const std::string& path, const char* what) {
  v.resize(r.section(t, sizeof(uint16_t)));
  for (size_t k = 0; k < v.size(); ++k) {
    const uint16_t c = r.get_bits<uint16_t>(t);
    if constexpr (std::is_same_v<T, Half16>) {
      v[k] = Half16::from_bits(c);
      if (!std::isfinite(float(v[k])))
        throw InvalidInput(path + ": " + what + " of sample " + std::to_string(k) + " is not finite (binary16 " +
                           std::to_string(c) + ")");
    } else {
      v[k].code = c;
    }
  }
}
// A 16-bit field (Unorm16, Half16) as float32, as files before version 5 store it. A value the
// field cannot hold (not finite, outside [0, 1] for a unorm16, beyond ±65,504 for a binary16) is
// refused by name, never clamped.
template <class T>
void get_floats(Reader& r, const char (&t)[5], std::vector<T>& v, const std::string& path, const char* what) {
  v.resize(r.section(t, sizeof(float)));
  const bool unit = std::is_same_v<T, Unorm16>;
  for (size_t k = 0; k < v.size(); ++k) {
    float x;
    r.get(x, t);
    if (!(std::isfinite(x) && (unit ? x >= 0.0f && x <= 1.0f : std::abs(x) <= Half16::max)))
      throw InvalidInput(path + ": " + what + " of sample " + std::to_string(k) + " is " + std::to_string(x) +
                         (unit ? ", outside [0, 1]" : ", not a finite value of at most 65,504"));
    v[k] = x;
  }
}
// A 16-bit field's section as @p version stores it: float32 before version 5, codes from it.
template <class T>
void get_field(Reader& r, const char (&t)[5], std::vector<T>& v, const std::string& path, const char* what,
               uint32_t version) {
  if (version >= 5)
    get_codes(r, t, v, path, what);
  else
    get_floats(r, t, v, path, what);
}
// A per-sample field whose codes are all equal is one code (version 7), whether the model holds it
// uniform or materialised: the same model gives the same bytes. Other fields: every sample's code.
template <class T>
void put_codes(Writer& w, const char (&t)[5], const SampleField<T>& f) {
  const size_t count = f.all_equal() ? std::min<size_t>(f.size(), 1) : f.size();
  w.tag(t, count);
  for (size_t k = 0; k < count; ++k) w.put_bits(code_of(f[k]));
}
// The field of @p samples samples a section holds: one code for all (version 7), or one each
// (uniform in the model when they are all equal), or none (filled with defaults later).
template <class T>
void get_field(Reader& r, const char (&t)[5], SampleField<T>& f, const std::string& path, const char* what,
               uint32_t version, size_t samples) {
  std::vector<T> v;
  get_field(r, t, v, path, what, version);
  if (version >= 7 && v.size() == 1 && samples > 1)
    f.assign(samples, v[0]);
  else
    f.assign(std::move(v));
}
template <class V, class Scalar>
void get_vectors(Reader& r, const char (&t)[5], std::vector<V>& v) {
  v.resize(r.section(t, 3 * sizeof(Scalar)));
  for (V& x : v)
    for (int k = 0; k < 3; ++k) {
      Scalar s;
      r.get(s, t);
      x[k] = s;
    }
}

// 8-bit texel arrays (version 3): stored as they lie in memory, 3 or 1 bytes per texel.
static_assert(sizeof(Srgb8) == 3 && alignof(Srgb8) == 1);
template <class T>
void put_bytes(Writer& w, const char (&t)[5], const std::vector<T>& v) {
  w.tag(t, v.size());
  w.put_raw(reinterpret_cast<const uint8_t*>(v.data()), v.size() * sizeof(T));
}
template <class T>
void get_bytes(Reader& r, const char (&t)[5], std::vector<T>& v) {
  v.resize(r.section(t, sizeof(T)));
  if (!v.empty()) std::memcpy(v.data(), r.take(v.size() * sizeof(T)), v.size() * sizeof(T));
}
// A texel field whose codes are all equal is one element (version 7), as for the per-sample
// fields; check_layout_sizes() gives it the texel count once that is known.
template <class T>
void put_bytes(Writer& w, const char (&t)[5], const SampleField<T>& f) {
  const bool one = f.all_equal();
  const size_t count = one ? std::min<size_t>(f.size(), 1) : f.size();
  const T first = f.empty() ? T{} : f[0];
  w.tag(t, count);
  w.put_raw(reinterpret_cast<const uint8_t*>(one ? &first : f.data()), count * sizeof(T));
}
template <class T>
void get_bytes(Reader& r, const char (&t)[5], SampleField<T>& f) {
  std::vector<T> v;
  get_bytes(r, t, v);
  f.assign(std::move(v));
}

// Versions 1 and 2 stored colour as 3 float32 linear RGB and roughness as float32: read and
// encoded to 8 bits once, refusing what those versions' loader refused (non-finite colours,
// roughness outside [0,1]).
void get_float_colour(Reader& r, SlabModel& m, const std::string& path) {
  std::vector<Vec3f> linear;
  get_vectors<Vec3f, float>(r, "COLR", linear);
  std::vector<Srgb8> colour(linear.size());
  for (size_t t = 0; t < linear.size(); ++t) {
    if (!linear[t].allFinite()) throw InvalidInput(path + ": colour of texel " + std::to_string(t) + " is not finite");
    colour[t] = encode_srgb8(linear[t]);
  }
  m.colour.assign(std::move(colour));
}
void get_float_roughness(Reader& r, SlabModel& m, const std::string& path) {
  std::vector<float> v;
  get_scalars(r, "RUFF", v);
  std::vector<uint8_t> roughness(v.size());
  for (size_t t = 0; t < v.size(); ++t) {
    if (!(v[t] >= 0.0f && v[t] <= 1.0f))
      throw InvalidInput(path + ": roughness of texel " + std::to_string(t) + " is outside [0, 1] or not finite");
    roughness[t] = unit_to_unorm8(v[t]);
  }
  m.roughness.assign(std::move(roughness));
}

// Checks the sizes the stored counts imply before rebuild_derived() builds the sample and texel
// layouts from them: grid_n and texel_density alone decide how much those layouts allocate, so
// the file must hold one displacement per sample and one colour per texel of exactly that layout.
// A texel field of one element (version 7) takes the texel count here.
void check_layout_sizes(SlabModel& m, const std::string& path, uint32_t version) {
  auto refuse = [&](const std::string& why) { throw InvalidInput(path + ": " + why); };
  const int64_t n = m.grid_n, big_n = int64_t(m.grid_n) * m.texel_density;
  if (n < 1 || n > 1024) refuse("grid_n = " + std::to_string(m.grid_n) + " outside [1, 1024]");
  if (m.texel_density < 1 || big_n > 4096)
    refuse("texel_density = " + std::to_string(m.texel_density) + " must be >= 1 with grid_n·texel_density <= 4096");
  if (m.inner.size() != m.outer.size()) refuse("inner and outer vertex counts differ");
  // Samples, boxes and normals are float: coordinates beyond max_model_coordinate would overflow them.
  for (size_t v = 0; v < m.inner.size(); ++v)
    if (!(m.inner[v].cwiseAbs().maxCoeff() <= max_model_coordinate &&
          m.outer[v].cwiseAbs().maxCoeff() <= max_model_coordinate))
      refuse("coarse vertex " + std::to_string(v) + " is not finite or lies beyond ±1e15 model units");
  if (m.slabs.empty()) refuse("no slabs");
  const auto C = static_cast<int64_t>(m.inner.size()), S = static_cast<int64_t>(m.slabs.size());
  if (C > std::numeric_limits<int32_t>::max() || S > std::numeric_limits<int32_t>::max() / 3)
    refuse(std::to_string(C) + " coarse vertices and " + std::to_string(S) + " slabs: more than hdm's limit");
  std::vector<uint64_t> edges;
  edges.reserve(3 * m.slabs.size());
  for (size_t s = 0; s < m.slabs.size(); ++s)
    for (int k = 0; k < 3; ++k) {
      const int64_t a = m.slabs[s][k], b = m.slabs[s][(k + 1) % 3];
      if (a < 0 || a >= C || b < 0 || b >= C || a == b)
        refuse("slab " + std::to_string(s) + ": invalid coarse vertex ids");
      edges.push_back((uint64_t(std::min(a, b)) << 32) | uint64_t(std::max(a, b)));
    }
  std::sort(edges.begin(), edges.end());
  const auto E = static_cast<int64_t>(std::unique(edges.begin(), edges.end()) - edges.begin());
  // Samples of a layout with k intervals per edge: corners, k-1 per edge, (k-1)(k-2)/2 per slab.
  auto count = [&](int64_t k) { return C + E * (k - 1) + S * ((k - 1) * (k - 2) / 2); };
  auto grid_points = [&](int64_t k) { return S * ((k + 1) * (k + 2) / 2); };
  const int64_t ns = count(n), nt = count(big_n);
  const int64_t limit = std::numeric_limits<int32_t>::max();
  if (ns > limit || nt > limit || grid_points(big_n) > limit)
    refuse(std::to_string(S) + " slabs at grid n = " + std::to_string(n) + " and " + std::to_string(m.texel_density) +
           " texels per interval need more samples or texels than hdm's limit of 2,147,483,647");
  if (static_cast<int64_t>(m.displacement.size()) != ns)
    refuse("corrupt (DISP holds " + std::to_string(m.displacement.size()) + " displacements, but " + std::to_string(S) +
           " slabs over " + std::to_string(C) + " coarse vertices at grid n = " + std::to_string(n) + " have " +
           std::to_string(ns) + " samples)");
  if (version >= 7 && nt > 1) {
    if (m.colour.size() == 1) m.colour.assign(size_t(nt), Srgb8(m.colour[0]));
    if (m.roughness.size() == 1) m.roughness.assign(size_t(nt), uint8_t(m.roughness[0]));
  }
  if (static_cast<int64_t>(m.colour.size()) != nt)
    refuse("corrupt (COLR holds " + std::to_string(m.colour.size()) +
           " colours, but the texel grid (n·m = " + std::to_string(big_n) + ") has " + std::to_string(nt) + " texels)");
}

// The file's bytes, in order, into @p sink.
void write_model(const SlabModel& m, FileSink& sink) {
  Writer w(sink);
  w.put_raw(reinterpret_cast<const uint8_t*>(kMagic), 4);
  w.put(hdm_format_version);
  w.tag("GRID", 2);
  w.put(static_cast<int32_t>(m.grid_n));
  w.put(static_cast<int32_t>(m.texel_density));
  put_vectors(w, "INNR", m.inner);
  put_vectors(w, "OUTR", m.outer);
  put_vectors(w, "SLAB", m.slabs);
  put_codes(w, "DISP", m.displacement);  // version 6: unorm16 codes, as the model holds them
  put_bytes(w, "COLR", m.colour);
  put_codes(w, "FRST", m.friction_static);
  put_codes(w, "FRDY", m.friction_dynamic);
  put_codes(w, "STIF", m.stiffness_scale);
  w.tag("SRCN", m.source.size());
  w.put_raw(reinterpret_cast<const uint8_t*>(m.source.data()), m.source.size());
  w.tag("SRCT", 1);
  w.put(static_cast<int64_t>(m.source_triangles));
  w.tag("SRCD", 1);
  w.put(m.source_diagonal);
  // Version 2: rendering roughness, the under-layer's depth and material.
  put_bytes(w, "RUFF", m.roughness);
  put_codes(w, "LAYD", m.layer_displacement);
  const UnderLayer& u = m.under_layer;
  w.tag("LAYM", 1);
  for (float v : {u.colour.x(), u.colour.y(), u.colour.z(), u.stiffness_scale, u.friction_static, u.friction_dynamic,
                  u.roughness})
    w.put(v);
  // Version 4: hardness per sample and the under-layer's.
  put_codes(w, "HARD", m.hardness);
  w.tag("LAYH", 1);
  w.put(u.hardness_hv);
  w.finish();
}

}  // namespace

void save_model(const SlabModel& m, const std::string& path) {
  write_file_atomic(path, [&](FileSink& sink) { write_model(m, sink); });
}

namespace {

// The stored members of a model from a file's bytes (everything but rebuild_derived()).
SlabModel read_stored(std::span<const uint8_t> bytes, const std::string& path, const ModelLoadOptions& options) {
  check_input_size(bytes.size(), options.max_file_bytes, path);
  if (bytes.size() < 4) throw IoError(path + ": truncated (" + std::to_string(bytes.size()) + " bytes, no header)");
  if (std::memcmp(bytes.data(), kMagic, 4) != 0) throw IoError(path + ": not an hdm model file (bad magic)");
  Reader r(path, bytes);
  r.get_bits<uint32_t>("magic");
  const uint32_t version = r.get_bits<uint32_t>("the version");
  if (version < 1 || version > hdm_format_version)
    throw IoError(path + ": format version " + std::to_string(version) + ", this hdm reads versions 1 to " +
                  std::to_string(hdm_format_version));

  SlabModel m;
  int32_t grid_n = 0, density = 0;
  r.fixed_section("GRID", 4, 2);
  r.get(grid_n, "GRID");
  r.get(density, "GRID");
  m.grid_n = grid_n;
  m.texel_density = density;
  get_vectors<Vec3, double>(r, "INNR", m.inner);
  get_vectors<Vec3, double>(r, "OUTR", m.outer);
  get_vectors<Tri, int32_t>(r, "SLAB", m.slabs);
  if (version >= 6)
    get_codes(r, "DISP", m.displacement, path, "displacement");
  else
    get_floats(r, "DISP", m.displacement, path, "displacement");
  if (version >= 3)
    get_bytes(r, "COLR", m.colour);
  else
    get_float_colour(r, m, path);
  get_field(r, "FRST", m.friction_static, path, "static friction", version, m.displacement.size());
  get_field(r, "FRDY", m.friction_dynamic, path, "dynamic friction", version, m.displacement.size());
  get_field(r, "STIF", m.stiffness_scale, path, "stiffness scale", version, m.displacement.size());
  const uint64_t name_bytes = r.section("SRCN", 1);
  m.source.assign(reinterpret_cast<const char*>(r.take(name_bytes)), name_bytes);
  int64_t triangles = 0;
  r.fixed_section("SRCT", 8, 1);
  r.get(triangles, "SRCT");
  m.source_triangles = triangles;
  r.fixed_section("SRCD", 8, 1);
  r.get(m.source_diagonal, "SRCD");
  if (version >= 2) {
    if (version >= 3)
      get_bytes(r, "RUFF", m.roughness);
    else
      get_float_roughness(r, m, path);
    get_field(r, "LAYD", m.layer_displacement, path, "under-layer top", version, m.displacement.size());
    r.fixed_section("LAYM", 28, 1);
    float v[7];
    for (float& x : v) r.get(x, "LAYM");
    m.under_layer = UnderLayer{Vec3f(v[0], v[1], v[2]), v[3], v[4], v[5], v[6]};
  }
  if (version >= 4) {
    get_field(r, "HARD", m.hardness, path, "hardness", version, m.displacement.size());
    r.fixed_section("LAYH", 4, 1);
    r.get(m.under_layer.hardness_hv, "LAYH");
  }

  const size_t end = r.position();
  if (bytes.size() < end + kChecksumBytes) throw IoError(path + ": truncated (the checksum is missing)");
  if (bytes.size() > end + kChecksumBytes)
    throw IoError(path + ": corrupt (" + std::to_string(bytes.size() - end - kChecksumBytes) +
                  " unexpected bytes before the checksum)");
  const uint64_t stored = r.get_bits<uint64_t>("the checksum");
  if (stored != fnv1a64(bytes.data(), end)) throw IoError(path + ": checksum mismatch (file corrupt)");
  check_layout_sizes(m, path, version);
  return m;
}

// The derived members of a model read from @p path, an error naming the file.
void derive(SlabModel& m, const std::string& path) {
  try {
    rebuild_derived(m);
  } catch (const InvalidInput& e) {
    throw InvalidInput(path + ": " + e.what());
  }
}

}  // namespace

SlabModel load_model(const std::string& path, const ModelLoadOptions& options) {
  SlabModel m;
  {
    // The file's bytes are freed before the derived data are built: the two never coexist
    // (370 MiB less at the peak of loading a 100,000-slab model).
    const std::string bytes = read_file(path, options.max_file_bytes);
    m = read_stored({reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()}, path, options);
  }
  derive(m, path);
  return m;
}

SlabModel load_model_from_memory(std::span<const uint8_t> bytes, const std::string& path,
                                 const ModelLoadOptions& options) {
  SlabModel m = read_stored(bytes, path, options);
  derive(m, path);
  return m;
}

}  // namespace hdm
