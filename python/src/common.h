#pragma once
// What the files of the extension module share: numpy conversions, the Control that lets a long
// call report to a Python callback and stop on Ctrl-C, and name parsing with Python-friendly
// messages. The module is a thin shell over MotionMap::motionmap, like apps/cli.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "motionmap/core/control.h"
#include "motionmap/core/error.h"
#include "motionmap/core/metric.h"
#include "motionmap/skeleton/skeleton.h"

namespace motionmap::python {

namespace py = pybind11;

/// A 2-D float64 C-ordered view of any array-like (float32, non-contiguous, lists: converted once).
using InputArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// `array` as #rows by #cols. @throws ParameterError naming `what` unless it is 2-D and non-empty.
RowMatrix to_row_matrix(const InputArray& array, const std::string& what);

/// A numpy array that owns `m` (moved into a capsule, no copy), shaped `shape` (its size must be
/// m.size(); C order).
py::array owning_array(RowMatrix&& m, std::vector<py::ssize_t> shape);

/// A Control whose progress goes to `progress` (None: nowhere; a callable(fraction, stage), or a
/// tqdm-like object with `total`/`n`/`update`/`set_description`) and whose cancel check runs
/// Python's signal handlers, so Ctrl-C stops the computation. Call it with the GIL released; it
/// takes the GIL for each report and check.
class PyControl {
 public:
  explicit PyControl(py::object progress);
  const Control& control() const { return m_control; }
  /// After the library threw Cancelled: raises the Python exception (KeyboardInterrupt, or what
  /// the callback raised) that stopped it. Call with the GIL held.
  [[noreturn]] void rethrow() const;

 private:
  struct State {
    py::object progress;
    std::optional<py::error_already_set> error;
  };
  std::shared_ptr<State> m_state;
  Control m_control;
};

/// Runs `fn` with the GIL released under `progress`'s control; a Cancelled from Ctrl-C or a
/// callback's exception is raised as that Python exception.
template <class Fn>
auto run_released(py::object progress, Fn&& fn) {
  PyControl control(std::move(progress));
  try {
    py::gil_scoped_release release;
    return fn(control.control());
  } catch (const Cancelled&) {
    control.rethrow();
  }
}

/// Clips from a Python list of motionmap.Clip objects and/or paths (str, os.PathLike): paths
/// are loaded (with `asf`, `fps`, and with `sha256` their SHA-256 for a map file's record),
/// Clip objects copied.
std::vector<Clip> clips_from_python(const py::handle& clips, const std::string& asf, double fps,
                                    bool sha256 = false);

}  // namespace motionmap::python
