// motionmap._motionmap: clips (load, Clip, Skeleton), features, errors. The maps are in maps.cpp.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstring>
#include <sstream>

#include "common.h"
#include "motionmap/embed/points.h"
#include "motionmap/features/diagnostics.h"
#include "motionmap/features/features.h"
#include "motionmap/io/bvh.h"
#include "motionmap/io/clip_inputs.h"
#include "motionmap/io/load.h"
#include "motionmap/skeleton/forward_kinematics.h"

namespace motionmap::python {

void bind_maps(py::module_& m);

RowMatrix to_row_matrix(const InputArray& array, const std::string& what) {
  if (array.ndim() != 2) {
    throw ParameterError(what + ": expected a 2-D array (#frames by #columns), got " +
                         std::to_string(array.ndim()) + " dimensions");
  }
  if (array.shape(0) == 0 || array.shape(1) == 0) {
    throw ParameterError(what + ": the array is empty (" + std::to_string(array.shape(0)) + " by " +
                         std::to_string(array.shape(1)) + ")");
  }
  RowMatrix out(array.shape(0), array.shape(1));
  std::memcpy(out.data(), array.data(), sizeof(double) * static_cast<std::size_t>(array.size()));
  return out;
}

py::array owning_array(RowMatrix&& m, std::vector<py::ssize_t> shape) {
  auto* owned = new RowMatrix(std::move(m));
  py::capsule free_it(owned, [](void* p) { delete static_cast<RowMatrix*>(p); });
  std::vector<py::ssize_t> strides(shape.size());
  py::ssize_t stride = sizeof(double);
  for (std::size_t i = shape.size(); i-- > 0;) {
    strides[i] = stride;
    stride *= shape[i];
  }
  return py::array(py::dtype::of<double>(), shape, strides, owned->data(), free_it);
}

PyControl::PyControl(py::object progress) : m_state(std::make_shared<State>()) {
  m_state->progress = std::move(progress);
  auto state = m_state;
  Control::ProgressFn report;
  if (!m_state->progress.is_none()) {
    report = [state](double fraction, std::string_view stage) {
      if (state->error) return;
      py::gil_scoped_acquire gil;
      try {
        py::object& p = state->progress;
        if (py::hasattr(p, "update") && py::hasattr(p, "n")) {
          // tqdm: total = 100 (set by the caller or here), advance in whole steps to the
          // fraction's share of it (a bar then reads 47/100, not 47.956…/100).
          if (py::hasattr(p, "set_description")) p.attr("set_description")(std::string(stage));
          const double total = p.attr("total").is_none() ? 100.0 : p.attr("total").cast<double>();
          const double done = std::floor(fraction * total) - p.attr("n").cast<double>();
          if (done >= 1) p.attr("update")(static_cast<long long>(done));
        } else {
          p(fraction, std::string(stage));
        }
      } catch (py::error_already_set& e) {
        state->error.emplace(std::move(e));
      }
    };
  }
  auto cancel = [state]() {
    if (state->error) return true;
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) {
      state->error.emplace();  // fetches the pending KeyboardInterrupt
      return true;
    }
    return false;
  };
  m_control = Control(std::move(report), std::move(cancel));
}

void PyControl::rethrow() const {
  if (m_state->error) throw std::move(*m_state->error);
  throw Cancelled();
}

namespace {

std::string path_string(const py::handle& h) {
  return py::str(py::module_::import("os").attr("fspath")(h)).cast<std::string>();
}

bool is_path(const py::handle& h) {
  return py::isinstance<py::str>(h) || py::hasattr(h, "__fspath__");
}

}  // namespace

std::vector<Clip> clips_from_python(const py::handle& clips, const std::string& asf, double fps,
                                    bool sha256) {
  std::vector<py::handle> items;
  if (is_path(clips) || py::isinstance<Clip>(clips)) {
    items.push_back(clips);
  } else {
    for (const py::handle item : clips) items.push_back(item);
  }
  if (items.empty()) throw ParameterError("clips: no clip given");
  io::LoadOptions load;
  load.asf_path = asf;
  load.fps = fps;
  load.sha256 = sha256;
  std::vector<Clip> out;
  out.reserve(items.size());
  for (const py::handle item : items) {
    if (py::isinstance<Clip>(item)) {
      out.push_back(item.cast<const Clip&>());
    } else if (is_path(item)) {
      const std::string path = path_string(item);
      py::gil_scoped_release release;
      out.push_back(io::load_clip(path, load));
    } else {
      throw ParameterError("clips: expected motionmap.Clip objects or paths, got " +
                           py::str(py::type::of(item)).cast<std::string>());
    }
  }
  return out;
}

