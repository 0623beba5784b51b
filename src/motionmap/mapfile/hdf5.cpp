#include "motionmap/mapfile/detail/hdf5.h"

#include <hdf5.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <string_view>

#include "motionmap/core/error.h"

namespace motionmap::mapfile::detail {

namespace {

// Debian's serial HDF5 is not built thread-safe: one Writer or Reader at a time per process
// (recursive, so one thread may hold a Reader while it writes).
std::recursive_mutex& hdf5_lock() {
  static std::recursive_mutex lock;
  return lock;
}

// An HDF5 identifier with the function that closes it.
class Id {
 public:
  Id() = default;
  Id(hid_t id, herr_t (*close)(hid_t)) : m_id(id), m_close(close) {}
  ~Id() { reset(); }
  Id(Id&& o) noexcept : m_id(o.m_id), m_close(o.m_close) { o.m_id = H5I_INVALID_HID; }
  Id& operator=(Id&& o) noexcept {
    if (this != &o) {
      reset();
      m_id = o.m_id;
      m_close = o.m_close;
      o.m_id = H5I_INVALID_HID;
    }
    return *this;
  }
  Id(const Id&) = delete;
  Id& operator=(const Id&) = delete;

  hid_t get() const { return m_id; }
  bool valid() const { return m_id >= 0; }
  /// Closes now; false if HDF5 reports a failure (a write that could not be flushed).
  bool reset() {
    bool ok = true;
    if (m_id >= 0 && m_close) ok = m_close(m_id) >= 0;
    m_id = H5I_INVALID_HID;
    return ok;
  }

 private:
  hid_t m_id = H5I_INVALID_HID;
  herr_t (*m_close)(hid_t) = nullptr;
};

// While alive: the process-wide lock, and HDF5's automatic error printing (a stack dump on
// stderr for every failed call, including the ones we expect, such as probing for an
// attribute) switched off; the previous handler comes back afterwards.
class Quiet {
 public:
  Quiet() : m_lock(hdf5_lock()) {
    H5Eget_auto2(H5E_DEFAULT, &m_func, &m_data);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~Quiet() { H5Eset_auto2(H5E_DEFAULT, m_func, m_data); }
  Quiet(const Quiet&) = delete;
  Quiet& operator=(const Quiet&) = delete;

 private:
  std::lock_guard<std::recursive_mutex> m_lock;
  H5E_auto2_t m_func = nullptr;
  void* m_data = nullptr;
};

// The first message of HDF5's error stack ("unable to open file", …), for our messages.
std::string hdf5_reason() {
  std::string reason;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_DOWNWARD,
      [](unsigned n, const H5E_error2_t* e, void* out) -> herr_t {
        if (n == 0 && e && e->desc) *static_cast<std::string*>(out) = e->desc;
        return 0;
      },
      &reason);
  return reason;
}

Id variable_string_type(H5T_cset_t cset = H5T_CSET_UTF8) {
  Id type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.get(), H5T_VARIABLE);
  H5Tset_cset(type.get(), cset);
  return type;
}

// A fixed-length UTF-8 string type of `size` bytes (at least 1), null-padded.
Id fixed_string_type(std::size_t size) {
  Id type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.get(), std::max<std::size_t>(size, 1));
  H5Tset_strpad(type.get(), H5T_STR_NULLPAD);
  H5Tset_cset(type.get(), H5T_CSET_UTF8);
  return type;
}

// A fixed-length string as read: up to its first NUL, and without the trailing spaces of a
// space-padded one (MATLAB's).
std::string fixed_string(const char* data, std::size_t size, H5T_str_t pad) {
  std::string s(data, size);
  s.resize(std::strlen(s.c_str()));
  if (pad == H5T_STR_SPACEPAD) {
    while (!s.empty() && s.back() == ' ') s.pop_back();
  }
  return s;
}

std::string le_bytes(const void* value) {
  return std::string(static_cast<const char*>(value), 8);
}

// A memory type for reading strings of the file type `file_type`: HDF5 converts neither between
// ASCII and UTF-8 strings nor between variable and fixed length, so it takes the file's.
Id string_memory_type(hid_t file_type) {
  const H5T_cset_t cset = H5Tget_cset(file_type);
  if (H5Tis_variable_str(file_type) > 0) return variable_string_type(cset);
  // Its size and padding too: a null-terminated memory type would cut a null-padded string's last
  // byte for the terminator.
  Id type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.get(), H5Tget_size(file_type));
  H5Tset_strpad(type.get(), H5Tget_strpad(file_type));
  H5Tset_cset(type.get(), cset);
  return type;
}

