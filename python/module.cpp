// The compiled part of the `littoral` Python package (python/littoral/__init__.py wraps it): the
// operations of the command line on the same C++ code, with numpy arrays in and out.
//   waves(...)            surfaces::generateWaveSurface with the `waves` command's options
//   WaveSurface           its height field, mesh, statistics (JSON) and summary; write(path)
//   check_scene(path)     pipelines::checkScene (the summary `check-scene` prints)
//   run(scene, out, ...)  pipelines::runScene, as `littoral run` (one output set, a folder lock)
//   read_envi / read_exr  render::readEnvi / readExr: (bands, rows, cols) float32 and the bands
//   read_raster(path)     any image OpenImageIO reads: channels, their names, the header's attributes
// An InputError is raised as littoral.InputError with the command's message ("file:line:col: ...").
#include <filesystem>
#include <string>
#include <type_traits>
#include <vector>

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/mesh.h"
#include "core/progress.h"
#include "pipelines/lib_scene.h"
#include "pipelines/lib_sweep.h"
#include "pipelines/lib_waves.h"
#include "render/estimator_settings.h"
#include "render/image_output.h"
#include "surfaces/facetize.h"
#include "surfaces/wave_report.h"
#include "surfaces/wave_surface.h"

namespace py = pybind11;
using namespace littoral;

