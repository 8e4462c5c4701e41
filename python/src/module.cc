// The extension module dba._dba: the solve of `dba solve` on a file or on
// NumPy arrays, and problem reading, for the Python package dba
// (python/dba/__init__.py turns keyword options into command-line arguments
// and the results into Python objects).
//
// Both run the one solve session (session/solve_session.h): on a file as
// the command line does (RunSolve: the files checked, loaded, solved,
// written), on arrays from the problem they make. Options are parsed by
// ParseSolveArguments, so names, defaults and validation are the command
// line's. The GIL is released while reading and solving; Ctrl-C stops a
// solve (KeyboardInterrupt, nothing written: PythonSignals). C++ exceptions
// become Python exceptions with the same messages: dba::InputError ->
// dba.InputError (a ValueError, with .file and .line), std::invalid_argument
// -> ValueError, other errors -> RuntimeError.
#include <algorithm>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "dba/common/error.h"
#include "dba/common/interrupt.h"
#include "dba/common/memory.h"
#include "dba/common/timer.h"
#include "dba/io/read_problem.h"
#include "dba/precision/covariance_csv.h"
#include "dba/session/solve_option_table.h"
#include "dba/session/solve_options.h"
#include "dba/session/solve_outputs.h"
#include "dba/session/solve_session.h"
#include "problem_arrays.h"

namespace py = pybind11;

namespace dba::python {
namespace {

// The covariance as the files hold it (README.md, Precision), as arrays:
// None without one; else "pose" (images × 6 × 6, NaN where "state" says
// held or undetermined), "state" and, with points, "points" (× 3 × 3, NaN
// where undetermined) and "point_index" (each one's index in the input).
py::object CovarianceArrays(const SolveResult& result) {
  if (!result.covariance) return py::none();
  const CameraCovariances& c = *result.covariance;
  const double scale = result.report.covariance.Scale();
  const py::ssize_t n = static_cast<py::ssize_t>(c.pose.size());
  py::array_t<double> pose({n, py::ssize_t{6}, py::ssize_t{6}});
  py::list state;
  for (py::ssize_t i = 0; i < n; ++i) {
    Eigen::Map<Eigen::Matrix<double, 6, 6, Eigen::RowMajor>> out(pose.mutable_data(i));
    state.append(PoseState(c, static_cast<size_t>(i)));
    out = c.pose[i] ? PoseInOutputFrame(*c.pose[i], result.gauge_moved, scale)
                    : PoseCovariance::Constant(std::numeric_limits<double>::quiet_NaN());
  }
  py::dict d;
  d["pose"] = pose, d["state"] = state;
  if (result.point_covariance.empty()) return d;
  const std::vector<int64_t> loaded = LoadedPointIndices(result);
  const py::ssize_t m = static_cast<py::ssize_t>(std::min(loaded.size(), result.point_covariance.size()));
  py::array_t<double> points({m, py::ssize_t{3}, py::ssize_t{3}});
  py::array_t<int64_t> index(m);
  for (py::ssize_t k = 0; k < m; ++k) {
    Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(points.mutable_data(k)) =
        PointInOutputFrame(result.point_covariance[k], result.gauge_moved, scale);
    index.mutable_at(k) = loaded[k];
  }
  d["points"] = points, d["point_index"] = index;
  return d;
}

// What solve and solve_arrays return: the JSON report (as `dba solve
// --report` writes it), the adjusted problem's arrays, the printed text and
// the covariance's arrays (CovarianceArrays).
py::tuple Outcome(const SolveResult& result, const std::string& log) {
  return py::make_tuple(SolveReportJson(result.report), ProblemToArrays(result.problem), log,
                        CovarianceArrays(result));
}

// Ctrl-C during a solve (common/interrupt.h): the solve polls on this
// thread, and at most every 50 ms a poll takes the GIL and runs Python's
// signal handlers (PyErr_CheckSignals; they run in the main thread only). A
// handler's exception (KeyboardInterrupt) is kept, the solve unwound by
// Interrupted before it writes anything, and the exception raised again
// once the GIL is back.
class PythonSignals {
 public:
  struct Interrupted {};
  void Poll() {
    if (since_.Seconds() < 0.05) return;
    since_.Reset();
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() == 0) return;
    PyErr_Fetch(&type_, &value_, &trace_);
    throw Interrupted();
  }
  // With the GIL: the kept exception, raised.
  [[noreturn]] void Raise() {
    PyErr_Restore(type_, value_, trace_);
    throw py::error_already_set();
  }