// ---- The structure checksum, in the user block ------------------------------------------------
//
// HDF5 ignores the first kUserBlock bytes of a file written with a user block. MotionMap writes
// there, in text, a checksum of every byte of the file but the datasets' contiguous values
// (which carry checksums of their own): the superblock, object headers, B-trees, heaps, chunked
// data and free space. The reader checks it before HDF5 parses anything, since HDF5 1.10's own
// decoding of a damaged object header can read past its buffers or allocate terabytes.
//
//   MotionMap map file (docs/map-file.md)\n
//   structure-xxh3 0123456789abcdef\n        the checksum of what follows it, then of the bytes
//   size 481552\n                            from kUserBlock to `size` outside the raw extents
//   raw 20656 5824\n                         a dataset's contiguous values: offset, length
//   …                                        (increasing, not overlapping)
//   NUL padding to kUserBlock bytes

constexpr std::size_t kUserBlock = 4096;
constexpr std::string_view kUserBlockMagic = "MotionMap map file (docs/map-file.md)\n";
constexpr std::string_view kHdf5Signature = "\211HDF\r\n\032\n";

struct Extent {
  std::uint64_t offset = 0, length = 0;
};

// The contiguous values of every dataset of `file` (addresses within the file), sorted.
std::vector<Extent> raw_extents(hid_t file) {
  std::vector<Extent> out;
  H5Ovisit2(
      file, H5_INDEX_NAME, H5_ITER_NATIVE,
      [](hid_t root, const char* name, const H5O_info_t* info, void* data) -> herr_t {
        if (info->type != H5O_TYPE_DATASET) return 0;
        const Id set(H5Dopen2(root, name, H5P_DEFAULT), H5Dclose);
        if (!set.valid()) return 0;
        const haddr_t offset = H5Dget_offset(set.get());
        const hsize_t length = H5Dget_storage_size(set.get());
        if (offset != HADDR_UNDEF && length > 0) {
          static_cast<std::vector<Extent>*>(data)->push_back({offset, length});
        }
        return 0;
      },
      &out, H5O_INFO_BASIC);
  std::sort(out.begin(), out.end(), [](const Extent& a, const Extent& b) {
    return a.offset < b.offset || (a.offset == b.offset && a.length < b.length);
  });
  out.erase(std::unique(out.begin(), out.end(),
                        [](const Extent& a, const Extent& b) {
                          return a.offset == b.offset && a.length == b.length;
                        }),
            out.end());
  return out;
}

// The checksum of `described` (the header's lines after the checksum line) and of the bytes of
// `in` (of `size` bytes) from kUserBlock on outside `raw`; nullopt if `raw` is not a list of
// increasing extents inside the file.
std::optional<std::uint64_t> structure_checksum(std::istream& in, std::uint64_t size,
                                                const std::vector<Extent>& raw,
                                                const std::string& described) {
  Hasher h;
  h.bytes(described.data(), described.size());
  std::uint64_t at = kUserBlock;
  std::vector<char> buffer(std::size_t(1) << 20);
  auto hash_to = [&](std::uint64_t end) {
    in.seekg(std::streamoff(at));
    while (at < end) {
      const std::size_t n = std::size_t(std::min<std::uint64_t>(end - at, buffer.size()));
      if (!in.read(buffer.data(), std::streamsize(n))) return false;
      h.bytes(buffer.data(), n);
      at += n;
    }
    return true;
  };
  for (const Extent& e : raw) {
    if (e.offset < at || e.length > size || e.offset > size - e.length) return std::nullopt;
    if (!hash_to(e.offset)) return std::nullopt;
    at = e.offset + e.length;
  }
  if (at > size || !hash_to(size)) return std::nullopt;
  return h.digest();
}

std::string describe_extents(std::uint64_t size, const std::vector<Extent>& raw) {
  std::string out = "size " + std::to_string(size) + "\n";
  for (const Extent& e : raw) {
    out += "raw " + std::to_string(e.offset) + " " + std::to_string(e.length) + "\n";
  }
  return out;
}

// Writes the user block of the closed file `path`, whose datasets' values are `raw`.
void seal_structure(const std::string& path, const std::vector<Extent>& raw) {
  std::fstream file(path, std::ios::binary | std::ios::in | std::ios::out);
  file.seekg(0, std::ios::end);
  const auto size = static_cast<std::uint64_t>(file.tellg());
  const std::string described = describe_extents(size, raw);
  const std::optional<std::uint64_t> sum = structure_checksum(file, size, raw, described);
  std::string block = std::string(kUserBlockMagic) + "structure-xxh3 " +
                      (sum ? hex_digest(*sum) : std::string("none")) + "\n" + described;
  if (!file || !sum || size < kUserBlock || block.size() > kUserBlock) {
    throw Error(path + ": error: cannot write the structure checksum");
  }
  block.resize(kUserBlock, '\0');
  file.clear();
  file.seekp(0);
  file.write(block.data(), std::streamsize(block.size()));
  file.flush();
  if (!file) throw Error(path + ": error: cannot write the structure checksum");
}