namespace {

// ---- Clip -------------------------------------------------------------------------------------

int root_joint(const Clip& clip) {
  const auto roots = clip.skeleton.roots();
  return roots.empty() ? 0 : roots.front();
}

py::array rotations(const Clip& clip) {
  const Motion& m = clip.motion;
  RowMatrix q(static_cast<Eigen::Index>(m.num_frames) * m.num_joints, 4);
  for (std::size_t i = 0; i < m.rotations.size(); ++i) {
    const auto& r = m.rotations[i];
    q.row(static_cast<Eigen::Index>(i)) << r.w(), r.x(), r.y(), r.z();
  }
  return owning_array(std::move(q), {m.num_frames, m.num_joints, 4});
}

py::array translations(const Clip& clip) {
  const Motion& m = clip.motion;
  RowMatrix t(static_cast<Eigen::Index>(m.num_frames) * m.num_joints, 3);
  for (std::size_t i = 0; i < m.translations.size(); ++i)
    t.row(static_cast<Eigen::Index>(i)) = m.translations[i].transpose();
  return owning_array(std::move(t), {m.num_frames, m.num_joints, 3});
}

py::array root_translations(const Clip& clip) {
  const Motion& m = clip.motion;
  RowMatrix t(m.num_frames, 3);
  const int root = root_joint(clip);
  for (int f = 0; f < m.num_frames; ++f) t.row(f) = m.translation(f, root).transpose();
  return owning_array(std::move(t), {m.num_frames, 3});
}

py::array positions(const Clip& clip) {
  RowMatrix points;
  {
    py::gil_scoped_release release;
    points = world_points(clip.skeleton, clip.motion);
  }
  const py::ssize_t frames = points.rows(), count = points.cols() / 3;
  return owning_array(std::move(points), {frames, count, 3});
}

// What `motionmap info --json` prints, as a dict (numbers at full precision).
py::dict info(const Clip& clip) {
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
  std::vector<std::string> warnings = clip.warnings;
  {
    py::gil_scoped_release release;
    if (clip.motion.num_frames > 0) {
      const auto points = world_points(clip.skeleton, clip.motion);
      lo.setConstant(INFINITY);
      hi.setConstant(-INFINITY);
      for (Eigen::Index c = 0; c < points.cols(); c += 3) {
        lo = lo.cwiseMin(points.middleCols<3>(c).colwise().minCoeff().transpose());
        hi = hi.cwiseMax(points.middleCols<3>(c).colwise().maxCoeff().transpose());
      }
    }
    for (auto& w : features::clip_warnings(clip.skeleton, clip.motion))
      warnings.push_back(std::move(w));
  }
  const Skeleton& sk = clip.skeleton;
  py::list root_names;
  for (int r : sk.roots()) root_names.append(sk.joints[r].name);
  py::dict box;
  box["min"] = py::make_tuple(lo.x(), lo.y(), lo.z());
  box["max"] = py::make_tuple(hi.x(), hi.y(), hi.z());
  py::dict d;
  d["file"] = clip.path;
  d["joints"] = sk.num_joints();
  d["roots"] = sk.roots().size();
  d["root_names"] = root_names;
  d["channels"] = sk.num_channels();
  d["end_sites"] = sk.num_end_sites();
  d["frames"] = clip.motion.num_frames;
  d["frame_time"] = clip.motion.frame_time;
  d["fps"] = clip.motion.fps();
  d["duration"] = clip.motion.duration();
  d["bounding_box"] = box;
  d["warnings"] = warnings;
  return d;
}

void save(const Clip& clip, const py::object& path) {
  const std::string out = path_string(path);
  py::gil_scoped_release release;
  check_clip(clip);
  io::write_bvh(io::from_motion(clip.skeleton, clip.motion), out);
}

// ---- Skeleton ---------------------------------------------------------------------------------

py::list channel_layout(const Skeleton& sk) {
  py::list out;
  for (const Joint& j : sk.joints) {
    py::list names;
    for (ChannelType c : j.channels) names.append(std::string(channel_name(c)));
    out.append(names);
  }
  return out;
}

py::array offsets(const Skeleton& sk) {
  RowMatrix o(sk.num_joints(), 3);
  for (int j = 0; j < sk.num_joints(); ++j) o.row(j) = sk.joints[j].offset.transpose();
  return owning_array(std::move(o), {sk.num_joints(), 3});
}

py::list end_sites(const Skeleton& sk) {
  py::list out;
  for (const Joint& j : sk.joints) {
    RowMatrix e(static_cast<Eigen::Index>(j.end_sites.size()), 3);
    for (std::size_t i = 0; i < j.end_sites.size(); ++i)
      e.row(static_cast<Eigen::Index>(i)) = j.end_sites[i].transpose();
    const auto n = static_cast<py::ssize_t>(j.end_sites.size());
    out.append(owning_array(std::move(e), {n, 3}));
  }
  return out;
}

// ---- features ---------------------------------------------------------------------------------

template <class E>
E parse_name(const std::string& what, const std::string& value,
             std::optional<E> (*parse)(std::string_view), const std::vector<E>& all,
             std::string_view (*name)(E)) {
  if (auto v = parse(value)) return *v;
  std::string names;
  for (E e : all) names += (names.empty() ? "" : ", ") + std::string(name(e));
  throw ParameterError(what + ": unknown name '" + value + "' (expected one of " + names + ")");
}

}  // namespace