namespace {

std::string inputErrorText(const InputError& e) {
    const std::string loc = e.where().str();
    return loc.empty() ? e.message() : loc + ": " + e.message();
}

// A film as (bands, rows, cols) float32 with its band edges.
py::dict filmDict(const render::Film& f) {
    py::array_t<float> a({f.bandCount(), f.height, f.width});
    auto m = a.mutable_unchecked<3>();
    for (int b = 0; b < f.bandCount(); ++b)
        for (int y = 0; y < f.height; ++y)
            for (int x = 0; x < f.width; ++x) m(b, y, x) = f.at(x, y, b);
    py::list lo, hi;
    for (const Band& b : f.bands) lo.append(b.lo), hi.append(b.hi);
    py::dict d;
    d["data"] = a;
    d["band_lo_um"] = lo;
    d["band_hi_um"] = hi;
    return d;
}

// Any image OpenImageIO reads (the truth EXR, the GeoTIFF, the PSF and detector EXRs, the PNG
// previews): its channels as (channels, rows, cols) float32 (uint8 for 8-bit images), their names,
// and the string and number attributes of its header.
py::dict rasterDict(const std::string& path) {
    imageio::Reader in(path);
    if (!in.ok()) throw InputError(SourceLoc{path}, "cannot read the image: " + in.error());
    const imageio::Header spec = in.header();
    const bool bytes = spec.storedAs(imageio::PixelType::UInt8);
    const size_t n = static_cast<size_t>(spec.width) * spec.height * spec.channels;
    py::dict d;
    auto planes = [&](auto* pixels, auto arr, imageio::PixelType type) {
        std::vector<std::remove_pointer_t<decltype(pixels)>> buf(n);
        if (!in.read(spec.channels, type, buf.data()))
            throw InputError(SourceLoc{path}, "cannot read the image: " + in.error());
        auto m = arr.template mutable_unchecked<3>();
        for (int c = 0; c < spec.channels; ++c)
            for (int y = 0; y < spec.height; ++y)
                for (int x = 0; x < spec.width; ++x)
                    m(c, y, x) = buf[(static_cast<size_t>(y) * spec.width + x) * spec.channels + c];
        d["data"] = arr;
    };
    if (bytes) planes(static_cast<uint8_t*>(nullptr), py::array_t<uint8_t>({spec.channels, spec.height, spec.width}), imageio::PixelType::UInt8);
    else planes(static_cast<float*>(nullptr), py::array_t<float>({spec.channels, spec.height, spec.width}), imageio::PixelType::Float);
    d["channels"] = spec.channelNames;
    py::dict attrs;
    for (const imageio::Attribute& p : spec.attributes) {
        if (p.kind == imageio::Attribute::Kind::String) attrs[p.name.c_str()] = p.value;
        else if (p.kind == imageio::Attribute::Kind::Float) attrs[p.name.c_str()] = std::stod(p.value);
        else if (p.kind == imageio::Attribute::Kind::Int) attrs[p.name.c_str()] = std::stol(p.value);
    }
    d["attributes"] = attrs;
    return d;
}

struct PyWaveSurface {
    surfaces::WaveSurface s;
};

PyWaveSurface waves(const std::string& model, std::optional<double> wind, std::optional<double> windFrom,
                    std::optional<double> wavesFrom, std::optional<std::string> sea, double size,
                    std::optional<double> sizeY, double spacing, uint64_t seed, std::optional<long long> triangles,
                    double fetch, double gamma, double amplitude, double wavelength, double phase, double time,
                    double depth, bool progress) {
    pipelines::WavesOptions o;
    o.model = model;
    o.wind = wind;
    o.windFromDeg = windFrom;
    o.wavesFromDeg = wavesFrom;
    o.sea = sea;
    o.size = size;
    o.sizeY = sizeY;
    o.spacing = spacing;
    o.seed = seed;
    o.triangles = triangles;
    o.fetch = fetch, o.gamma = gamma, o.amplitude = amplitude, o.wavelength = wavelength, o.phase = phase;
    o.time = time, o.depth = depth;
    const surfaces::WaveParams p = pipelines::toParams(o);
    surfaces::validateWaveParams(p);
    Progress::setEnabled(progress);
    py::gil_scoped_release nogil;
    return PyWaveSurface{surfaces::generateWaveSurface(p)};
}

// The WaveSurface class: the height field, the mesh, the statistics and the mesh writer.
void bindWaveSurface(py::module_& m) {
    py::class_<PyWaveSurface>(m, "WaveSurface")
        .def_property_readonly("heights",
                               [](const PyWaveSurface& w) {
                                   const auto& f = w.s.field;
                                   py::array_t<double> a({f.ny, f.nx});
                                   std::copy(f.z.begin(), f.z.end(), a.mutable_data());
                                   return a;
                               })
        .def_property_readonly("x",
                               [](const PyWaveSurface& w) {
                                   py::array_t<double> a(w.s.field.nx);
                                   for (int i = 0; i < w.s.field.nx; ++i) a.mutable_at(i) = w.s.field.x(i);
                                   return a;
                               })
        .def_property_readonly("y",
                               [](const PyWaveSurface& w) {
                                   py::array_t<double> a(w.s.field.ny);
                                   for (int j = 0; j < w.s.field.ny; ++j) a.mutable_at(j) = w.s.field.y(j);
                                   return a;
                               })
        .def_property_readonly("vertices",
                               [](const PyWaveSurface& w) {
                                   const auto& v = w.s.mesh.positions;
                                   py::array_t<double> a({static_cast<py::ssize_t>(v.size()), py::ssize_t{3}});
                                   auto m = a.mutable_unchecked<2>();
                                   for (size_t i = 0; i < v.size(); ++i) m(i, 0) = v[i].x, m(i, 1) = v[i].y, m(i, 2) = v[i].z;
                                   return a;
                               })
        .def_property_readonly("triangles",
                               [](const PyWaveSurface& w) {
                                   const auto& t = w.s.mesh.triangles;
                                   py::array_t<uint32_t> a({static_cast<py::ssize_t>(t.size()), py::ssize_t{3}});
                                   auto m = a.mutable_unchecked<2>();
                                   for (size_t i = 0; i < t.size(); ++i)
                                       for (int k = 0; k < 3; ++k) m(i, k) = t[i][k];
                                   return a;
                               })
        .def_property_readonly("stats_json", [](const PyWaveSurface& w) { return surfaces::waveStatsJson(w.s).dump(2) + "\n"; })
        .def_property_readonly("summary", [](const PyWaveSurface& w) { return surfaces::waveSummary(w.s); })
        .def("write_mesh",
             [](const PyWaveSurface& w, const std::string& path) {
                 OutputSet set;
                 const std::filesystem::path p(path);
                 if (p.extension() == ".obj") surfaces::writeObj(p, w.s.mesh, w.s.vertexNormals);
                 else if (p.extension() == ".ply") writePly(p, w.s.mesh);
                 else throw InputError(fmt::format("'{}': unsupported extension; allowed: .ply, .obj", path));
                 set.commit();
             },
             py::arg("path"), "Write the mesh as the waves command's --out does (.ply or .obj)");
}

}  // namespace