// Checks the user block of `path` (an error naming what is wrong); false for a file without one
// (written before layout 3: HDF5's signature at its start).
bool check_structure(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  file.seekg(0, std::ios::end);
  const auto size = static_cast<std::uint64_t>(file.tellg());
  std::string block(std::size_t(std::min<std::uint64_t>(size, kUserBlock)), '\0');
  file.seekg(0);
  file.read(block.data(), std::streamsize(block.size()));
  if (!file) throw Error(path + ": error: cannot read it");
  if (block.rfind(kHdf5Signature, 0) == 0) return false;
  const std::string fail =
      path + ": error: its HDF5 structure (everything but the datasets' values) ";
  if (block.rfind(kUserBlockMagic, 0) != 0) {
    // HDF5 looks for its signature at 0, 512, 1024, 2048, …: one there is not a file of ours.
    if (size > kUserBlock && block.size() == kUserBlock) {
      std::string signature(kHdf5Signature.size(), '\0');
      file.read(signature.data(), std::streamsize(signature.size()));
      if (file && signature == kHdf5Signature) {
        throw Error(fail + "cannot be checked: its first " + std::to_string(kUserBlock) +
                    " bytes, which hold its structure checksum, are damaged");
      }
    }
    return false;
  }
  // The lines: the checksum, the size, the raw extents; then NULs.
  const std::size_t end = std::min(block.find('\0'), block.size());
  std::string_view text(block.data() + kUserBlockMagic.size(), end - kUserBlockMagic.size());
  auto damaged = [&](const std::string& what) -> Error {
    return Error(fail + "cannot be checked: its structure checksum is damaged (" + what + ")");
  };
  std::vector<std::string_view> lines;
  while (!text.empty()) {
    const std::size_t eol = text.find('\n');
    if (eol == std::string_view::npos) throw damaged("a line without its end");
    lines.push_back(text.substr(0, eol));
    text.remove_prefix(eol + 1);
  }
  auto number = [&](std::string_view t, int base) {
    std::uint64_t v = 0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v, base);
    if (r.ec != std::errc() || r.ptr != t.data() + t.size() || t.empty()) {
      throw damaged("'" + quote_token(t) + "' is not a number");
    }
    return v;
  };
  if (lines.size() < 2 || lines[0].rfind("structure-xxh3 ", 0) != 0 ||
      lines[1].rfind("size ", 0) != 0) {
    throw damaged("expected its checksum and size lines");
  }
  const std::uint64_t recorded = number(lines[0].substr(15), 16);
  if (number(lines[1].substr(5), 10) != size) {
    throw Error(fail + "is damaged: the file has " + std::to_string(size) + " bytes where it had " +
                std::string(lines[1].substr(5)) + " (cut or extended)");
  }
  std::vector<Extent> raw;
  for (std::size_t i = 2; i < lines.size(); ++i) {
    const std::string_view l = lines[i];
    const std::size_t space = l.find(' ', 4);
    if (l.rfind("raw ", 0) != 0 || space == std::string_view::npos) {
      throw damaged("expected a raw extent line, found '" + quote_token(l) + "'");
    }
    raw.push_back({number(l.substr(4, space - 4), 10), number(l.substr(space + 1), 10)});
  }
  const std::string described(block.data() + kUserBlockMagic.size() + lines[0].size() + 1,
                              block.data() + end);
  const std::optional<std::uint64_t> actual = structure_checksum(file, size, raw, described);
  if (!actual) throw damaged("its extents are not increasing extents inside the file");
  if (*actual != recorded) {
    throw Error(fail + "is damaged: its checksum is " + hex_digest(*actual) +
                " where the file records " + hex_digest(recorded));
  }
  return true;
}

// Integer datasets of at least this many values are chunked and compressed (sample → clip and
// frame numbers: 4 MB each at 10⁶ samples, 20–30 kB compressed).
constexpr std::uint64_t kCompressFrom = 1u << 16;
constexpr std::uint64_t kChunkValues = 1u << 17;

}  // namespace

std::string describe_element(const DatasetInfo& info) {
  switch (info.kind) {
    case DatasetInfo::Kind::Float:
      return "float" + std::to_string(8 * info.element_bytes);
    case DatasetInfo::Kind::Integer:
      return "int" + std::to_string(8 * info.element_bytes);
    case DatasetInfo::Kind::String:
      return "string";
    case DatasetInfo::Kind::Other:
      break;
  }
  return "another type (not a number or string)";
}

// ---- Writer ---------------------------------------------------------------------------------

struct Writer::State {
  Quiet quiet;
  std::string path;
  Id file;
  bool closed = false;
  // The attributes written on each object, for their checksums at close().
  std::map<std::string, std::vector<AttributeValue>> attributes;
  // Every dataset and link written, in order, for the root attribute `datasets`.
  std::string datasets;