 private:
  Timer since_;
  PyObject *type_ = nullptr, *value_ = nullptr, *trace_ = nullptr;
};

// `solve()` with the GIL released, stopped by a Python signal handler's
// exception (PythonSignals).
template <class Solve>
SolveResult Interruptible(const Solve& solve) {
  PythonSignals signals;
  try {
    py::gil_scoped_release release;
    const InterruptCheck check([&] { signals.Poll(); });
    return solve();
  } catch (const PythonSignals::Interrupted&) {
    signals.Raise();
  }
}

SolveOptions Parse(const std::vector<std::string>& args) {
  bool help = false;
  SolveOptions options = ParseSolveArguments(args, &help);
  if (help) throw std::invalid_argument("help: see help(dba.solve) and `dba solve --help`");
  return options;
}

// dba.solve: the whole of `dba solve ARGS` in this process (one rank), its
// outputs (-o, --report, --ply) included.
py::tuple Solve(const std::vector<std::string>& args, bool verbose) {
  const Timer since_call;  // the report's phases: from the call's start
  SolveOptions options = Parse(args);
  options.progress = verbose;  // the terminal's progress line only when printing the log
  std::ostringstream log;
  const SolveResult result = Interruptible([&] {
    Communicator comm(Communicator::SingleRank{});
    SolveResult r = RunSolve(options, &comm, verbose ? std::cout : log, since_call);
    if (verbose) std::cout.flush();
    return r;
  });
  return Outcome(result, log.str());
}

// dba.solve_arrays: the session of `dba solve` on a problem given as arrays;
// every option but the file outputs (the result is returned) and a COLMAP
// input's own.
py::tuple SolveArrays(const ProblemArrays& arrays, const std::vector<std::string>& option_args,
                      bool verbose, int covariance) {
  const Timer since_call;  // the report's phases: from the call's start
  std::vector<std::string> args = {"<arrays>"};
  args.insert(args.end(), option_args.begin(), option_args.end());
  // covariance=True (2: and points): computed and returned, not written
  // (no file outputs here: the names are placeholders, never checked).
  if (covariance > 0) args.insert(args.end(), {"--covariance", "<arrays>"});
  if (covariance > 1) args.insert(args.end(), {"--point-covariance", "<arrays: points>"});
  SolveOptions options = Parse(args);
  options.progress = verbose;
  // What solve_arrays has no place for (the file outputs, a COLMAP input's
  // and the ranks' options), by the option table.
  for (const std::string& a : option_args) {
    for (const OptionSpec<SolveOptions>& spec : SolveOptionTable()) {
      if ((a == spec.name || a == spec.alias) && !(spec.modes & kModePythonArrays)) {
        throw std::invalid_argument(PythonKeyword(spec.name) + ": " + spec.not_here);
      }
    }
  }
  const double startup_seconds = since_call.Seconds();
  const Timer read;
  SolveInput input;
  input.name = "<arrays>";
  input.problem = ProblemFromArrays(arrays);
  ApplyFixings(options.unknowns, &input.problem);  // fix_images, fix_intrinsics
  input.read_seconds = read.Seconds();
  std::ostringstream log;
  const SolveResult result = Interruptible([&] {
    SolveOptions checked = options;
    checked.covariance_path.clear(), checked.point_covariance_path.clear();
    CheckSolveFiles(checked, InputSource());  // arrays: no input file
    Communicator comm(Communicator::SingleRank{});
    std::ostream& out = verbose ? std::cout : log;
    SolveResult r = SolveSession(options, &comm, out).Run(std::move(input));
    r.report.startup_seconds = startup_seconds;
    r.report.peak_memory_bytes = PeakResidentBytes();
    r.report.total_seconds = since_call.Seconds();
    PrintSolveReport(r.report, out);
    out.flush();
    return r;
  });
  // No outputs to keep here: a covariance that failed after the solve is
  // said, and the solve returned without it.
  if (!result.covariance_error.empty()) {
    py::module_::import("warnings").attr("warn")(result.covariance_error, py::module_::import("builtins").attr("RuntimeWarning"));
  }
  return Outcome(result, log.str());
}

// An optional argument of solve_arrays: None, or the array `as` makes of it.
template <class Array>
std::optional<Array> Optional(const py::object& value, const char* name,
                              Array (*as)(const py::handle&, const char*)) {
  if (value.is_none()) return std::nullopt;
  return as(value, name);
}

// The option table (session/solve_option_table.h) for the Python keywords:
// per option its keyword, flag, kind, choices, range, whether it repeats,
// where it applies and why not elsewhere, what it needs.
py::list SolveOptionList() {
  py::list out;
  for (const OptionSpec<SolveOptions>& s : SolveOptionTable()) {
    py::dict d;
    d["keyword"] = PythonKeyword(s.name);
    d["flag"] = s.name;
    d["kind"] = OptionKindName(s.kind);
    d["choices"] = s.choices;
    d["min"] = s.min;
    d["max"] = s.max;
    d["repeatable"] = s.repeatable;
    d["file"] = (s.modes & kModePythonFile) != 0;
    d["arrays"] = (s.modes & kModePythonArrays) != 0;
    d["not_here"] = s.not_here;
    d["needs"] = s.needs;
    d["help"] = s.help;
    out.append(d);
  }
  return out;
}

// The Python class dba.InputError; leaked on purpose: it must outlive every
// translation, and a static py::object would be destroyed after the
// interpreter.
py::exception<dba::InputError>* input_error = nullptr;

void TranslateInputError(std::exception_ptr p) {
  try {
    if (p) std::rethrow_exception(p);
  } catch (const dba::InputError& e) {
    py::object error = py::handle(input_error->ptr())(e.what());
    error.attr("file") = e.file();
    error.attr("line") = e.line();
    PyErr_SetObject(input_error->ptr(), error.ptr());
  }
}

py::dict Read(const std::string& path) {
  Problem problem;
  {
    py::gil_scoped_release release;
    problem = ReadInputProblem(DecideInput(path), DefaultFixings());
  }
  return ProblemToArrays(problem);
}

}  // namespace
}  // namespace dba::python