PYBIND11_MODULE(_littoral, m) {
    m.doc() = "Littoral: coastal ocean scenes and their physically based rendering (C++ core)";
    render::registerEstimatorKinds();
    static py::exception<InputError> inputError(m, "InputError", PyExc_ValueError);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const InputError& e) {
            PyErr_SetString(inputError.ptr(), inputErrorText(e).c_str());
        } catch (const std::filesystem::filesystem_error& e) {
            PyErr_SetString(PyExc_OSError, (e.path1().string() + ": " + e.code().message()).c_str());
        }
    });

    bindWaveSurface(m);

    m.def("waves", &waves, py::arg("model") = "beaufort", py::kw_only(), py::arg("wind") = py::none(),
          py::arg("wind_from") = py::none(), py::arg("waves_from") = py::none(), py::arg("sea") = py::none(),
          py::arg("size") = 300.0, py::arg("size_y") = py::none(), py::arg("spacing") = 0.25, py::arg("seed") = 500,
          py::arg("triangles") = py::none(), py::arg("fetch") = 0.0, py::arg("gamma") = 3.3, py::arg("amplitude") = 0.5,
          py::arg("wavelength") = 2.0, py::arg("phase") = 0.0, py::arg("time") = 0.0, py::arg("depth") = 0.0,
          py::arg("progress") = false,
          "Generate a wave surface with the options of `littoral waves` (wind_from: --wind-from, ...)");
    m.def("check_scene", [](const std::string& path) { return pipelines::checkScene(path); }, py::arg("scene"),
          "Check a scene file as `littoral check-scene` does; returns its summary, raises InputError");
    m.def("run",
          [](const std::string& scene, const std::string& out, const std::string& sensor, int threads, bool progress) {
              pipelines::RunOptions o;
              o.scene = scene;
              o.out = out;
              o.sensor = sensor;
              o.threads = threads;
              o.progress = progress;
              Progress::setEnabled(progress);
              py::gil_scoped_release nogil;
              OutputSet set;  // as the command: every file published together, or none
              const OutputFolderLock lock(out);
              const std::string summary = pipelines::runScene(o);
              set.commit();
              return summary;
          },
          py::arg("scene"), py::arg("out"), py::kw_only(), py::arg("sensor") = "", py::arg("threads") = 0,
          py::arg("progress") = true, "Build and render a scene file as `littoral run SCENE --out OUT` does");
    m.def("sweep",
          [](const std::string& scene, const std::string& out, const std::vector<std::string>& vary, int threads,
             bool progress) {
              pipelines::SweepOptions o;
              o.scene = scene;
              o.out = out;
              o.vary = vary;
              o.threads = threads;
              o.progress = progress;
              Progress::setEnabled(progress);
              py::gil_scoped_release nogil;
              OutputSet set;  // as the command: each finished run is published as it ends
              const std::string summary = pipelines::runSweep(o);
              set.commit();
              return summary;
          },
          py::arg("scene"), py::arg("out"), py::arg("vary"), py::kw_only(), py::arg("threads") = 0,
          py::arg("progress") = true,
          "Run a grid of runs as `littoral sweep SCENE --vary KEY=V1,V2 ... --out OUT` does (vary: the KEY=V1,V2 strings)");
    m.def("read_envi", [](const std::string& path) { return filmDict(render::readEnvi(path)); }, py::arg("path"));
    m.def("read_exr", [](const std::string& path) { return filmDict(render::readExr(path)); }, py::arg("path"));
    m.def("read_raster", &rasterDict, py::arg("path"),
          "Any image OpenImageIO reads: {'data': (channels, rows, cols), 'channels': names, 'attributes': header}");
}
