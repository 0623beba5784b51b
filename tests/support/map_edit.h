#pragma once
// Edits a map file with the HDF5 C API, for the map file tests and the structure-aware map file
// fuzzer (fuzz/fuzz_mapfile_edits.cpp).
#include <hdf5.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "motionmap/mapfile/detail/checksum.h"
#include "motionmap/mapfile/detail/hdf5.h"

namespace motionmap::test {

// Edits a file with the HDF5 C API, as another program (or a damaged copy) would leave it.
//
// An edit is sealed by default: the file's checksums are recomputed afterwards, so that it is a
// file made that way on purpose and reaches the checks behind the checksums. Damage::Unsealed
// leaves the datasets' and attributes' checksums as they were, as damage on a disk would, and
// recomputes only the structure checksum (the user block), so that the checks behind it are
// reached (tests of the structure checksum change the file's bytes directly).
class Edit {
 public:
  enum class Damage { Sealed, Unsealed };
  explicit Edit(const std::string& path, Damage damage = Damage::Sealed)
      : m_path(path), m_damage(damage), m_file(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT)) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~Edit() {
    if (!m_finished) finish();
  }
  // Closes the file and seals it as the damage says (the destructor does when this was not
  // called). @throws Error when the checksums cannot be computed of what the edits left.
  void finish() {
    m_finished = true;
    H5Fclose(m_file);
    if (m_damage == Damage::Sealed) {
      mapfile::detail::write_checksums(m_path);
    } else {
      mapfile::detail::write_structure_checksum(m_path);
    }
  }
  // Leaves the checksums as they were after all (an edit whose values cannot be hashed).
  void unsealed() { m_damage = Damage::Unsealed; }
  Edit(const Edit&) = delete;
  Edit& operator=(const Edit&) = delete;

  void remove_attribute(const std::string& object, const std::string& name) {
    H5Adelete_by_name(m_file, object.c_str(), name.c_str(), H5P_DEFAULT);
  }
  // Removes every checksum, as a file of layout 1 or 2 has none.
  void remove_checksums() {
    for (const char* object : {"/", "/clips", "/samples", "/parameters", "/skeleton", "/blend",
                               "/joints", "/model", "/model/landmarks", "/model/graph"}) {
      remove_attribute(object, mapfile::detail::kAttributesChecksumAttribute);
    }
    H5Ovisit2(
        m_file, H5_INDEX_NAME, H5_ITER_NATIVE,
        [](hid_t file, const char* name, const H5O_info_t* info, void*) -> herr_t {
          if (info->type == H5O_TYPE_DATASET) {
            H5Adelete_by_name(file, name, mapfile::detail::kChecksumAttribute, H5P_DEFAULT);
          }
          return 0;
        },
        nullptr, H5O_INFO_BASIC);
  }
  // A dataset of rows × cols float64 whose values were never written (no storage).
  void unwritten(const std::string& name, hsize_t rows, hsize_t cols) {
    remove(name);
    const hsize_t dims[2] = {rows, cols};
    const hid_t space = H5Screate_simple(2, dims, nullptr);
    const hid_t d = H5Dcreate2(m_file, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT,
                               H5P_DEFAULT, H5P_DEFAULT);
    H5Dclose(d);
    H5Sclose(space);
  }

