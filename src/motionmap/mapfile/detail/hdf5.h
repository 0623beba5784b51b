#pragma once
// The HDF5 C API behind two small classes, the only code of MotionMap that includes <hdf5.h>:
// Writer creates a file of groups, attributes and datasets; Reader opens one and reads them back
// with their shapes and element classes, so that the map file's code can check every item
// before it trusts it. Every failure is a motionmap::Error naming the file and the object.
//
//   detail::Writer w("lib.mmap.h5");
//   w.group("/model");
//   w.attribute("/", "format", "motionmap-map");
//   w.doubles("/coordinates", data, rows, cols);   // row-major, stored as rows × cols
//   w.close();
//
// Matrices are row-major here and in the file (HDF5's order, and numpy's): Eigen's
// column-major matrices are transposed by the caller. HDF5's own error printing is switched off
// while a Writer or Reader is in use, and one process-wide lock serialises them (Debian's serial
// HDF5 is not built thread-safe).
//
// Writer writes no variable-length data (strings are fixed-length UTF-8), so that reading a file
// of ours never has HDF5 follow a global-heap reference a damaged file could hold; and it gives
// every dataset and every object's attributes a checksum (detail/checksum.h).
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "motionmap/mapfile/detail/checksum.h"

namespace motionmap::mapfile::detail {

/// What a dataset holds: its element class and size, and its shape (empty for a scalar).
struct DatasetInfo {
  enum class Kind { Float, Integer, String, Other } kind = Kind::Other;
  std::size_t element_bytes = 0;
  std::vector<std::uint64_t> shape;
};

/// The element class as a reader would name it: "float64", "int32", "string", "compound", …
std::string describe_element(const DatasetInfo& info);

class Writer {
 public:
  /// Creates `path` (replacing a file there). @throws Error naming the path.
  explicit Writer(const std::string& path);
  ~Writer();
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  /// Creates the group `name` ("/model/landmarks"); its parent must exist.
  void group(const std::string& name);
  /// Scalar attributes on the object `object` ("/" for the root); text as fixed-length UTF-8.
  void attribute(const std::string& object, const std::string& name, const std::string& value);
  void attribute(const std::string& object, const std::string& name, const char* value) {
    attribute(object, name, std::string(value));
  }
  void attribute(const std::string& object, const std::string& name, std::int64_t value);
  void attribute(const std::string& object, const std::string& name, int value) {
    attribute(object, name, std::int64_t{value});
  }
  void attribute(const std::string& object, const std::string& name, bool value) {
    attribute(object, name, std::int64_t{value ? 1 : 0});
  }
  void attribute(const std::string& object, const std::string& name, double value);

  /// A float64 dataset of `rows` values (cols = 0) or rows × cols values, row-major. Large ones
  /// are chunked and compressed (shuffle + deflate, lossless).
  void doubles(const std::string& name, const double* data, std::uint64_t rows,
               std::uint64_t cols = 0);
  /// An int32 dataset of `count` values.
  void ints(const std::string& name, const std::int32_t* data, std::uint64_t count);
  /// A dataset of fixed-length UTF-8 strings (as long as the longest, at least 1 byte), null-
  /// padded.
  void strings(const std::string& name, const std::vector<std::string>& values);
  /// A second name for an existing object (an HDF5 hard link: one copy of the data).
  void link(const std::string& existing, const std::string& name);

  /// Writes the attributes' checksums, flushes and closes the file. @throws Error if that fails.
  /// The destructor closes a file that was not closed (after an error) and removes it, so no
  /// half-written map is left.
  void close();

 private:
  struct State;
  std::unique_ptr<State> m;
};

class Reader {
 public:
  /// Opens `path` read-only, after checking its structure checksum (the user block layout 3
  /// writes; `check_structure` false skips it, for write_checksums()). @throws Error naming the
  /// path: missing or unreadable, a damaged structure, or not an HDF5 file.
  explicit Reader(const std::string& path, bool check_structure = true);
  ~Reader();
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  const std::string& path() const;
  /// Whether the file's structure checksum (its user block, layout 3) was there and checked
  /// before HDF5 read it. A file with a damaged one is refused when opened.
  bool structure_checked() const;
  /// From now on, a variable-length string (which layout 3 never writes) is an error instead of
  /// a read: HDF5 would follow its global-heap reference, which a damaged file can point anywhere.
  void refuse_variable_length_strings();

  /// Whether an object (group or dataset) named `name` exists ("/model/landmarks/frames").
  bool has(const std::string& name) const;
  bool has_attribute(const std::string& object, const std::string& name) const;

  /// Scalar attributes; nullopt when absent. @throws Error for one of another class or shape.
  std::optional<std::string> text_attribute(const std::string& object,
                                            const std::string& name) const;
  std::optional<std::int64_t> int_attribute(const std::string& object,
                                            const std::string& name) const;
  std::optional<double> real_attribute(const std::string& object, const std::string& name) const;
  /// A checksum attribute (an unsigned 64-bit integer); nullopt when absent.
  std::optional<std::uint64_t> checksum_attribute(const std::string& object,
                                                  const std::string& name) const;
  /// Every attribute of `object` as attributes_checksum() reads them. @throws Error for one that
  /// is not a single string, integer or float.
  std::vector<AttributeValue> attributes(const std::string& object) const;

  /// The dataset `name`'s class and shape. @throws Error if it is not a dataset, or if its shape
  /// holds more values than its storage can (a damaged size, not an allocation to attempt).
  DatasetInfo info(const std::string& name) const;
  /// All values of a dataset, in row-major order: float datasets as double, integer ones as
  /// int64, strings (variable or fixed length) as std::string. The caller checks info() first.
  std::vector<double> doubles(const std::string& name) const;
  std::vector<std::int64_t> ints(const std::string& name) const;
  std::vector<std::string> strings(const std::string& name) const;
  /// Rows [first, first + count) of a float dataset of rank 1 or 2, as double, row-major, into
  /// `out` (count × the row's values): large matrices read straight into their storage, or in
  /// slabs, without a second whole copy.
  void double_rows(const std::string& name, std::uint64_t first, std::uint64_t count,
                   double* out) const;

 private:
  struct State;
  std::unique_ptr<State> m;
};

/// Whether the file `path` starts with the user block layout 3 writes or with HDF5's signature.
bool has_map_file_start(const std::string& path);

/// Recomputes every checksum of the map file `path` in place (each dataset's and each object's
/// attributes', then its structure's), so that a file edited on purpose reads as sound: for
/// tests and fuzzing of the checks behind the checksums. @throws Error naming the path.
void write_checksums(const std::string& path);
/// Recomputes the structure checksum only (a file written with a user block of 4 096 bytes).
void write_structure_checksum(const std::string& path);

}  // namespace motionmap::mapfile::detail