  [[noreturn]] void fail(const std::string& what) const {
    const std::string reason = hdf5_reason();
    throw Error(path + ": error: cannot write " + what + (reason.empty() ? "" : ": " + reason));
  }
  Id open_object(const std::string& object) const {
    Id id(H5Oopen(file.get(), object.c_str(), H5P_DEFAULT), H5Oclose);
    if (!id.valid()) fail("attributes of " + object + " (no such object)");
    return id;
  }
  void write_attribute(const std::string& object, const std::string& name, hid_t file_type,
                       hid_t memory_type, const void* value) const {
    const Id target = open_object(object);
    const Id space(H5Screate(H5S_SCALAR), H5Sclose);
    const Id attr(
        H5Acreate2(target.get(), name.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT),
        H5Aclose);
    if (!attr.valid() || H5Awrite(attr.get(), memory_type, value) < 0) {
      fail("attribute " + name + " of " + object);
    }
  }
  void write_checksum(const std::string& object, const std::string& name,
                      std::uint64_t digest) const {
    write_attribute(object, name, H5T_STD_U64LE, H5T_NATIVE_UINT64, &digest);
  }
};

Writer::Writer(const std::string& path) : m(std::make_unique<State>()) {
  m->path = path;
  const Id create(H5Pcreate(H5P_FILE_CREATE), H5Pclose);
  H5Pset_userblock(create.get(), kUserBlock);
  m->file = Id(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, create.get(), H5P_DEFAULT), H5Fclose);
  if (!m->file.valid()) {
    const std::string reason = hdf5_reason();
    throw Error(path + ": error: cannot create the file" + (reason.empty() ? "" : ": " + reason));
  }
}

Writer::~Writer() {
  if (m && !m->closed) {
    m->file.reset();
    std::error_code ec;
    std::filesystem::remove(m->path, ec);
  }
}

