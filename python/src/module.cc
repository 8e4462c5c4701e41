// The extension module dba._dba: the solve of `dba solve` on a file or on
// NumPy arrays, and problem reading, for the Python package dba
// (python/dba/__init__.py turns keyword options into command-line arguments
// and the results into Python objects).
//
// Both run the one solve session (session/solve_session.h): on a file as
// the command line does (RunSolve: the files checked, loaded, solved,
// written), on arrays from the problem they make. Options are parsed by
// ParseSolveArguments, so names, defaults and validation are the command
// line's. The GIL is released while reading and solving. C++ exceptions
// become Python exceptions with the same messages: dba::InputError ->
// dba.InputError (a ValueError, with .file and .line), std::invalid_argument
// -> ValueError, other errors -> RuntimeError.
#include <algorithm>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "dba/common/error.h"
#include "dba/common/memory.h"
#include "dba/common/timer.h"
#include "dba/io/read_problem.h"
#include "dba/session/solve_option_table.h"
#include "dba/session/solve_options.h"
#include "dba/session/solve_outputs.h"
#include "dba/session/solve_session.h"
#include "problem_arrays.h"

namespace py = pybind11;

namespace dba::python {
namespace {

// What solve and solve_arrays return: the JSON report (as `dba solve
// --report` writes it), the adjusted problem's arrays, and the printed text.
py::tuple Outcome(const SolveReport& report, const Problem& problem, const std::string& log) {
  return py::make_tuple(SolveReportJson(report), ProblemToArrays(problem), log);
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
  SolveResult result;
  {
    py::gil_scoped_release release;
    Communicator comm(Communicator::SingleRank{});
    result = RunSolve(options, &comm, verbose ? std::cout : log, since_call);
    if (verbose) std::cout.flush();
  }
  return Outcome(result.report, result.problem, log.str());
}

// dba.solve_arrays: the session of `dba solve` on a problem given as arrays;
// every option but the file outputs (the result is returned) and a COLMAP
// input's own.
py::tuple SolveArrays(const ProblemArrays& arrays, const std::vector<std::string>& option_args,
                      bool verbose) {
  const Timer since_call;  // the report's phases: from the call's start
  std::vector<std::string> args = {"<arrays>"};
  args.insert(args.end(), option_args.begin(), option_args.end());
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
  SolveResult result;
  {
    py::gil_scoped_release release;
    CheckSolveFiles(options);
    Communicator comm(Communicator::SingleRank{});
    std::ostream& out = verbose ? std::cout : log;
    result = SolveSession(options, &comm, out).Run(std::move(input));
    result.report.startup_seconds = startup_seconds;
    result.report.peak_memory_bytes = PeakResidentBytes();
    result.report.total_seconds = since_call.Seconds();
    PrintSolveReport(result.report, out);
    out.flush();
  }
  return Outcome(result.report, result.problem, log.str());
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
    problem = LoadSolveInput(path, UnknownsOptions{});
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
        "dba solve ARGS in this process: (report JSON, adjusted problem arrays, printed text)");
  m.def(
      "solve_arrays",
      [](const std::string& camera_model, DoubleArray cameras, DoubleArray points,
         DoubleArray observations, IndexArray camera_indices, IndexArray point_indices,
         std::optional<DoubleArray> intrinsics, std::optional<IndexArray> camera_intrinsics,
         std::optional<FlagArray> fixed_cameras, std::optional<FlagArray> fixed_intrinsics,
         std::optional<std::vector<std::string>> lens_models,
         const std::vector<std::string>& args, bool verbose, std::optional<IndexArray> frame_indices,
         std::optional<DoubleArray> rig_from_world, std::optional<DoubleArray> sensor_from_rig,
         std::optional<IndexArray> sensor_kinds) {
        ProblemArrays a;
        a.camera_model = camera_model;
        a.cameras = std::move(cameras);
        a.points = std::move(points);
        a.observations = std::move(observations);
        a.camera_indices = std::move(camera_indices);
        a.point_indices = std::move(point_indices);
        a.intrinsics = std::move(intrinsics);
        a.camera_intrinsics = std::move(camera_intrinsics);
        a.fixed_cameras = std::move(fixed_cameras);
        a.fixed_intrinsics = std::move(fixed_intrinsics);
        a.lens_models = std::move(lens_models);
        a.frame_indices = std::move(frame_indices);
        a.rig_from_world = std::move(rig_from_world);
        a.sensor_from_rig = std::move(sensor_from_rig);
        a.sensor_kinds = std::move(sensor_kinds);
        return SolveArrays(a, args, verbose);
      },
      py::arg("camera_model"), py::arg("cameras"), py::arg("points"), py::arg("observations"),
      py::arg("camera_indices"), py::arg("point_indices"), py::arg("intrinsics"),
      py::arg("camera_intrinsics"), py::arg("fixed_cameras"), py::arg("fixed_intrinsics"),
      py::arg("lens_models"), py::arg("args"), py::arg("verbose") = false,
      py::arg("frame_indices") = py::none(), py::arg("rig_from_world") = py::none(),
      py::arg("sensor_from_rig") = py::none(), py::arg("sensor_kinds") = py::none(),
      "the solve of dba solve on arrays: (report JSON, adjusted problem arrays, printed text)");
  m.def("solve_options", &SolveOptionList,
        "dba solve's options as the option table declares them (one dict per option)");
  m.def("solve_options_markdown", []() -> std::string { return dba::OptionsMarkdown(dba::SolveOptionTable(), dba::SolveOptions()); },
        "README.md's table of dba solve's options, made from the option table");
  m.def("read_problem", &Read, py::arg("path"),
        "the problem at path (BAL, .dba, COLMAP directory) as a dict of arrays");
}