PYBIND11_MODULE(_dba, m) {
  using namespace dba::python;
  m.doc() = "dba's bundle adjuster (use the package dba, not this module)";
  input_error = new py::exception<dba::InputError>(m, "InputError", PyExc_ValueError);
  input_error->attr("__doc__") =
      "Malformed input: the message names the file and the line (attributes file, line; "
      "line 0 when the error is not at a line)";
  py::register_exception_translator(&TranslateInputError);

  m.def("solve", &Solve, py::arg("args"), py::arg("verbose") = false,
        "dba solve ARGS in this process: (report JSON, adjusted problem arrays, printed text, "
        "covariance arrays or None)");
  m.def(
      "solve_arrays",
      [](const std::string& camera_model, py::object cameras, py::object points,
         py::object observations, py::object camera_indices, py::object point_indices,
         py::object intrinsics, py::object camera_intrinsics, py::object fixed_cameras,
         py::object fixed_intrinsics, std::optional<std::vector<std::string>> lens_models,
         const std::vector<std::string>& args, bool verbose, py::object frame_indices,
         py::object rig_from_world, py::object sensor_from_rig, py::object sensor_kinds, int covariance) {
        ProblemArrays a;
        a.camera_model = camera_model;
        a.cameras = AsDoubleArray(cameras, "cameras");
        a.points = AsDoubleArray(points, "points");
        a.observations = AsDoubleArray(observations, "observations");
        a.camera_indices = AsIndexArray(camera_indices, "camera_indices");
        a.point_indices = AsIndexArray(point_indices, "point_indices");
        a.intrinsics = Optional(intrinsics, "intrinsics", AsDoubleArray);
        a.camera_intrinsics = Optional(camera_intrinsics, "camera_intrinsics", AsIndexArray);
        a.fixed_cameras = Optional(fixed_cameras, "fixed_cameras", AsFlagArray);
        a.fixed_intrinsics = Optional(fixed_intrinsics, "fixed_intrinsics", AsFlagArray);
        a.lens_models = std::move(lens_models);
        a.frame_indices = Optional(frame_indices, "frame_indices", AsIndexArray);
        a.rig_from_world = Optional(rig_from_world, "rig_from_world", AsDoubleArray);
        a.sensor_from_rig = Optional(sensor_from_rig, "sensor_from_rig", AsDoubleArray);
        a.sensor_kinds = Optional(sensor_kinds, "sensor_kinds", AsIndexArray);
        return SolveArrays(a, args, verbose, covariance);
      },
      py::arg("camera_model"), py::arg("cameras"), py::arg("points"), py::arg("observations"),
      py::arg("camera_indices"), py::arg("point_indices"), py::arg("intrinsics"),
      py::arg("camera_intrinsics"), py::arg("fixed_cameras"), py::arg("fixed_intrinsics"),
      py::arg("lens_models"), py::arg("args"), py::arg("verbose") = false,
      py::arg("frame_indices") = py::none(), py::arg("rig_from_world") = py::none(),
      py::arg("sensor_from_rig") = py::none(), py::arg("sensor_kinds") = py::none(),
      py::arg("covariance") = 0,
      "the solve of dba solve on arrays: (report JSON, adjusted problem arrays, printed text, "
      "covariance arrays or None); covariance 1: the images', 2: and the points'");
  m.def("solve_options", &SolveOptionList,
        "dba solve's options as the option table declares them (one dict per option)");
  m.def("solve_options_markdown", []() -> std::string { return dba::OptionsMarkdown(dba::SolveOptionTable(), dba::SolveOptions()); },
        "README.md's table of dba solve's options, made from the option table");
  m.def("read_problem", &Read, py::arg("path"),
        "the problem at path (BAL, .dba, COLMAP directory) as a dict of arrays");
}
