// Virtual fluoroscopy into numpy arrays.
#include <pybind11/stl.h>

#include <cmath>
#include <stdexcept>

#include "endovascular_sim/imaging/detector.h"
#include "endovascular_sim/imaging/xray_renderer.h"
#include "py_simulation.h"

namespace evsim::python {

namespace {

/// A renderer and the model it renders (it keeps a pointer to it).
struct PyXray {
  std::shared_ptr<const PyModel> owner;
  std::unique_ptr<XrayRenderer> renderer;
  long frames{0};
};

XraySpec specOf(const SceneModel& m, int pixels, py::object lao_deg, py::object cranial_deg) {
  XraySpec spec = m.xray;
  if (pixels != 0) {
    if (pixels < 8 || pixels > 4096) throw py::value_error("pixels must lie in [8, 4096]");
    spec.c_arm.pixels = pixels;
  }
  if (!lao_deg.is_none()) spec.c_arm.lao = lao_deg.cast<double>() * M_PI / 180.0;
  if (!cranial_deg.is_none()) spec.c_arm.cranial = cranial_deg.cast<double>() * M_PI / 180.0;
  const std::string why = validateCArm(spec.c_arm);
  if (!why.empty()) throw py::value_error(why);
  return spec;
}

}  // namespace

void bindImaging(py::module_& m) {
  py::class_<PyXray>(m, "XrayRenderer", "Virtual fluoroscopy of a scene (its `xray:` section)")
      .def(py::init([](std::shared_ptr<PyModel> model, int pixels, py::object lao_deg,
                       py::object cranial_deg) {
             PyXray x{model, nullptr, 0};
             x.renderer = std::make_unique<XrayRenderer>(model->get(),
                                                         specOf(model->get(), pixels, lao_deg, cranial_deg));
             return x;
           }),
           py::arg("model"), py::arg("pixels") = 0, py::arg("lao_deg") = py::none(),
           py::arg("cranial_deg") = py::none(),
           "pixels per side (0: the scene's), the C-arm's LAO and cranial angles [deg] (None: "
           "the scene's)")
      .def(
          "render",
          [](PyXray& x, const PyData& data) {
            requireCompatible(*x.owner, data);
            XrayFrame frame;
            std::vector<std::uint8_t> gray;
            {
              py::gil_scoped_release release;
              x.renderer->render(data.data, &frame);
              gray = detectorGray(frame, x.renderer->spec(), x.renderer->referenceAttenuation(),
                                  x.frames++, nullptr, &x.renderer->bodyAttenuation());
            }
            py::array_t<std::uint8_t> image({frame.height, frame.width});
            std::copy(gray.begin(), gray.end(), image.mutable_data());
            return image;
          },
          py::arg("data"), "The detector's image (height x width, uint8): devices dark on a light body")
      .def(
          "attenuation",
          [](PyXray& x, const PyData& data) {
            requireCompatible(*x.owner, data);
            XrayFrame frame;
            {
              py::gil_scoped_release release;
              x.renderer->render(data.data, &frame);
            }
            py::array_t<float> a({frame.height, frame.width});
            std::copy(frame.attenuation.begin(), frame.attenuation.end(), a.mutable_data());
            return a;
          },
          py::arg("data"), "The line integrals of attenuation per pixel (float32) [-]")
      .def(
          "inject_contrast",
          [](PyXray& x, const PyData& data, py::handle device, double duration) {
            requireCompatible(*x.owner, data);
            if (!(duration > 0.0 && duration <= 60.0))
              throw py::value_error("duration must lie in (0, 60] s");
            const int d = deviceIndex(data.model(), device);
            return x.renderer->injectContrast(data.data.devices[d].position.back(), data.data.time, duration);
          },
          py::arg("data"), py::arg("device"), py::arg("duration") = 1.0,
          "Contrast from a device's tip for `duration` [s]; the vessel segments filled")
      .def("set_c_arm",
           [](PyXray& x, double lao_deg, double cranial_deg) {
             CArmSpec c = x.renderer->spec().c_arm;
             c.lao = lao_deg * M_PI / 180.0;
             c.cranial = cranial_deg * M_PI / 180.0;
             try {
               x.renderer->setCArm(c);
             } catch (const std::invalid_argument& e) {
               throw py::value_error(e.what());
             }
           },
           py::arg("lao_deg"), py::arg("cranial_deg") = 0.0, "Turns the C-arm [deg]")
      .def(
          "project",
          [](const PyXray& x, py::array_t<double, py::array::c_style | py::array::forcecast> points) {
            if (points.ndim() != 2 || points.shape(1) != 3)
              throw py::value_error("points must be an (n x 3) array [m]");
            const XrayCamera& cam = x.renderer->camera();
            py::array_t<double> uv({points.shape(0), py::ssize_t{2}});
            auto in = points.unchecked<2>();
            auto out = uv.mutable_unchecked<2>();
            for (py::ssize_t i = 0; i < points.shape(0); ++i) {
              const Vec3 q = cam.project(Vec3(in(i, 0), in(i, 1), in(i, 2)));
              out(i, 0) = q.x();
              out(i, 1) = q.y();
            }
            return uv;
          },
          py::arg("points"),
          "Where points (n x 3) [m] fall on the detector: (n x 2) pixel coordinates (u, v)")
      .def_property_readonly("pixels", [](const PyXray& x) { return x.renderer->spec().c_arm.pixels; });
}

}  // namespace evsim::python
