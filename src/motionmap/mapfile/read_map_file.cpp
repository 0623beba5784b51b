// Reading a map file back: every item checked before it is trusted (docs/map-file.md).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <new>
#include <optional>
#include <set>
#include <string_view>
#include <utility>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/core/names.h"
#include "motionmap/core/parallel.h"
#include "motionmap/mapfile/detail/checksum.h"
#include "motionmap/mapfile/detail/hdf5.h"
#include "motionmap/mapfile/detail/layout.h"
#include "motionmap/mapfile/map_file.h"

namespace motionmap::mapfile {

using detail::DatasetInfo;
using embed::Method;

namespace {

// The largest magnitude of a value read: far beyond any coordinate, feature or parameter of a
// map, and small enough that squares and sums of thousands of squares stay finite — a file that
// holds 1e300 (finite) would otherwise overflow distances into inf and NaN downstream.
constexpr double kMaxMagnitude = 1e100;

bool uses_graph_method(Method method) {
  return embed::uses_graph(method);
}

// "364×2", "31".
std::string shape_text(const std::vector<std::uint64_t>& shape) {
  if (shape.empty()) return "a scalar";
  std::string s;
  for (std::size_t i = 0; i < shape.size(); ++i) s += (i ? "×" : "") + std::to_string(shape[i]);
  return s;
}

// Whether `s` is text a message may show as it is: UTF-8 (no overlong forms, no surrogates) with
// no control characters.
bool printable_utf8(std::string_view s) {
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x80) {
      if (c < 0x20 || c == 0x7f) return false;
      ++i;
      continue;
    }
    const int extra = c >= 0xf0 ? 3 : c >= 0xe0 ? 2 : c >= 0xc2 ? 1 : -1;
    if (extra < 0 || c > 0xf4 || s.size() - i <= std::size_t(extra)) return false;
    char32_t code = c & (0x3f >> extra);
    for (int k = 1; k <= extra; ++k) {
      const auto b = static_cast<unsigned char>(s[i + std::size_t(k)]);
      if ((b & 0xc0) != 0x80) return false;
      code = (code << 6) | (b & 0x3f);
    }
    const char32_t least = extra == 1 ? 0x80 : extra == 2 ? 0x800 : 0x10000;
    if (code < least || code > 0x10ffff || (code >= 0xd800 && code <= 0xdfff) ||
        (code >= 0x80 && code < 0xa0))
      return false;
    i += std::size_t(extra) + 1;
  }
  return true;
}

// A read with every check, every failure an Error "path: error: …" naming the item and what was
// expected of it. A size of −1 accepts any size (and is then fixed by what was read). Every
// dataset's values and every object's attributes are checked against their checksums (layout 3
// requires them; older files have none, and unchecked() says so); every text must be printable
// UTF-8, and a message quotes a file's bytes with quote_token().
class Input {
 public:
  explicit Input(const detail::Reader& reader) : m_r(reader) {}

  /// From layout 3 on, every checksum must be there.
  void require_checksums(bool required) { m_required = required; }
  /// Whether something was read without a checksum to check it against.
  bool unchecked() const { return m_unchecked; }

  // The attributes of `object` against their checksum (once per object).
  void verify_attributes(const std::string& object) const {
    if (!m_verified.insert(object).second) return;
    const std::optional<std::uint64_t> stored =
        m_r.checksum_attribute(object, detail::kAttributesChecksumAttribute);
    if (!stored) {
      if (m_required) {
        fail(missing_attribute(object, detail::kAttributesChecksumAttribute,
                               "the checksum of its attributes, which layout 3 requires"));
      }
      m_unchecked = true;
      return;
    }
    const std::uint64_t actual = detail::attributes_checksum(m_r.attributes(object));
    if (actual != *stored) {
      fail("the attributes of " + object + " are damaged: their checksum is " +
           detail::hex_digest(actual) + " where the file records " + detail::hex_digest(*stored));
    }
  }
  // The values of dataset `name`, whose checksum is `actual`, against the file's.
  void verify_dataset(const std::string& name, std::uint64_t actual) const {
    const std::optional<std::uint64_t> stored =
        m_r.checksum_attribute(name, detail::kChecksumAttribute);
    if (!stored) {
      if (m_required) {
        fail(missing_attribute(name, detail::kChecksumAttribute,
                               "the checksum of its values, which layout 3 requires"));
      }
      m_unchecked = true;
      return;
    }
    if (actual != *stored) {
      fail(name + " is damaged: the checksum of its values is " + detail::hex_digest(actual) +
           " where the file records " + detail::hex_digest(*stored));
    }
  }
  // `value` (read from `where`) when it is printable UTF-8.
  const std::string& checked_text(const std::string& value, const std::string& where) const {
    if (!printable_utf8(value)) {
      fail(where + " is not printable UTF-8 text: '" + quote_token(value) + "'");
    }
    return value;
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw Error(m_r.path() + ": error: " + what);
  }

  bool has(const std::string& name) const { return m_r.has(name); }
  bool has_attribute(const std::string& object, const std::string& name) const {
    return m_r.has_attribute(object, name);
  }