void Writer::group(const std::string& name) {
  const Id g(H5Gcreate2(m->file.get(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
             H5Gclose);
  if (!g.valid()) m->fail("group " + name);
}

void Writer::attribute(const std::string& object, const std::string& name,
                       const std::string& value) {
  const Id type = fixed_string_type(value.size());
  const std::string padded = value + '\0';  // an empty text is one NUL
  m->write_attribute(object, name, type.get(), type.get(), padded.data());
  m->attributes[object].push_back({name, 's', value});
}

void Writer::attribute(const std::string& object, const std::string& name, std::int64_t value) {
  m->write_attribute(object, name, H5T_STD_I64LE, H5T_NATIVE_INT64, &value);
  m->attributes[object].push_back({name, 'i', le_bytes(&value)});
}

void Writer::attribute(const std::string& object, const std::string& name, double value) {
  m->write_attribute(object, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value);
  m->attributes[object].push_back({name, 'f', le_bytes(&value)});
}

void Writer::doubles(const std::string& name, const double* data, std::uint64_t rows,
                     std::uint64_t cols) {
  const hsize_t dims[2] = {rows, cols};
  const int rank = cols == 0 ? 1 : 2;
  const std::uint64_t count = rank == 1 ? rows : rows * cols;
  const Id space(H5Screate_simple(rank, dims, nullptr), H5Sclose);
  // Contiguous and not compressed: shuffle + deflate saves only 20–30 % of float64 map data
  // (coordinates, distances) and reads at 100–400 MB/s on one thread, so a 10⁶-sample Isomap
  // model (3 GB) took 14 s to read, against 2 s as it is.
  const Id set(H5Dcreate2(m->file.get(), name.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT,
                          H5P_DEFAULT, H5P_DEFAULT),
               H5Dclose);
  if (!set.valid()) m->fail("dataset " + name);
  if (count > 0 &&
      H5Dwrite(set.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0) {
    m->fail("dataset " + name);
  }
  Hasher h;
  h.doubles(data, count);
  m->write_checksum(name, kChecksumAttribute, h.digest());
  m->datasets += (m->datasets.empty() ? "" : " ") + name;
}

void Writer::ints(const std::string& name, const std::int32_t* data, std::uint64_t count) {
  const hsize_t dims[1] = {count};
  const Id space(H5Screate_simple(1, dims, nullptr), H5Sclose);
  const Id create(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  if (count >= kCompressFrom) {
    const hsize_t chunk[1] = {std::min<std::uint64_t>(count, kChunkValues)};
    H5Pset_chunk(create.get(), 1, chunk);
    H5Pset_shuffle(create.get());
    H5Pset_deflate(create.get(), 1);
  }
  const Id set(H5Dcreate2(m->file.get(), name.c_str(), H5T_STD_I32LE, space.get(), H5P_DEFAULT,
                          create.get(), H5P_DEFAULT),
               H5Dclose);
  if (!set.valid()) m->fail("dataset " + name);
  if (count > 0 && H5Dwrite(set.get(), H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0) {
    m->fail("dataset " + name);
  }
  Hasher h;
  h.int32s(data, count);
  m->write_checksum(name, kChecksumAttribute, h.digest());
  m->datasets += (m->datasets.empty() ? "" : " ") + name;
}

void Writer::strings(const std::string& name, const std::vector<std::string>& values) {
  const hsize_t dims[1] = {values.size()};
  const Id space(H5Screate_simple(1, dims, nullptr), H5Sclose);
  std::size_t size = 1;
  for (const std::string& v : values) size = std::max(size, v.size());
  const Id type = fixed_string_type(size);
  const Id set(H5Dcreate2(m->file.get(), name.c_str(), type.get(), space.get(), H5P_DEFAULT,
                          H5P_DEFAULT, H5P_DEFAULT),
               H5Dclose);
  if (!set.valid()) m->fail("dataset " + name);
  std::vector<char> text(values.size() * size, '\0');
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::copy(values[i].begin(), values[i].end(), text.begin() + std::ptrdiff_t(i * size));
  }
  if (!text.empty() &&
      H5Dwrite(set.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, text.data()) < 0) {
    m->fail("dataset " + name);
  }
  Hasher h;
  h.strings(values);
  m->write_checksum(name, kChecksumAttribute, h.digest());
  m->datasets += (m->datasets.empty() ? "" : " ") + name;
}

void Writer::link(const std::string& existing, const std::string& name) {
  if (H5Lcreate_hard(m->file.get(), existing.c_str(), m->file.get(), name.c_str(), H5P_DEFAULT,
                     H5P_DEFAULT) < 0) {
    m->fail("link " + name + " to " + existing);
  }
  m->datasets += (m->datasets.empty() ? "" : " ") + name;
}

void Writer::close() {
  if (m->closed) return;
  attribute("/", kDatasetsAttribute, m->datasets);
  for (const auto& [object, attributes] : m->attributes) {
    m->write_checksum(object, kAttributesChecksumAttribute, attributes_checksum(attributes));
  }
  const bool flushed = H5Fflush(m->file.get(), H5F_SCOPE_GLOBAL) >= 0;
  const std::vector<Extent> raw = raw_extents(m->file.get());
  const bool closed = m->file.reset();
  if (!flushed || !closed) m->fail("the file (flushing it to disk failed)");
  seal_structure(m->path, raw);
  m->closed = true;
}

// ---- Reader ---------------------------------------------------------------------------------

struct Reader::State {
  Quiet quiet;
  std::string path;
  Id file;
  bool fixed_strings_only = false;
  bool structure_checked = false;

  [[noreturn]] void fail(const std::string& what) const { throw Error(path + ": error: " + what); }
  Id dataset(const std::string& name) const {
    Id set(H5Dopen2(file.get(), name.c_str(), H5P_DEFAULT), H5Dclose);
    if (!set.valid()) fail(name + " is not a dataset");
    return set;
  }
  // The attribute, or an invalid Id when absent; its dataspace must hold one value.
  Id attribute(const std::string& object, const std::string& name) const {
    if (H5Aexists_by_name(file.get(), object.c_str(), name.c_str(), H5P_DEFAULT) <= 0) return {};
    Id attr(H5Aopen_by_name(file.get(), object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT),
            H5Aclose);
    if (!attr.valid()) fail("cannot read attribute " + name + " of " + object);
    const Id space(H5Aget_space(attr.get()), H5Sclose);
    if (H5Sget_simple_extent_npoints(space.get()) != 1) {
      fail("attribute " + name + " of " + object + " holds " +
           std::to_string(H5Sget_simple_extent_npoints(space.get())) +
           " values, expected a single value");
    }
    return attr;
  }
  H5T_class_t attribute_class(const Id& attr) const {
    const Id type(H5Aget_type(attr.get()), H5Tclose);
    return H5Tget_class(type.get());
  }
};

Reader::Reader(const std::string& path, bool check_structure_first) : m(std::make_unique<State>()) {
  m->path = path;
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw Error(path + ": error: is a directory, expected a map file");
  }
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw Error(path + ": error: cannot open: " + std::strerror(errno));
  }
  if (check_structure_first) m->structure_checked = check_structure(path);
  if (H5Fis_hdf5(path.c_str()) <= 0) {
    throw Error(path +
                ": error: not an HDF5 file (expected a MotionMap map file, as `motionmap map "
                "--save` writes)");
  }
  m->file = Id(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!m->file.valid()) {
    const std::string reason = hdf5_reason();
    throw Error(path + ": error: cannot open the HDF5 file" +
                (reason.empty() ? "" : ": " + reason));
  }
}

Reader::~Reader() = default;

const std::string& Reader::path() const {
  return m->path;
}

bool Reader::structure_checked() const {
  return m->structure_checked;
}

void Reader::refuse_variable_length_strings() {
  m->fixed_strings_only = true;
}

bool Reader::has(const std::string& name) const {
  // H5Lexists fails (rather than saying no) when a parent is missing: check each prefix.
  std::size_t at = 0;
  while (at != std::string::npos) {
    at = name.find('/', at + 1);
    const std::string prefix = name.substr(0, at);
    if (prefix.empty() || prefix == "/") continue;
    if (H5Lexists(m->file.get(), prefix.c_str(), H5P_DEFAULT) <= 0) return false;
  }
  return H5Oexists_by_name(m->file.get(), name.c_str(), H5P_DEFAULT) > 0;
}

bool Reader::has_attribute(const std::string& object, const std::string& name) const {
  return has(object) &&
         H5Aexists_by_name(m->file.get(), object.c_str(), name.c_str(), H5P_DEFAULT) > 0;
}

std::optional<std::string> Reader::text_attribute(const std::string& object,
                                                  const std::string& name) const {
  if (!has_attribute(object, name)) return std::nullopt;
  const Id attr = m->attribute(object, name);
  const Id type(H5Aget_type(attr.get()), H5Tclose);
  if (H5Tget_class(type.get()) != H5T_STRING) {
    m->fail("attribute " + name + " of " + object + " is not a string");
  }
  const Id memory = string_memory_type(type.get());
  if (H5Tis_variable_str(type.get()) > 0) {
    if (m->fixed_strings_only) {
      m->fail("attribute " + name + " of " + object +
              " is a variable-length string, which layout 3 does not write");
    }
    char* text = nullptr;
    if (H5Aread(attr.get(), memory.get(), &text) < 0) {
      m->fail("cannot read attribute " + name + " of " + object);
    }
    std::string out = text ? text : "";
    if (text) H5free_memory(text);
    return out;
  }
  const std::size_t size = H5Tget_size(type.get());
  if (size > (std::size_t(1) << 20)) {
    m->fail("attribute " + name + " of " + object + " is a string of " + std::to_string(size) +
            " bytes, more than a map file's text holds (1 MiB)");
  }
  std::vector<char> buffer(size + 1, '\0');
  if (H5Aread(attr.get(), memory.get(), buffer.data()) < 0) {
    m->fail("cannot read attribute " + name + " of " + object);
  }
  return fixed_string(buffer.data(), size, H5Tget_strpad(type.get()));
}

std::optional<std::int64_t> Reader::int_attribute(const std::string& object,
                                                  const std::string& name) const {
  if (!has_attribute(object, name)) return std::nullopt;
  const Id attr = m->attribute(object, name);
  if (m->attribute_class(attr) != H5T_INTEGER) {
    m->fail("attribute " + name + " of " + object + " is not an integer");
  }
  std::int64_t value = 0;
  if (H5Aread(attr.get(), H5T_NATIVE_INT64, &value) < 0) {
    m->fail("cannot read attribute " + name + " of " + object);
  }
  return value;
}

std::optional<double> Reader::real_attribute(const std::string& object,
                                             const std::string& name) const {
  if (!has_attribute(object, name)) return std::nullopt;
  const Id attr = m->attribute(object, name);
  const H5T_class_t c = m->attribute_class(attr);
  if (c != H5T_FLOAT && c != H5T_INTEGER) {
    m->fail("attribute " + name + " of " + object + " is not a number");
  }
  double value = 0;
  if (H5Aread(attr.get(), H5T_NATIVE_DOUBLE, &value) < 0) {
    m->fail("cannot read attribute " + name + " of " + object);
  }
  return value;
}

std::optional<std::uint64_t> Reader::checksum_attribute(const std::string& object,
                                                        const std::string& name) const {
  if (!has_attribute(object, name)) return std::nullopt;
  const Id attr = m->attribute(object, name);
  if (m->attribute_class(attr) != H5T_INTEGER) {
    m->fail("attribute " + name + " of " + object + " is not an integer (a checksum)");
  }
  std::uint64_t value = 0;
  if (H5Aread(attr.get(), H5T_NATIVE_UINT64, &value) < 0) {
    m->fail("cannot read attribute " + name + " of " + object);
  }
  return value;
}

std::vector<AttributeValue> Reader::attributes(const std::string& object) const {
  std::vector<std::string> names;
  hsize_t at = 0;
  const herr_t walked = H5Aiterate_by_name(
      m->file.get(), object.c_str(), H5_INDEX_NAME, H5_ITER_NATIVE, &at,
      [](hid_t, const char* name, const H5A_info_t*, void* out) -> herr_t {
        static_cast<std::vector<std::string>*>(out)->emplace_back(name);
        return 0;
      },
      &names, H5P_DEFAULT);
  if (walked < 0) m->fail("cannot list the attributes of " + object);
  std::vector<AttributeValue> out;
  for (const std::string& name : names) {
    if (name == kChecksumAttribute || name == kAttributesChecksumAttribute) continue;
    const Id attr = m->attribute(object, name);
    switch (m->attribute_class(attr)) {
      case H5T_STRING:
        out.push_back({name, 's', *text_attribute(object, name)});
        break;
      case H5T_INTEGER: {
        const std::int64_t v = *int_attribute(object, name);
        out.push_back({name, 'i', le_bytes(&v)});
        break;
      }
      case H5T_FLOAT: {
        const double v = *real_attribute(object, name);
        out.push_back({name, 'f', le_bytes(&v)});
        break;
      }
      default:
        m->fail("attribute " + name + " of " + object + " is not a string or a number");
    }
  }
  return out;
}

DatasetInfo Reader::info(const std::string& name) const {
  const Id set = m->dataset(name);
  const Id type(H5Dget_type(set.get()), H5Tclose);
  const Id space(H5Dget_space(set.get()), H5Sclose);
  DatasetInfo out;
  switch (H5Tget_class(type.get())) {
    case H5T_FLOAT:
      out.kind = DatasetInfo::Kind::Float;
      break;
    case H5T_INTEGER:
      out.kind = DatasetInfo::Kind::Integer;
      break;
    case H5T_STRING:
      out.kind = DatasetInfo::Kind::String;
      break;
    default:
      out.kind = DatasetInfo::Kind::Other;
  }
  out.element_bytes = H5Tget_size(type.get());
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0) m->fail("cannot read the shape of " + name);
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  if (rank > 0) H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  out.shape.assign(dims.begin(), dims.end());
  // A damaged size must not become an allocation: the values must fit in what is stored (at
  // most 1 100 times more, and 16 MiB, when compressed).
  std::uint64_t values = 1;
  bool overflow = false;
  for (const std::uint64_t d : out.shape) {
    if (d != 0 && values > UINT64_MAX / d) overflow = true;
    values *= d;
  }
  const std::uint64_t element = std::max<std::uint64_t>(out.element_bytes, 1);
  const std::uint64_t stored = H5Dget_storage_size(set.get());
  const Id create(H5Dget_create_plist(set.get()), H5Pclose);
  const bool filtered = create.valid() && H5Pget_nfilters(create.get()) > 0;
  const std::uint64_t most = filtered ? stored * 1100 + (std::uint64_t(1) << 24) : stored;
  if (overflow || values > UINT64_MAX / element ||
      (out.kind != DatasetInfo::Kind::String && values * element > most) ||
      (out.kind == DatasetInfo::Kind::String && values * element > most + (1u << 16))) {
    m->fail(name + " has shape " + std::to_string(out.shape.empty() ? 0 : out.shape[0]) +
            (out.shape.size() > 1 ? "×" + std::to_string(out.shape[1]) : "") +
            ", more values than its " + std::to_string(stored) + " stored bytes hold");
  }
  return out;
}

namespace {

std::uint64_t element_count(const DatasetInfo& info) {
  std::uint64_t n = 1;
  for (const std::uint64_t d : info.shape) n *= d;
  return n;
}

}  // namespace

std::vector<double> Reader::doubles(const std::string& name) const {
  const std::uint64_t n = element_count(info(name));
  std::vector<double> out(n);
  const Id set = m->dataset(name);
  if (n > 0 &&
      H5Dread(set.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0) {
    m->fail("cannot read " + name + ": " + hdf5_reason());
  }
  return out;
}

void Reader::double_rows(const std::string& name, std::uint64_t first, std::uint64_t count,
                         double* out) const {
  const DatasetInfo shape = info(name);
  if (shape.shape.empty() || shape.shape.size() > 2 || first + count > shape.shape[0]) {
    m->fail("cannot read rows " + std::to_string(first) + " to " + std::to_string(first + count) +
            " of " + name);
  }
  if (count == 0 || (shape.shape.size() == 2 && shape.shape[1] == 0)) return;
  const Id set = m->dataset(name);
  const Id file_space(H5Dget_space(set.get()), H5Sclose);
  const int rank = static_cast<int>(shape.shape.size());
  const hsize_t start[2] = {first, 0};
  const hsize_t size[2] = {count, rank == 2 ? shape.shape[1] : 1};
  const Id memory(H5Screate_simple(rank, size, nullptr), H5Sclose);
  if (!file_space.valid() || !memory.valid() ||
      H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, size, nullptr) < 0 ||
      H5Dread(set.get(), H5T_NATIVE_DOUBLE, memory.get(), file_space.get(), H5P_DEFAULT, out) < 0) {
    m->fail("cannot read " + name + ": " + hdf5_reason());
  }
}

std::vector<std::int64_t> Reader::ints(const std::string& name) const {
  const std::uint64_t n = element_count(info(name));
  std::vector<std::int64_t> out(n);
  const Id set = m->dataset(name);
  if (n > 0 &&
      H5Dread(set.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0) {
    m->fail("cannot read " + name + ": " + hdf5_reason());
  }
  return out;
}

std::vector<std::string> Reader::strings(const std::string& name) const {
  const std::uint64_t n = element_count(info(name));
  const Id set = m->dataset(name);
  const Id type(H5Dget_type(set.get()), H5Tclose);
  std::vector<std::string> out;
  out.reserve(n);
  if (n == 0) return out;
  const Id memory = string_memory_type(type.get());
  if (H5Tis_variable_str(type.get()) > 0) {
    if (m->fixed_strings_only) {
      m->fail(name + " holds variable-length strings, which layout 3 does not write");
    }
    std::vector<char*> text(n, nullptr);
    if (H5Dread(set.get(), memory.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, text.data()) < 0) {
      m->fail("cannot read " + name + ": " + hdf5_reason());
    }
    for (char* t : text) out.emplace_back(t ? t : "");
    const Id space(H5Dget_space(set.get()), H5Sclose);
    // H5Treclaim from 1.12 on; 1.10 (Debian 12) declares it but only exports H5Dvlen_reclaim.
#if H5_VERSION_GE(1, 12, 0)
    H5Treclaim(memory.get(), space.get(), H5P_DEFAULT, text.data());
#else
    H5Dvlen_reclaim(memory.get(), space.get(), H5P_DEFAULT, text.data());
#endif
    return out;
  }
  const std::size_t size = H5Tget_size(type.get());
  std::vector<char> buffer(n * size + 1, '\0');
  if (H5Dread(set.get(), memory.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()) < 0) {
    m->fail("cannot read " + name + ": " + hdf5_reason());
  }
  const H5T_str_t pad = H5Tget_strpad(type.get());
  for (std::uint64_t i = 0; i < n; ++i)
    out.push_back(fixed_string(buffer.data() + i * size, size, pad));
  return out;
}

// ---- write_checksums -------------------------------------------------------------------------

void write_checksums(const std::string& path) {
  struct Item {
    std::string name;
    bool dataset = false;
  };
  std::vector<Item> items;
  std::vector<std::pair<std::string, std::uint64_t>> sums;  // (object / attribute, digest)
  {
    const Reader reader(path, false);
    const Quiet quiet;
    const Id file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    if (!file.valid()) throw Error(path + ": error: cannot open the HDF5 file");
    H5Ovisit2(
        file.get(), H5_INDEX_NAME, H5_ITER_NATIVE,
        [](hid_t, const char* name, const H5O_info_t* info, void* out) -> herr_t {
          const std::string n = std::string(name) == "." ? "/" : "/" + std::string(name);
          static_cast<std::vector<Item>*>(out)->push_back({n, info->type == H5O_TYPE_DATASET});
          return 0;
        },
        &items, H5O_INFO_BASIC);
    for (const Item& item : items) {
      if (item.dataset) {
        const DatasetInfo info = reader.info(item.name);
        Hasher h;
        if (info.kind == DatasetInfo::Kind::Float) {
          const std::vector<double> v = reader.doubles(item.name);
          h.doubles(v.data(), v.size());
        } else if (info.kind == DatasetInfo::Kind::Integer) {
          const std::vector<std::int64_t> v = reader.ints(item.name);
          const std::vector<std::int32_t> v32(v.begin(), v.end());
          h.int32s(v32.data(), v32.size());
        } else if (info.kind == DatasetInfo::Kind::String) {
          h.strings(reader.strings(item.name));
        } else {
          continue;
        }
        sums.emplace_back(item.name + "\n" + kChecksumAttribute, h.digest());
      }
      const std::vector<AttributeValue> attributes = reader.attributes(item.name);
      if (!attributes.empty()) {
        sums.emplace_back(item.name + "\n" + kAttributesChecksumAttribute,
                          attributes_checksum(attributes));
      }
    }
  }
  {
    const Quiet quiet;
    const Id file(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
    if (!file.valid()) throw Error(path + ": error: cannot open the HDF5 file for writing");
    for (const auto& [where, digest] : sums) {
      const std::string object = where.substr(0, where.find('\n'));
      const std::string name = where.substr(where.find('\n') + 1);
      if (H5Aexists_by_name(file.get(), object.c_str(), name.c_str(), H5P_DEFAULT) > 0) {
        H5Adelete_by_name(file.get(), object.c_str(), name.c_str(), H5P_DEFAULT);
      }
      const Id space(H5Screate(H5S_SCALAR), H5Sclose);
      const Id attr(H5Acreate_by_name(file.get(), object.c_str(), name.c_str(), H5T_STD_U64LE,
                                      space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                    H5Aclose);
      if (!attr.valid() || H5Awrite(attr.get(), H5T_NATIVE_UINT64, &digest) < 0) {
        throw Error(path + ": error: cannot write attribute " + name + " of " + object);
      }
    }
  }  // closed: HDF5 writes its metadata before the structure is hashed
  write_structure_checksum(path);
}

bool has_map_file_start(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string head(kUserBlockMagic.size(), '\0');
  in.read(head.data(), std::streamsize(head.size()));
  const std::size_t got = std::size_t(in.gcount());
  return (got >= kHdf5Signature.size() && head.rfind(kHdf5Signature, 0) == 0) ||
         (got == head.size() && head == kUserBlockMagic);
}

void write_structure_checksum(const std::string& path) {
  std::vector<Extent> raw;
  {
    const Quiet quiet;
    const Id file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    if (!file.valid()) throw Error(path + ": error: cannot open the HDF5 file");
    raw = raw_extents(file.get());
  }
  seal_structure(path, raw);
}

}  // namespace motionmap::mapfile::detail