features::FeatureOptions feature_options(const py::dict& o) {
  features::FeatureOptions f;
  for (const auto& [key, value] : o) {
    const std::string k = key.cast<std::string>();
    if (k == "features") {
      f.features = parse_name("features", value.cast<std::string>(), features::parse_feature_kind,
                              features::all_feature_kinds(), features::feature_kind_name);
    } else if (k == "distance") {
      f.distance = parse_name("distance", value.cast<std::string>(), features::parse_distance_kind,
                              features::all_distance_kinds(), features::distance_kind_name);
    } else if (k == "joints") {
      f.joints = parse_name("joints", value.cast<std::string>(), features::parse_joint_selection,
                            features::all_joint_selections(), features::joint_selection_name);
    } else if (k == "up") {
      const std::string up = value.cast<std::string>();
      const std::optional<Axis> axis = parse_axis(up);
      if (!axis || *axis == Axis::X)
        throw ParameterError("up: '" + up + "' is not an axis (expected 'y' or 'z')");
      f.up = *axis;
    } else if (k == "exclude") {
      f.exclude = value.is_none() ? std::string() : value.cast<std::string>();
    } else if (k == "frames") {
      if (!value.is_none()) {
        const auto range = value.cast<py::tuple>();
        if (range.size() != 2) throw ParameterError("frames: expected (first, end)");
        f.first_frame = range[0].is_none() ? 0 : range[0].cast<int>();
        f.end_frame = range[1].is_none() ? -1 : range[1].cast<int>();
      }
    } else if (k == "stride") {
      f.stride = value.cast<int>();
    } else if (k == "keep_first") {
      f.keep_first = value.cast<bool>();
    } else {
      continue;  // the map's own options (maps.cpp)
    }
  }
  f.validate();
  return f;
}

namespace {

// The metric of the points D is computed from (as the pipeline measures them: geodesic
// distances between quaternion rows, Euclidean otherwise).
Metric metric_of(features::DistanceKind kind) {
  return kind == features::DistanceKind::Geodesic ? Metric::QuaternionAngles : Metric::Euclidean;
}

// X; D when `distances`; the k nearest neighbours of every frame (indices and distances, #frames
// by k each) when `neighbors` > 0, found from the points without D (embed/points.h).
py::tuple build_features(const py::object& clips, const py::dict& options, bool distances,
                         int neighbors, const std::string& asf, double fps, py::object progress) {
  const features::FeatureOptions f = feature_options(options);
  const std::vector<Clip> loaded = clips_from_python(clips, asf, fps);
  embed::NeighborLists nn;
  std::string search;
  features::FeatureSet set = run_released(std::move(progress), [&](const Control& control) {
    const double end = neighbors > 0 ? 0.7 : 1.0;
    features::FeatureSet out =
        features::build_features(loaded, f, control.part(0.0, end),
                                 distances ? features::Distances::Now : features::Distances::Later);
    if (neighbors > 0) {
      const embed::PointSet points{&out.distance_input, metric_of(out.distance)};
      embed::NeighborSearchReport report;
      nn = embed::knn_from_points(points, neighbors, embed::NeighborSearch::Auto,
                                  control.stage("neighbours", end, 1.0), &report);
      search = report.description();
    }
    return out;
  });
  py::object D = py::none(), index = py::none(), distance = py::none();
  if (distances) D = py::cast(std::move(set.D));
  if (neighbors > 0) {
    const py::ssize_t n = nn.frames();
    index = py::array_t<int>({n, py::ssize_t(nn.k)}, nn.index.data());
    distance = py::array_t<double>({n, py::ssize_t(nn.k)}, nn.distance.data());
  }
  return py::make_tuple(py::cast(std::move(set.X)), D, index, distance, search);
}

}  // namespace

