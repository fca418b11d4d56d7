#include "PluginViews.h"

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <stdexcept>

namespace py = pybind11;

namespace budget_slam::python {
namespace {

/// The landmarks of `which` (indices into ctx.landmarks) as a dict of equal-length columns.
py::dict columns(const DropContext& c, const std::vector<std::size_t>& which,
                 bool mark_candidates) {
  const auto n = static_cast<py::ssize_t>(which.size());
  py::array_t<std::int64_t> id(n), n_obs(n), first(n), last(n);
  py::array_t<double> x(n), y(n), vx(n), vy(n), cxy(n), ox(n), oy(n);
  auto i_id = id.mutable_unchecked<1>(), i_n = n_obs.mutable_unchecked<1>(),
       i_first = first.mutable_unchecked<1>(), i_last = last.mutable_unchecked<1>();
  auto d_x = x.mutable_unchecked<1>(), d_y = y.mutable_unchecked<1>(),
       d_vx = vx.mutable_unchecked<1>(), d_vy = vy.mutable_unchecked<1>(),
       d_cxy = cxy.mutable_unchecked<1>(), d_ox = ox.mutable_unchecked<1>(),
       d_oy = oy.mutable_unchecked<1>();
  for (py::ssize_t k = 0; k < n; ++k) {
    const LandmarkView& l = c.landmarks[which[static_cast<std::size_t>(k)]];
    i_id(k) = l.id, i_n(k) = static_cast<std::int64_t>(l.n_obs);
    i_first(k) = static_cast<std::int64_t>(l.first_step);
    i_last(k) = static_cast<std::int64_t>(l.last_step);
    d_x(k) = l.mean.x(), d_y(k) = l.mean.y();
    d_vx(k) = l.cov(0, 0), d_vy(k) = l.cov(1, 1), d_cxy(k) = l.cov(0, 1);
    d_ox(k) = l.obs_mean.x(), d_oy(k) = l.obs_mean.y();
  }
  py::dict d;
  d["id"] = id, d["x"] = x, d["y"] = y, d["var_x"] = vx, d["var_y"] = vy, d["cov_xy"] = cxy;
  d["n_obs"] = n_obs, d["obs_x"] = ox, d["obs_y"] = oy, d["first_step"] = first;
  d["last_step"] = last;
  if (mark_candidates) {
    py::array_t<bool> cand(n);
    auto b = cand.mutable_unchecked<1>();
    for (py::ssize_t k = 0; k < n; ++k) b(k) = false;
    for (const std::size_t i : c.candidates) b(static_cast<py::ssize_t>(i)) = true;
    d["candidate"] = cand;
  }
  return d;
}

py::dict sightingColumns(const std::vector<Sighting>& s) {
  const auto n = static_cast<py::ssize_t>(s.size());
  py::array_t<std::int64_t> id(n);
  py::array_t<double> range(n), bearing(n);
  for (py::ssize_t k = 0; k < n; ++k) {
    const Sighting& x = s[static_cast<std::size_t>(k)];
    id.mutable_at(k) = x.id, range.mutable_at(k) = x.range, bearing.mutable_at(k) = x.bearing;
  }
  py::dict d;
  d["id"] = id, d["range"] = range, d["bearing"] = bearing;
  return d;
}

py::tuple poseTuple(const Pose2& p) { return py::make_tuple(p.x, p.y, p.phi); }

}  // namespace

const DropContext& DropView::ctx() const {
  if (!ctx_) throw std::runtime_error("this Drop is over: its decision has been made");
  return *ctx_;
}

py::dict DropView::candidates() {
  if (!candidates_) candidates_ = columns(ctx(), ctx().candidates, false);
  return *candidates_;
}
py::dict DropView::landmarks() {
  if (!landmarks_) {
    std::vector<std::size_t> all(ctx().landmarks.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
    landmarks_ = columns(ctx(), all, true);
  }
  return *landmarks_;
}

void definePluginViews(py::module_& m) {
  py::class_<DropView>(m, "Drop",
                       "What a plugin reducer's choose(drop) is given at one drop (docs/PYTHON.md "
                       "\"A reducer in Python\"); valid during the call only.")
      .def_property_readonly(
          "step", [](const DropView& d) { return static_cast<long long>(d.ctx().step); },
          "the step after which the drop happens")
      .def_property_readonly(
          "seed", [](const DropView& d) { return d.seed(); }, "[LandmarkBudget] seed of the run")
      .def_property_readonly(
          "backend", [](const DropView& d) { return d.ctx().backend.name(); }, "ekf or graph")
      .def_property_readonly("candidates", &DropView::candidates,
                             "the landmarks this drop may take, a dict of columns: id, x, y, "
                             "var_x, var_y, cov_xy, n_obs, obs_x, obs_y, first_step, last_step")
      .def_property_readonly("landmarks", &DropView::landmarks,
                             "every landmark of the map, the same columns plus candidate (bool)")
      .def_property_readonly(
          "robot", [](const DropView& d) { return poseTuple(d.ctx().backend.robotPose().mean); },
          "the latest robot pose (x, y, yaw) [m, m, rad]")
      .def_property_readonly(
          "robot_cov",
          [](const DropView& d) { return Eigen::Matrix3d(d.ctx().backend.robotPose().cov); },
          "its 3 x 3 marginal covariance")
      .def(
          "information_gain",
          [](const DropView& d, const std::vector<long long>& ids) {
            const std::vector<LandmarkId> l(ids.begin(), ids.end());
            const Backend& b = d.ctx().backend;
            std::vector<double> g;
            {
              py::gil_scoped_release release;
              g = b.informationGain(l);
            }
            return py::array_t<double>(static_cast<py::ssize_t>(g.size()), g.data());
          },
          py::arg("ids"), "each landmark's information gain [bits] (docs/ALGORITHMS.md \"mi\")")
      .def(
          "covariance",
          [](const DropView& d, long long id) {
            return Eigen::Matrix2d(d.ctx().backend.landmarkCovariance(static_cast<LandmarkId>(id)));
          },
          py::arg("id"), "a landmark's 2 x 2 marginal covariance [m^2]")
      .def(
          "joint_covariance",
          [](const DropView& d, const std::vector<long long>& ids) {
            std::vector<VariableKey> vars;
            for (const long long id : ids)
              vars.push_back(VariableKey::landmark(static_cast<LandmarkId>(id)));
            const Backend& b = d.ctx().backend;
            Eigen::MatrixXd c;
            {
              py::gil_scoped_release release;
              c = b.jointCovariance(vars);
            }
            return c;
          },
          py::arg("ids"), "the landmarks' joint marginal covariance (2 rows a landmark, in order)");

  py::class_<SeenView>(m, "Seen",
                       "What a plugin reducer's observe(seen) is given at every step, after the "
                       "backend's update and before the step's drops")
      .def_property_readonly("step",
                             [](const SeenView& s) { return static_cast<long long>(s.seen.step); })
      .def_property_readonly(
          "robot", [](const SeenView& s) { return poseTuple(s.seen.robot); },
          "the robot pose estimate (x, y, yaw) [m, m, rad]")
      .def_property_readonly(
          "observed",
          [](const SeenView& s) {
            std::vector<std::int64_t> ids(s.seen.observed.begin(), s.seen.observed.end());
            return py::array_t<std::int64_t>(static_cast<py::ssize_t>(ids.size()), ids.data());
          },
          "ids of the map's landmarks observed at this step, new ones too")
      .def_property_readonly(
          "sightings", [](const SeenView& s) { return sightingColumns(s.seen.sightings); },
          "the readings behind observed: columns id, range [m], bearing [rad]")
      .def_property_readonly(
          "withheld", [](const SeenView& s) { return sightingColumns(s.seen.withheld); },
          "readings of landmarks the map does not keep: columns id, range, bearing")
      .def_property_readonly(
          "sensor_pose", [](const SeenView& s) { return poseTuple(s.seen.sensor_pose); },
          "the sensor's pose on the robot (x, y, yaw)")
      .def_property_readonly(
          "sensor_max_range", [](const SeenView& s) { return s.seen.sensor_max_range; },
          "[m]; 0 when the step did not say")
      .def_property_readonly(
          "sensor_fov", [](const SeenView& s) { return s.seen.sensor_fov; },
          "total horizontal field of view [rad]; 0 when unknown");
}

}  // namespace budget_slam::python
