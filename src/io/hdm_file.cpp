// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/io/hdm_file.h>

#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace hdm {
namespace {

constexpr char kMagic[4] = {'H', 'D', 'M', '\0'};
constexpr size_t kChecksumBytes = 8;

uint64_t fnv1a64(const uint8_t* data, size_t size) {
  uint64_t h = 14695981039346656037ull;
  for (size_t k = 0; k < size; ++k) h = (h ^ data[k]) * 1099511628211ull;
  return h;
}

// ---- writing: every value goes through put_bits, which stores little-endian ----

class Writer {
 public:
  std::vector<uint8_t> bytes;

  template <class U>
  void put_bits(U bits) {
    for (size_t k = 0; k < sizeof(U); ++k) bytes.push_back(static_cast<uint8_t>(bits >> (8 * k)));
  }
  void put(int32_t v) { put_bits(static_cast<uint32_t>(v)); }
  void put(uint32_t v) { put_bits(v); }
  void put(int64_t v) { put_bits(static_cast<uint64_t>(v)); }
  void put(uint64_t v) { put_bits(v); }
  void put(float v) { put_bits(std::bit_cast<uint32_t>(v)); }
  void put(double v) { put_bits(std::bit_cast<uint64_t>(v)); }
  void tag(const char (&t)[5], uint64_t count) {
    bytes.insert(bytes.end(), t, t + 4);
    put(count);
  }
};

// ---- reading: bounds-checked cursor over the file's bytes ----

class Reader {
 public:
  Reader(const std::string& path, const std::vector<uint8_t>& bytes) : path_(path), bytes_(bytes) {}

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
  const std::vector<uint8_t>& bytes_;
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

std::vector<uint8_t> read_whole_file(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw IoError(path + ": no such file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open for reading");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) throw IoError(path + ": cannot determine the file size");
  in.seekg(0, std::ios::beg);
  std::vector<uint8_t> bytes(static_cast<size_t>(size));
  if (!in.read(reinterpret_cast<char*>(bytes.data()), size)) throw IoError(path + ": read error");
  return bytes;
}

}  // namespace

void write_file_atomic(const std::string& path, const void* data, size_t size) {
  const std::string tmp = path + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw IoError(path + ": cannot create " + tmp + ": " + std::strerror(errno));
  bool ok = size == 0 || std::fwrite(data, 1, size, f) == size;
  ok = ok && std::fflush(f) == 0;
  ok = ok && ::fsync(::fileno(f)) == 0;  // the data must be on disk before the rename replaces the old file
  const int saved_errno = errno;
  ok = (std::fclose(f) == 0) && ok;
  std::error_code ec;
  if (!ok) {
    std::filesystem::remove(tmp, ec);
    throw IoError(path + ": cannot write " + tmp + ": " + std::strerror(saved_errno ? saved_errno : errno));
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw IoError(path + ": cannot rename " + tmp + " over it: " + ec.message());
  }
}

void save_model(const SlabModel& m, const std::string& path) {
  Writer w;
  w.bytes.reserve(64 + m.inner.size() * 48 + m.slabs.size() * 12 + m.displacement.size() * 16 +
                  m.colour.size() * 12 + m.source.size());
  w.bytes.insert(w.bytes.end(), kMagic, kMagic + 4);
  w.put(hdm_format_version);
  w.tag("GRID", 2);
  w.put(static_cast<int32_t>(m.grid_n));
  w.put(static_cast<int32_t>(m.texel_density));
  put_vectors(w, "INNR", m.inner);
  put_vectors(w, "OUTR", m.outer);
  put_vectors(w, "SLAB", m.slabs);
  put_scalars(w, "DISP", m.displacement);
  put_vectors(w, "COLR", m.colour);
  put_scalars(w, "FRST", m.friction_static);
  put_scalars(w, "FRDY", m.friction_dynamic);
  put_scalars(w, "STIF", m.stiffness_scale);
  w.tag("SRCN", m.source.size());
  w.bytes.insert(w.bytes.end(), m.source.begin(), m.source.end());
  w.tag("SRCT", 1);
  w.put(static_cast<int64_t>(m.source_triangles));
  w.tag("SRCD", 1);
  w.put(m.source_diagonal);
  // Version 2: rendering roughness, the under-layer's depth and material.
  put_scalars(w, "RUFF", m.roughness);
  put_scalars(w, "LAYD", m.layer_displacement);
  const UnderLayer& u = m.under_layer;
  w.tag("LAYM", 1);
  for (float v : {u.colour.x(), u.colour.y(), u.colour.z(), u.stiffness_scale, u.friction_static, u.friction_dynamic,
                  u.roughness})
    w.put(v);
  w.put(fnv1a64(w.bytes.data(), w.bytes.size()));
  write_file_atomic(path, w.bytes.data(), w.bytes.size());
}

SlabModel load_model(const std::string& path) {
  const std::vector<uint8_t> bytes = read_whole_file(path);
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
  get_scalars(r, "DISP", m.displacement);
  get_vectors<Vec3f, float>(r, "COLR", m.colour);
  get_scalars(r, "FRST", m.friction_static);
  get_scalars(r, "FRDY", m.friction_dynamic);
  get_scalars(r, "STIF", m.stiffness_scale);
  const uint64_t name_bytes = r.section("SRCN", 1);
  m.source.assign(reinterpret_cast<const char*>(r.take(name_bytes)), name_bytes);
  int64_t triangles = 0;
  r.fixed_section("SRCT", 8, 1);
  r.get(triangles, "SRCT");
  m.source_triangles = triangles;
  r.fixed_section("SRCD", 8, 1);
  r.get(m.source_diagonal, "SRCD");
  if (version >= 2) {
    get_scalars(r, "RUFF", m.roughness);
    get_scalars(r, "LAYD", m.layer_displacement);
    r.fixed_section("LAYM", 28, 1);
    float v[7];
    for (float& x : v) r.get(x, "LAYM");
    m.under_layer = UnderLayer{Vec3f(v[0], v[1], v[2]), v[3], v[4], v[5], v[6]};
  }

  const size_t end = r.position();
  if (bytes.size() < end + kChecksumBytes) throw IoError(path + ": truncated (the checksum is missing)");
  if (bytes.size() > end + kChecksumBytes)
    throw IoError(path + ": corrupt (" + std::to_string(bytes.size() - end - kChecksumBytes) +
                  " unexpected bytes before the checksum)");
  const uint64_t stored = r.get_bits<uint64_t>("the checksum");
  if (stored != fnv1a64(bytes.data(), end)) throw IoError(path + ": checksum mismatch (file corrupt)");

  try {
    rebuild_derived(m);
  } catch (const InvalidInput& e) {
    throw InvalidInput(path + ": " + e.what());
  }
  return m;
}

}  // namespace hdm