  void require_group(const std::string& name, const std::string& meaning) const {
    if (!m_r.has(name)) fail("missing group " + name + " (" + meaning + ")");
  }

  std::string text(const std::string& object, const std::string& name,
                   const std::string& meaning) const {
    verify_attributes(object);
    const std::optional<std::string> v = m_r.text_attribute(object, name);
    if (!v) fail(missing_attribute(object, name, "a string: " + meaning));
    return checked_text(*v, "attribute " + name + " of " + object);
  }
  std::int64_t integer(const std::string& object, const std::string& name, std::int64_t lo,
                       std::int64_t hi, const std::string& meaning) const {
    verify_attributes(object);
    const std::optional<std::int64_t> v = m_r.int_attribute(object, name);
    if (!v) fail(missing_attribute(object, name, "an integer: " + meaning));
    if (*v < lo || *v > hi) {
      fail("attribute " + name + " of " + object + " is " + std::to_string(*v) + ", expected " +
           meaning + " in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    return *v;
  }
  int integer32(const std::string& object, const std::string& name, std::int64_t lo,
                const std::string& meaning) const {
    return static_cast<int>(integer(object, name, lo, INT32_MAX, meaning));
  }
  bool flag(const std::string& object, const std::string& name, const std::string& meaning) const {
    return integer(object, name, 0, 1, meaning + " (0 or 1)") != 0;
  }
  double real(const std::string& object, const std::string& name,
              const std::string& meaning) const {
    verify_attributes(object);
    const std::optional<double> v = m_r.real_attribute(object, name);
    if (!v) fail(missing_attribute(object, name, "a number: " + meaning));
    if (!std::isfinite(*v)) {
      fail("attribute " + name + " of " + object + " is not a finite number (" + meaning + ")");
    }
    if (std::abs(*v) > kMaxMagnitude) {
      fail("attribute " + name + " of " + object + " is " + format_number(*v) + " (" + meaning +
           "): no value of a map is that large (at most 1e100 in magnitude)");
    }
    return *v;
  }
  template <class E, std::size_t N>
  E name_of(const EnumName<E> (&table)[N], const std::string& object, const std::string& name,
            const std::string& meaning) const {
    const std::string v = text(object, name, meaning);
    if (const std::optional<E> e = parse_enum(table, v)) return *e;
    fail("attribute " + name + " of " + object + " is '" + quote_token(v) + "', expected " +
         meaning + ": " + choices(table));
  }
  // A name parsed by `parse` (features::parse_feature_kind, …), which returns an optional.
  template <class Parse>
  auto parsed(const std::string& object, const std::string& name, Parse parse,
              const std::string& meaning) const {
    const std::string v = text(object, name, meaning);
    const auto e = parse(v);
    if (!e) {
      fail("attribute " + name + " of " + object + " is '" + quote_token(v) + "', expected " +
           meaning);
    }
    return *e;
  }
  template <class E, std::size_t N>
  static std::string choices(const EnumName<E> (&table)[N]) {
    std::string s;
    for (std::size_t i = 0; i < N; ++i) s += (i ? ", " : "") + std::string(table[i].name);
    return s;
  }

  // The dataset's info after checking it exists, has the expected rank and sizes and element
  // class. `shape` holds the expected sizes, −1 for any.
  DatasetInfo dataset(const std::string& name, DatasetInfo::Kind kind,
                      const std::vector<std::int64_t>& shape, const std::string& meaning) const {
    const std::string element = kind == DatasetInfo::Kind::Float     ? "float64"
                                : kind == DatasetInfo::Kind::Integer ? "integer"
                                                                     : "string";
    if (!m_r.has(name)) fail("missing dataset " + name + " (" + meaning + ", " + element + ")");
    const DatasetInfo info = m_r.info(name);
    if (info.kind != kind || (kind == DatasetInfo::Kind::Float && info.element_bytes != 8) ||
        (kind == DatasetInfo::Kind::Integer && info.element_bytes > 8)) {
      fail(name + " holds " + detail::describe_element(info) + " values, expected " + element +
           " (" + meaning + ")");
    }
    bool same = info.shape.size() == shape.size();
    for (std::size_t i = 0; same && i < shape.size(); ++i) {
      same = shape[i] < 0 || info.shape[i] == std::uint64_t(shape[i]);
    }
    if (!same) {
      std::string want;
      for (std::size_t i = 0; i < shape.size(); ++i) {
        want += (i ? "×" : "") + (shape[i] < 0 ? std::string("any") : std::to_string(shape[i]));
      }
      fail(name + " has shape " + shape_text(info.shape) + ", expected " + want + " (" + meaning +
           ")");
    }
    return info;
  }

  // A float64 matrix of rows × cols (−1: any), every value finite, read a slab of rows at a time
  // into its column-major storage (no whole row-major copy beside it: 2 GB for the geodesic
  // distances of a 10⁶-sample Isomap model).
  Eigen::MatrixXd matrix(const std::string& name, std::int64_t rows, std::int64_t cols,
                         const std::string& meaning) const {
    const DatasetInfo info = dataset(name, DatasetInfo::Kind::Float, {rows, cols}, meaning);
    const std::uint64_t R = info.shape[0], C = info.shape[1];
    Eigen::MatrixXd out(static_cast<Eigen::Index>(R), static_cast<Eigen::Index>(C));
    // 8 rows of 10⁶ values, 64 MB: a cache line of each column per slab.
    constexpr std::uint64_t kSlabValues = std::uint64_t(1) << 23;
    constexpr Eigen::Index kColumnsPerBlock = 8192;
    const std::uint64_t slab =
        std::max<std::uint64_t>(1, kSlabValues / std::max<std::uint64_t>(1, C));
    std::vector<double> buffer;
    detail::Hasher sum;
    for (std::uint64_t r = 0; r < R; r += slab) {
      const std::uint64_t n = std::min(slab, R - r);
      buffer.resize(n * C);
      m_r.double_rows(name, r, n, buffer.data());
      sum.doubles(buffer.data(), n * C);
      check_finite(name, buffer.data(), n * C, C, r);
      const Eigen::Map<const RowMatrix> rows(buffer.data(), Eigen::Index(n), Eigen::Index(C));
      // Column blocks in parallel (the scattered writes, and the first touch of out's pages).
      const int blocks = static_cast<int>((C + kColumnsPerBlock - 1) / kColumnsPerBlock);
      parallel_chunks(blocks, [&](int b, int) {
        const Eigen::Index c0 = Eigen::Index(b) * kColumnsPerBlock;
        const Eigen::Index width = std::min<Eigen::Index>(kColumnsPerBlock, Eigen::Index(C) - c0);
        out.block(Eigen::Index(r), c0, Eigen::Index(n), width) = rows.middleCols(c0, width);
      });
    }
    verify_dataset(name, sum.digest());
    return out;
  }
  RowMatrix row_matrix(const std::string& name, std::int64_t rows, std::int64_t cols,
                       const std::string& meaning) const {
    const DatasetInfo info = dataset(name, DatasetInfo::Kind::Float, {rows, cols}, meaning);
    RowMatrix out(static_cast<Eigen::Index>(info.shape[0]),
                  static_cast<Eigen::Index>(info.shape[1]));
    m_r.double_rows(name, 0, info.shape[0], out.data());
    detail::Hasher sum;
    sum.doubles(out.data(), std::size_t(out.size()));
    verify_dataset(name, sum.digest());
    check_finite(name, out.data(), std::uint64_t(out.size()), info.shape[1], 0);
    return out;
  }
  Eigen::VectorXd vector(const std::string& name, std::int64_t size,
                         const std::string& meaning) const {
    dataset(name, DatasetInfo::Kind::Float, {size}, meaning);
    const std::vector<double> values = m_r.doubles(name);
    detail::Hasher sum;
    sum.doubles(values.data(), values.size());
    verify_dataset(name, sum.digest());
    check_finite(name, values.data(), values.size(), 1, 0);
    return Eigen::Map<const Eigen::VectorXd>(values.data(), Eigen::Index(values.size()));
  }
  // Integers in [lo, hi).
  std::vector<int> ints(const std::string& name, std::int64_t size, std::int64_t lo,
                        std::int64_t hi, const std::string& meaning) const {
    dataset(name, DatasetInfo::Kind::Integer, {size}, meaning);
    const std::vector<std::int64_t> values = m_r.ints(name);
    {
      // The checksum is of the values as int32: a wider value cannot match it.
      const std::vector<std::int32_t> as_written(values.begin(), values.end());
      detail::Hasher sum;
      sum.int32s(as_written.data(), as_written.size());
      verify_dataset(name, sum.digest());
    }
    std::vector<int> out;
    out.reserve(values.size());
    for (std::size_t i = 0; i < values.size(); ++i) {
      if (values[i] < lo || values[i] >= hi) {
        fail(name + " holds " + std::to_string(values[i]) + " at index " + std::to_string(i) +
             ", expected " + meaning + " in [" + std::to_string(lo) + ", " + std::to_string(hi) +
             ")");
      }
      out.push_back(static_cast<int>(values[i]));
    }
    return out;
  }
  std::vector<std::string> strings(const std::string& name, std::int64_t size,
                                   const std::string& meaning) const {
    dataset(name, DatasetInfo::Kind::String, {size}, meaning);
    std::vector<std::string> values = m_r.strings(name);
    detail::Hasher sum;
    sum.strings(values);
    verify_dataset(name, sum.digest());
    for (std::size_t i = 0; i < values.size(); ++i) {
      checked_text(values[i], name + "[" + std::to_string(i) + "]");
    }
    return values;
  }

 private:
  static std::string missing_attribute(const std::string& object, const std::string& name,
                                       const std::string& meaning) {
    return "missing attribute " + name + " of " + object + " (" + meaning + ")";
  }
  // Fails naming the first non-finite of `count` values — or larger than kMaxMagnitude —, which
  // start at row `first_row` of a dataset of `cols` values per row. In parallel: a model's 3 GB
  // are read at a time.
  void check_finite(const std::string& name, const double* values, std::uint64_t count,
                    std::uint64_t cols, std::uint64_t first_row) const {
    constexpr std::uint64_t kValuesPerBlock = std::uint64_t(1) << 16;
    const int blocks = static_cast<int>((count + kValuesPerBlock - 1) / kValuesPerBlock);
    std::vector<std::uint64_t> first(std::size_t(blocks), count);
    parallel_chunks(blocks, [&](int b, int) {
      const std::uint64_t end = std::min(count, (std::uint64_t(b) + 1) * kValuesPerBlock);
      for (std::uint64_t i = std::uint64_t(b) * kValuesPerBlock; i < end; ++i) {
        if (!(std::abs(values[i]) <= kMaxMagnitude)) {
          first[std::size_t(b)] = i;
          return;
        }
      }
    });
    if (blocks == 0) return;
    const std::uint64_t i = *std::min_element(first.begin(), first.end());
    if (i == count) return;
    const std::string at = cols > 1 ? "row " + std::to_string(first_row + i / cols) + ", column " +
                                          std::to_string(i % cols)
                                    : "index " + std::to_string(first_row + i);
    if (!std::isfinite(values[i])) {
      fail(name + " holds a non-finite value (" + std::to_string(values[i]) + ") at " + at);
    }
    fail(name + " holds " + format_number(values[i]) + " at " + at +
         ": no value of a map is that large (at most 1e100 in magnitude)");
  }

  const detail::Reader& m_r;
  bool m_required = false;
  mutable bool m_unchecked = false;
  mutable std::set<std::string> m_verified;
};

// ---- read_map_file's sections, in the order they are read ----------------------------------

// What the file is, before anything else is trusted: its format and layout version.
// From layout 3 on, every dataset and every object's attributes carry a checksum.
std::int64_t read_version(detail::Reader& reader, Input& in) {
  // Layout 3 has no variable-length strings: known before its first string is read.
  try {
    const std::optional<std::int64_t> peek = reader.int_attribute("/", "format_version");
    if (peek && *peek >= 3) reader.refuse_variable_length_strings();
  } catch (const Error&) {  // said below, once the format is known
  }
  const std::optional<std::string> format = reader.text_attribute("/", "format");
  if (!format) {
    in.fail("not a MotionMap map file: the root has no 'format' attribute (expected format = " +
            std::string(kFormatName) + ", as `motionmap map --save` writes)");
  }
  if (*format != kFormatName) {
    in.fail("not a MotionMap map file: its format is '" + quote_token(*format) + "', expected '" +
            std::string(kFormatName) + "'");
  }
  const std::optional<std::int64_t> version = reader.int_attribute("/", "format_version");
  if (!version)
    in.fail("missing root attribute format_version (an integer; this MotionMap reads 1 to " +
            std::to_string(kFormatVersion) + ")");
  if (*version > kFormatVersion) {
    in.fail("map file layout version " + std::to_string(*version) +
            " is newer than this MotionMap reads (" + std::to_string(kFormatVersion) +
            "); read it with a newer MotionMap");
  }
  if (*version < 1) {
    in.fail("unknown map file layout version " + std::to_string(*version) +
            " (this MotionMap reads versions 1 to " + std::to_string(kFormatVersion) + ")");
  }
  if (*version >= 3 && !reader.structure_checked()) {
    in.fail(
        "layout 3 without its structure checksum (the first 4096 bytes, before HDF5's "
        "superblock): a copy made by a tool that dropped them cannot be checked; save it "
        "again");
  }
  in.require_checksums(*version >= 3);
  in.verify_attributes("/");
  return *version;
}

// /clips and /samples: the clips, and the clip and frame of every map row.
void read_clips(const Input& in, MapFile& f) {
  in.require_group("/clips", "the clips the map was made from");
  const std::vector<std::string> paths = in.strings("/clips/path", -1, "the clips' paths");
  const auto C = static_cast<std::int64_t>(paths.size());
  if (C == 0) in.fail("/clips/path is empty: a map has at least one clip");
  const std::vector<std::string> hashes = in.strings("/clips/sha256", C, "one hash per clip");
  const std::vector<int> frames =
      in.ints("/clips/frames", C, 1, INT32_MAX, "the frames in each clip's file");
  const Eigen::VectorXd frame_times = in.vector("/clips/frame_time", C, "seconds per frame");
  in.require_group("/samples", "the clip and frame of every map row");
  const std::vector<int> clip_of = in.ints("/samples/clip", -1, 0, C, "a clip index");
  const auto N = static_cast<std::int64_t>(clip_of.size());
  if (N == 0) in.fail("/samples/clip is empty: a map has at least one sample");
  const std::vector<int> firsts = in.ints("/clips/first_sample", C, 0, N, "a map row");
  const std::vector<int> counts = in.ints("/clips/samples", C, 1, N + 1, "a number of rows");
  const std::vector<int> frame_of = in.ints("/samples/frame", N, 0, INT32_MAX, "a frame index");
  for (std::int64_t c = 0, row = 0; c < C; ++c) {
    if (hashes[c].size() != 64 ||
        hashes[c].find_first_not_of("0123456789abcdef") != std::string::npos) {
      in.fail("/clips/sha256[" + std::to_string(c) + "] is '" + quote_token(hashes[c]) +
              "', expected 64 lowercase hexadecimal digits");
    }
    if (!(frame_times[c] > 0)) {
      in.fail("/clips/frame_time[" + std::to_string(c) + "] is not a positive number of seconds");
    }
    if (firsts[c] != row) {
      in.fail("/clips/first_sample[" + std::to_string(c) + "] is " + std::to_string(firsts[c]) +
              ", expected " + std::to_string(row) + " (clips' rows follow each other)");
    }
    for (std::int64_t i = row; i < row + counts[c]; ++i) {
      if (i >= N || clip_of[i] != c) {
        in.fail("/samples/clip does not hold clip " + std::to_string(c) + " in rows " +
                std::to_string(row) + " to " + std::to_string(row + counts[c] - 1) +
                " as /clips/first_sample and /clips/samples say");
      }
      if (frame_of[i] >= frames[c]) {
        in.fail("/samples/frame holds " + std::to_string(frame_of[i]) + " at row " +
                std::to_string(i) + ", but clip " + std::to_string(c) + " has " +
                std::to_string(frames[c]) + " frames");
      }
    }
    row += counts[c];
    if (c + 1 == C && row != N) {
      in.fail("/clips/samples adds up to " + std::to_string(row) + " rows, but the map has " +
              std::to_string(N));
    }
  }
  for (std::int64_t c = 0; c < C; ++c) {
    f.clips.push_back({paths[c], hashes[c], frames[c], frame_times[c], firsts[c], counts[c]});
  }
  f.clip_of = clip_of;
  f.frame_of = frame_of;
}

// /parameters (the options the map was made with, and what they came to), /notes, /warnings.
void read_parameters(const Input& in, MapFile& f) {
  const std::string p = "/parameters";
  in.require_group(p, "the effective parameters");
  f.parameters = in.text(p, "description", "the parameters line");
  features::FeatureOptions& fo = f.options.features;
  embed::EmbedOptions& eo = f.options.embed;
  fo.features =
      in.parsed(p, "features", features::parse_feature_kind, "a feature kind (quat, positions)");
  fo.distance = in.parsed(p, "distance", features::parse_distance_kind,
                          "a distance kind (pointcloud, geodesic, features)");
  fo.up = in.name_of(kAxisNames, p, "up", "an up axis");
  fo.exclude = in.text(p, "exclude", "the excluded joints' pattern");
  fo.first_frame = in.integer32(p, "first_frame", 0, "the first frame");
  fo.end_frame = in.integer32(p, "end_frame", -1, "one past the last frame (−1: the end)");
  fo.stride = in.integer32(p, "stride", 1, "the stride");
  fo.keep_first = in.flag(p, "keep_first", "keep a bind pose");
  fo.joints =
      in.parsed(p, "joints", features::parse_joint_selection, "a joint selection (all, common)");
  eo.method = in.parsed(p, "method", embed::parse_method,
                        "a method (pca, svd, mds, isomap, le, lle, umap, gplvm)");
  eo.dimensions = int(in.integer(p, "dims", 2, 3, "the map's dimensions"));
  eo.k = in.integer32(p, "k", 1, "neighbours per frame");
  f.k_used = in.integer32(p, "k_used", 0, "neighbours per frame used");
  f.heat_used = in.real(p, "heat_used", "the heat-kernel width used");
  if (!in.flag(p, "heat_auto", "whether the heat was automatic")) {
    eo.heat = in.real(p, "heat", "the heat-kernel width asked for");
  }
  eo.reg = in.real(p, "reg", "LLE's regularisation");
  if (eo.method == Method::Umap) {
    eo.min_dist = in.real(p, "min_dist", "umap's smallest map distance");
    eo.epochs = in.integer32(p, "epochs", 0, "umap's layout epochs (0: the default)");
    eo.seed = in.integer32(p, "seed", 0, "umap's random seed");
  }
  // gplvm maps written before these were kept read with the defaults.
  if (eo.method == Method::Gplvm && in.has_attribute(p, "max_iterations")) {
    eo.max_iterations = in.integer32(p, "max_iterations", 1, "gplvm's L-BFGS iteration limit");
    eo.inducing = in.integer32(p, "inducing", 0, "gplvm's inducing points (0: the default)");
  }
  // …and those written before the lengthscale was held were fitted with it free.
  if (eo.method == Method::Gplvm) {
    eo.lengthscale = in.has_attribute(p, "lengthscale")
                         ? in.real(p, "lengthscale", "gplvm's lengthscale held (0: fitted)")
                         : 0.0;
  }
  eo.standardize = in.flag(p, "standardize", "standardised PCA");
  eo.strict = in.flag(p, "strict", "strict neighbour graphs");
  eo.landmarks = in.integer32(p, "landmarks", 0, "landmarks asked for (0: the default)");
  f.landmarks_used = in.integer32(p, "landmarks_used", 0, "landmarks chosen");
  eo.search = in.name_of(embed::kSearchNames, p, "search", "a neighbour search");
  f.options.path = in.name_of(pipeline::kMapPathNames, p, "path", "a map path asked for");
  f.options.dense_limit = in.integer32(p, "dense_limit", 0, "the dense path's frame limit");
  const std::string taken = in.text(p, "path_taken", "the path taken (dense, points)");
  if (taken != "dense" && taken != "points") {
    in.fail("attribute path_taken of " + p + " is '" + quote_token(taken) +
            "', expected dense or points");
  }
  f.dense = taken == "dense";
  f.neighbor_search = in.text(p, "neighbor_search", "how neighbours were found");
  f.graph_components = in.integer32(p, "graph_components", 0, "the graph's components");
  f.connecting_edges = in.integer32(p, "connecting_edges", 0, "the edges joining them");
  if (in.has("/notes")) f.notes = in.strings("/notes", -1, "the features' notes");
  if (in.has("/warnings")) f.warnings = in.strings("/warnings", -1, "the map's warnings");
}

// /skeleton and /blend: the first clip's joint hierarchy, and what blending its clips needs.
void read_skeleton(const Input& in, MapFile& f) {
  in.require_group("/skeleton", "the first clip's joint hierarchy");
  f.skeleton.names = in.strings("/skeleton/names", -1, "joint names");
  const auto J = static_cast<std::int64_t>(f.skeleton.names.size());
  if (J == 0) in.fail("/skeleton/names is empty: a skeleton has at least one joint");
  f.skeleton.parents = in.ints("/skeleton/parents", J, -1, J, "a parent joint index (−1: root)");
  for (std::int64_t j = 0; j < J; ++j) {
    if (f.skeleton.parents[j] >= j) {
      in.fail("/skeleton/parents[" + std::to_string(j) + "] is " +
              std::to_string(f.skeleton.parents[j]) + ", expected an earlier joint or −1");
    }
  }
  f.skeleton.end_sites = in.ints("/skeleton/end_sites", J, 0, 1 << 16, "End Sites per joint");
  if (in.has("/blend")) {
    BlendRecord b;
    b.motion_root = static_cast<int>(
        in.integer("/blend", "motion_root", 0, J - 1, "the joint carrying the root motion"));
    if (in.has("/blend/moving_joints")) {
      b.moving = in.ints("/blend/moving_joints", -1, 0, J, "a joint the blend averages");
      for (std::size_t k = 0; k < b.moving.size(); ++k) {
        if (b.moving[k] == b.motion_root || (k > 0 && b.moving[k] <= b.moving[k - 1]))
          in.fail("/blend/moving_joints is not increasing or names the motion root " +
                  std::to_string(b.motion_root));
      }
    }
    f.blend = std::move(b);
  }
}

// /joints: the joints the features use, and the columns they make.
void read_joints(const Input& in, MapFile& f) {
  const features::FeatureOptions& fo = f.options.features;
  in.require_group("/joints", "the joints the features use");
  f.joints = in.strings("/joints/used", -1, "the joints the features use");
  if (in.has("/joints/shared")) f.shared_joints = in.strings("/joints/shared", -1, "shared joints");
  if (fo.joints == features::JointSelection::Common && f.shared_joints.empty()) {
    in.fail("missing dataset /joints/shared (the joint names a --joints common map compares by)");
  }
  f.x_columns = in.integer32("/joints", "x_columns", 1, "the columns of X");
  f.point_columns = in.integer32("/joints", "point_columns", 1, "the columns of the points");
}

// /labels: the samples' labels, when the map has them.
void read_labels(const Input& in, MapFile& f) {
  if (!in.has("/labels")) return;
  const std::vector<std::string> names = in.strings("/labels/names", -1, "the label names");
  if (names.empty() || names.size() > std::size_t(pipeline::kMaxLabels)) {
    in.fail("/labels/names holds " + std::to_string(names.size()) + " names, expected 1 to " +
            std::to_string(pipeline::kMaxLabels));
  }
  for (std::size_t l = 0; l < names.size(); ++l) {
    const std::string g = "/labels/" + std::to_string(l);
    in.require_group(g, "the values of label '" + quote_token(names[l]) + "'");
    pipeline::LabelColumn column;
    column.name = names[l];
    column.categories = in.strings(g + "/values", -1, "the label's distinct values");
    if (column.categories.empty()) in.fail(g + "/values is empty, expected at least one value");
    const std::vector<int> codes =
        in.ints(g + "/codes", f.num_samples(), 0, std::int64_t(column.categories.size()),
                "each sample's value (an index into " + g + "/values)");
    column.codes.assign(codes.begin(), codes.end());
    f.labels.columns.push_back(std::move(column));
  }
  try {
    pipeline::check_labels(f.labels, f.num_samples());
  } catch (const ParameterError& e) {
    in.fail(std::string("/labels: ") + e.what());
  }
}

// An item the method needs must be there; one it does not need is read when present.
bool need(const Input& in, const std::string& name, bool needed, const std::string& who) {
  if (needed && !in.has(name)) {
    in.fail("missing dataset " + name + " (" + who + " places new frames with it)");
  }
  return in.has(name);
}

// /model/landmarks: a landmark fit of M model samples.
embed::LandmarkFit read_landmarks(const Input& in, const embed::MapModel& m, std::int64_t M) {
  const std::string g = "/model", l = g + "/landmarks";
  const int dims = m.dimensions;
  embed::LandmarkFit fit;
  // Landmarks index the rows of /model/points (a landmark mds map: its own rows, in order).
  fit.frames = in.ints(l + "/frames", -1, 0, M, "a model sample index");
  const auto L = static_cast<std::int64_t>(fit.frames.size());
  if (L == 0) in.fail(l + "/frames is empty");
  if (m.points_are_landmarks && m.points.rows() != L) {
    in.fail(g + "/points has " + std::to_string(m.points.rows()) + " rows, but there are " +
            std::to_string(L) + " landmarks");
  }
  fit.projection = in.matrix(l + "/projection", dims, L, "dims by #landmarks");
  fit.mean_squared = in.vector(l + "/mean_squared", L, "#landmarks");
  fit.offset = in.vector(l + "/offset", dims, "dims");
  if (in.has(l + "/geodesic")) {
    fit.geodesic = in.matrix(l + "/geodesic", L, M, "#landmarks by #model samples");
  }
  return fit;
}

// /model/graph: the neighbour graph of M model samples (CSR).
embed::Graph read_graph(const Input& in, std::int64_t M) {
  const std::string gr = "/model/graph";
  embed::Graph graph;
  graph.offsets = in.ints(gr + "/offsets", M + 1, 0, INT32_MAX, "an offset into targets");
  graph.targets = in.ints(gr + "/targets", -1, 0, M, "a model sample index");
  const auto E = static_cast<std::int64_t>(graph.targets.size());
  const Eigen::VectorXd weights = in.vector(gr + "/weights", E, "one per target");
  graph.weights.assign(weights.data(), weights.data() + weights.size());
  if (graph.offsets.front() != 0 || graph.offsets.back() != E ||
      !std::is_sorted(graph.offsets.begin(), graph.offsets.end())) {
    in.fail(gr + "/offsets is not a CSR offset list (from 0, never decreasing, to the " +
            std::to_string(E) + " targets)");
  }
  if (std::any_of(graph.weights.begin(), graph.weights.end(), [](double w) { return w < 0; })) {
    in.fail(gr + "/weights holds a negative edge length");
  }
  return graph;
}

// /model: every item whose method uses it, each checked against the others' sizes, so that
// embed::place() reads only what is there.
void read_model(const Input& in, std::int64_t version, MapFile& f) {
  const embed::EmbedOptions& eo = f.options.embed;
  const int dims = eo.dimensions;
  const std::int64_t N = f.num_samples();
  in.require_group("/model", "what placing new frames needs");
  embed::MapModel& m = f.model;
  const std::string g = "/model";
  m.method = in.parsed(g, "method", embed::parse_method, "a method");
  if (m.method != eo.method) {
    in.fail("the model's method (" + std::string(embed::method_name(m.method)) +
            ") is not the map's (" + std::string(embed::method_name(eo.method)) + ")");
  }
  m.dimensions = int(in.integer(g, "dimensions", dims, dims, "the map's dimensions"));
  m.metric = in.name_of(kMetricNames, g, "metric", "a pose metric");
  m.points_are_landmarks = in.flag(g, "points_are_landmarks", "points hold the landmarks only");
  m.k = in.integer32(g, "k", 0, "neighbours a new frame joins through");
  m.heat = in.real(g, "heat", "the heat-kernel width");
  m.reg = in.real(g, "reg", "LLE's regularisation");
  // The model's samples: the map's rows (layout 1), or — a map of clips placed on a model fitted
  // on other frames (layout 2, placed_map_file) — as many as /model/coordinates has.
  m.coordinates =
      in.matrix(g + "/coordinates", version >= 2 ? -1 : N, dims, "#model samples by dims");
  const std::int64_t M = m.coordinates.rows();
  if (M == 0) in.fail(g + "/coordinates has no rows (a model has at least one sample)");

  const Method method = m.method;
  const bool projection = method == Method::Pca || method == Method::Svd;
  const std::string who = "the " + std::string(embed::method_name(method)) + " map";
  const std::int64_t X = f.x_columns, V = f.point_columns;
  const bool gplvm = method == Method::Gplvm;
  if (need(in, g + "/mean", method == Method::Pca || gplvm, who))
    m.mean = in.vector(g + "/mean", X, "#features");
  if (need(in, g + "/scale", method == Method::Pca && eo.standardize, who)) {
    m.scale = in.vector(g + "/scale", X, "#features");
    if ((m.scale.array() <= 0).any()) in.fail(g + "/scale holds a value ≤ 0");
  }
  if (need(in, g + "/axes", projection, who))
    m.axes = in.matrix(g + "/axes", X, dims, "#features by dims");
  if (need(in, g + "/points", !projection && !gplvm, who)) {
    // A landmark mds map keeps the landmarks' rows; the others every sample's.
    m.points = in.row_matrix(
        g + "/points", m.points_are_landmarks ? -1 : M, V,
        m.points_are_landmarks ? "#landmarks by #point values" : "#model samples by #point values");
  }
  if (need(in, g + "/eigenvalues", method == Method::LaplacianEigenmap, who)) {
    m.eigenvalues = in.vector(g + "/eigenvalues", dims, "one per axis");
    if (method == Method::LaplacianEigenmap && (m.eigenvalues.array() == 1.0).any()) {
      in.fail(g + "/eigenvalues holds 1 (the Nyström extension divides by 1 − λ)");
    }
  }
  if (need(in, g + "/features", method == Method::Lle || gplvm, who)) {
    m.features = in.row_matrix(g + "/features", M, X, "#model samples by #features");
  }
  if (uses_graph_method(method) && (m.k < 1 || m.k > M)) {
    in.fail("attribute k of " + g + " is " + std::to_string(m.k) + ", expected 1 to " +
            std::to_string(M) + " for " + who);
  }
  if (method == Method::LaplacianEigenmap && !(m.heat >= 0)) {
    in.fail("attribute heat of " + g + " is " + std::to_string(m.heat) +
            ", expected a heat-kernel width ≥ 0 (0: equal weights) for " + who);
  }
  if (method == Method::Lle && !(m.reg >= 0)) {
    in.fail("attribute reg of " + g + " is " + std::to_string(m.reg) +
            ", expected a regularisation ≥ 0 for " + who);
  }
  if (m.points_are_landmarks && method != Method::Mds) {
    in.fail("attribute points_are_landmarks of " + g +
            " is 1, but only an mds map keeps the "
            "landmarks' points alone");
  }
  if (need(in, g + "/landmarks", method == Method::Mds || method == Method::Isomap, who)) {
    m.landmarks = read_landmarks(in, m, M);
  }
  const bool dense_isomap =
      method == Method::Isomap && m.landmarks && m.landmarks->geodesic.size() == 0;
  if (need(in, g + "/graph", dense_isomap, who)) m.graph = read_graph(in, M);
  if (need(in, g + "/gplvm", gplvm, who)) {
    // The GP's predictive (embed::GplvmPredictive) over B basis points: the model's samples
    // (the full model) or its inducing inputs.
    const std::string p = g + "/gplvm";
    embed::GplvmPredictive& gp = m.gplvm;
    gp.basis = in.matrix(p + "/basis", -1, dims, "#basis points by dims");
    const std::int64_t B = gp.basis.rows();
    if (B == 0) in.fail(p + "/basis has no rows");
    gp.alpha = in.matrix(p + "/alpha", B, X, "#basis points by #features");
    gp.C = in.matrix(p + "/C", B, B, "#basis points by #basis points");
    gp.rbf_variance = in.real(p, "rbf_variance", "the kernel's RBF variance");
    gp.lengthscale = in.real(p, "lengthscale", "the kernel's lengthscale");
    gp.bias_variance = in.real(p, "bias_variance", "the kernel's bias variance");
    gp.prior_variance = in.real(p, "prior_variance", "the predictive variance far from the map");
    if (!(gp.rbf_variance > 0 && gp.lengthscale > 0 && gp.bias_variance >= 0 &&
          gp.prior_variance > 0)) {
      in.fail(p + ": the kernel's variances and lengthscale must be > 0");
    }
  }
}

// The root attribute `datasets` (layout 3): every dataset written must be there, so that one a
// damaged file lost is not taken for an optional one left out.
void read_manifest(const Input& in, std::int64_t version) {
  if (version < 3 && !in.has_attribute("/", detail::kDatasetsAttribute)) return;
  const std::string names =
      in.text("/", detail::kDatasetsAttribute, "the datasets written, separated by spaces");
  for (std::size_t at = 0; at < names.size();) {
    const std::size_t end = std::min(names.find(' ', at), names.size());
    const std::string name = names.substr(at, end - at);
    if (!name.empty() && !in.has(name)) {
      in.fail("missing dataset " + name + " (the root attribute datasets lists it)");
    }
    at = end + 1;
  }
}

// read_map_file() without its last line of defence.
MapFile read_checked(const std::string& path, const ReadOptions& options) {
  detail::Reader reader(path);
  Input in(reader);
  const std::int64_t version = read_version(reader, in);
  MapFile f;
  f.path = path;
  read_clips(in, f);
  read_parameters(in, f);
  read_skeleton(in, f);
  read_joints(in, f);
  f.coordinates =
      in.matrix("/coordinates", f.num_samples(), f.options.embed.dimensions, "#samples by dims");
  read_labels(in, f);
  // Showing or blending the map does not need the model, except a gplvm map's: its GP is what
  // its blends and its rule of where it is valid use (synth::BlendOptions::gplvm).
  if (options.model || f.options.embed.method == Method::Gplvm) read_model(in, version, f);
  read_manifest(in, version);
  if (in.unchecked()) {
    f.read_notes.push_back(path + " was written by an older MotionMap (layout " +
                           std::to_string(version) +
                           ") without checksums: damage to its data cannot be detected; save it "
                           "again to add them");
  }
  return f;
}

}  // namespace

bool looks_like_map_file(const std::string& path) {
  return detail::has_map_file_start(path);
}

MapFile read_map_file(const std::string& path, const ReadOptions& options) {
  try {
    return read_checked(path, options);
  } catch (const std::bad_alloc&) {
    // Every size is checked against what the file stores first; this is a last line, not a path.
    throw Error(path + ": error: its sizes need more memory than there is (a damaged file?)");
  }
}

}  // namespace motionmap::mapfile