void init_module(py::module_& m) {
  m.doc() = "MotionMap's C++ library, bound with pybind11 (use the package motionmap).";
  // Every error of the library is a motionmap.Error, a ValueError, with the library's message
  // (`path:line:col: error: …` for a malformed file).
  py::register_exception<Error>(m, "Error", PyExc_ValueError);

  py::class_<Skeleton>(m, "Skeleton",
                       "The joints of a clip, parents before children (read-only views).")
      .def_property_readonly(
          "names",
          [](const Skeleton& s) {
            std::vector<std::string> names;
            for (const Joint& j : s.joints) names.push_back(j.name);
            return names;
          },
          "Joint names, in file order.")
      .def_property_readonly(
          "parents",
          [](const Skeleton& s) {
            std::vector<int> parents;
            for (const Joint& j : s.joints) parents.push_back(j.parent);
            return py::array(py::cast(parents));
          },
          "Parent index of each joint (-1 for a root), int array of #joints.")
      .def_property_readonly("offsets", &offsets,
                             "Rest offsets from the parent, #joints by 3 (file units).")
      .def_property_readonly("channels", &channel_layout,
                             "Each joint's channels as in the file ('Xposition', …, 'Zrotation').")
      .def_property_readonly("end_sites", &end_sites,
                             "Each joint's End Site offsets (an #end sites by 3 array per joint).")
      .def_property_readonly("num_joints", &Skeleton::num_joints)
      .def_property_readonly("roots", &Skeleton::roots, "Indices of the joints without parent.")
      .def("find", &Skeleton::find, py::arg("name"), "Index of the joint called name, or -1.")
      .def("__len__", &Skeleton::num_joints)
      .def("__repr__", [](const Skeleton& s) {
        return "<motionmap.Skeleton of " + std::to_string(s.num_joints()) + " joints>";
      });

  py::class_<Clip>(m, "Clip",
                   "A motion clip: skeleton, frame time and per-frame local rotations and "
                   "translations. Made by motionmap.load().")
      .def_readonly("path", &Clip::path, "The file it was loaded from.")
      .def_readonly("warnings", &Clip::warnings,
                    "What the reader accepted with a warning ('path:line: warning: …').")
      .def_readonly("skeleton", &Clip::skeleton)
      .def_property_readonly(
          "frame_time", [](const Clip& c) { return c.motion.frame_time; }, "Seconds per frame.")
      .def_property_readonly("fps", [](const Clip& c) { return c.motion.fps(); })
      .def_property_readonly("num_frames", [](const Clip& c) { return c.motion.num_frames; })
      .def_property_readonly("duration", [](const Clip& c) { return c.motion.duration(); })
      .def_property_readonly("rotations", &rotations,
                             "Local joint rotations, #frames by #joints by 4 unit quaternions "
                             "(w, x, y, z); a new array each time.")
      .def_property_readonly("translations", &translations,
                             "Local joint translations, #frames by #joints by 3 (the rest offset "
                             "where the file animates no position).")
      .def_property_readonly("root_translations", &root_translations,
                             "The first root joint's translation per frame, #frames by 3.")
      .def("positions", &positions,
           "World positions by forward kinematics: #frames by (#joints + #end sites) by 3, "
           "joints first, then end sites.")
      .def("info", &info,
           "What `motionmap info --json` prints, as a dict (numbers at full precision).")
      .def("save", &save, py::arg("path"),
           "Writes the clip as BVH (its channel layout; rotations decomposed into its channels).")
      .def("__len__", [](const Clip& c) { return c.motion.num_frames; })
      .def("__repr__", [](const Clip& c) {
        std::ostringstream s;
        s << "<motionmap.Clip '" << c.path << "': " << c.motion.num_frames << " frames at "
          << c.motion.fps() << " fps, " << c.skeleton.num_joints() << " joints>";
        return s.str();
      });

  m.def(
      "load",
      [](const py::object& path, const py::object& asf, const py::object& fps) {
        io::LoadOptions load;
        const std::string p = path_string(path);
        if (!asf.is_none()) load.asf_path = path_string(asf);
        if (!fps.is_none()) {
          load.fps = fps.cast<double>();
          if (!(load.fps > 0) || !std::isfinite(load.fps))
            throw ParameterError("fps: " + py::str(fps).cast<std::string>() +
                                 " is not a number > 0");
        }
        py::gil_scoped_release release;
        return io::load_clip(p, load);
      },
      py::arg("path"), py::arg("asf") = py::none(), py::arg("fps") = py::none(),
      "Loads a .bvh, or an .amc with its .asf (asf=None: the one beside it).");

  m.def("_features", &build_features, py::arg("clips"), py::arg("options"), py::arg("distances"),
        py::arg("neighbors"), py::arg("asf"), py::arg("fps"), py::arg("progress"));

  bind_maps(m);
}

}  // namespace motionmap::python

PYBIND11_MODULE(_motionmap, m) {
  motionmap::python::init_module(m);
}