  void remove(const std::string& name) { H5Ldelete(m_file, name.c_str(), H5P_DEFAULT); }
  void int_attribute(const std::string& object, const std::string& name, long long value) {
    H5Adelete_by_name(m_file, object.c_str(), name.c_str(), H5P_DEFAULT);
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t a = H5Acreate_by_name(m_file, object.c_str(), name.c_str(), H5T_STD_I64LE, space,
                                      H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, H5T_NATIVE_LLONG, &value);
    H5Aclose(a);
    H5Sclose(space);
  }
  // A fixed-length ASCII string, as layout 3 writes (in UTF-8) and MATLAB does.
  void text_attribute(const std::string& object, const std::string& name, const char* value) {
    H5Adelete_by_name(m_file, object.c_str(), name.c_str(), H5P_DEFAULT);
    const hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, std::strlen(value) + 1);
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t a = H5Acreate_by_name(m_file, object.c_str(), name.c_str(), type, space,
                                      H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, type, value);
    H5Aclose(a);
    H5Sclose(space);
    H5Tclose(type);
  }
  // A variable-length ASCII string, as layouts 1 and 2 wrote (in UTF-8) and h5py does.
  void variable_text_attribute(const std::string& object, const std::string& name,
                               const char* value) {
    H5Adelete_by_name(m_file, object.c_str(), name.c_str(), H5P_DEFAULT);
    const hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, H5T_VARIABLE);
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t a = H5Acreate_by_name(m_file, object.c_str(), name.c_str(), type, space,
                                      H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, type, &value);
    H5Aclose(a);
    H5Sclose(space);
    H5Tclose(type);
  }
  // Replaces dataset `name` by fixed-length ASCII strings, null-padded, as MATLAB writes them.
  void fixed_strings(const std::string& name, const std::vector<std::string>& values) {
    remove(name);
    std::size_t size = 1;
    for (const std::string& v : values) size = std::max(size, v.size() + 1);
    std::vector<char> buffer(values.size() * size, '\0');
    for (std::size_t i = 0; i < values.size(); ++i) {
      std::memcpy(buffer.data() + i * size, values[i].data(), values[i].size());
    }
    const hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, size);
    H5Tset_strpad(type, H5T_STR_NULLPAD);
    const hsize_t dims[1] = {values.size()};
    const hid_t space = H5Screate_simple(1, dims, nullptr);
    const hid_t d =
        H5Dcreate2(m_file, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data());
    H5Dclose(d);
    H5Sclose(space);
    H5Tclose(type);
  }
  // Replaces dataset `name` by a rows × cols (cols 0: 1-D) one of `type` filled with `value`.
  void replace(const std::string& name, hsize_t rows, hsize_t cols, hid_t type, double value) {
    remove(name);
    const hsize_t dims[2] = {rows, cols};
    const hid_t space = H5Screate_simple(cols == 0 ? 1 : 2, dims, nullptr);
    const hid_t d =
        H5Dcreate2(m_file, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    std::vector<double> values(rows * std::max<hsize_t>(cols, 1), value);
    H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
    H5Dclose(d);
    H5Sclose(space);
  }
  // Sets one value of the float dataset `name` (rows × cols) in place.
  void set(const std::string& name, hsize_t row, hsize_t col, double value) {
    const hid_t d = H5Dopen2(m_file, name.c_str(), H5P_DEFAULT);
    const hid_t space = H5Dget_space(d);
    const hsize_t start[2] = {row, col}, one[2] = {1, 1};
    H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, one, nullptr);
    const hid_t memory = H5Screate_simple(2, one, nullptr);
    H5Dwrite(d, H5T_NATIVE_DOUBLE, memory, space, H5P_DEFAULT, &value);
    H5Sclose(memory);
    H5Sclose(space);
    H5Dclose(d);
  }
  // Sets the value at row-major position `index` of dataset `name` (any rank and number type,
  // converted by HDF5) in place; nothing when it has no such position.
  void set_flat(const std::string& name, hsize_t index, double value) {
    const hid_t d = H5Dopen2(m_file, name.c_str(), H5P_DEFAULT);
    if (d < 0) return;
    const hid_t space = H5Dget_space(d);
    const int rank = H5Sget_simple_extent_ndims(space);
    hsize_t dims[H5S_MAX_RANK] = {};
    if (rank > 0 && H5Sget_simple_extent_dims(space, dims, nullptr) == rank) {
      hsize_t start[H5S_MAX_RANK] = {}, one[H5S_MAX_RANK] = {};
      for (int r = rank - 1; r >= 0; --r) {
        one[r] = 1;
        start[r] = dims[r] == 0 ? 0 : index % dims[r];
        index = dims[r] == 0 ? 0 : index / dims[r];
      }
      const hsize_t single = 1;
      const hid_t memory = H5Screate_simple(1, &single, nullptr);
      if (H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, one, nullptr) >= 0) {
        H5Dwrite(d, H5T_NATIVE_DOUBLE, memory, space, H5P_DEFAULT, &value);
      }
      H5Sclose(memory);
    }
    H5Sclose(space);
    H5Dclose(d);
  }
  // Rewrites the float dataset `name` (2-D) chunked, shuffled and deflated, as MotionMap wrote
  // float datasets before 2026-11-25 and other writers may.
  void compress(const std::string& name) {
    hid_t d = H5Dopen2(m_file, name.c_str(), H5P_DEFAULT);
    const hid_t space = H5Dget_space(d);
    hsize_t dims[2] = {0, 0};
    H5Sget_simple_extent_dims(space, dims, nullptr);
    std::vector<double> values(dims[0] * dims[1]);
    H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
    H5Dclose(d);
    remove(name);
    const hid_t create = H5Pcreate(H5P_DATASET_CREATE);
    const hsize_t chunk[2] = {std::max<hsize_t>(1, std::min<hsize_t>(dims[0], 1000)), dims[1]};
    H5Pset_chunk(create, 2, chunk);
    H5Pset_shuffle(create);
    H5Pset_deflate(create, 1);
    d = H5Dcreate2(m_file, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, create, H5P_DEFAULT);
    H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
    H5Dclose(d);
    H5Pclose(create);
    H5Sclose(space);
  }

 private:
  std::string m_path;
  Damage m_damage;
  hid_t m_file;
  bool m_finished = false;
};

}  // namespace motionmap::test
