// The Python module (issue 17, item 2): `import signorini`, then
//   r = signorini.run(deck, output=None, progress=None)
// with `deck` a path (str or os.PathLike) to a YAML deck, or a dict with the deck's sections
// (a relative mesh file is taken from the current directory). `output`: a directory for the
// usual files (ParaView, CSV, summary.json), or None to write nothing. `progress`: called
// after every converged increment with a dict (step, increment, time, iterations). Returns a
// Result whose attributes are numpy arrays (see the class's docstring). A bad deck raises
// signorini.InputError (a ValueError) with the same file:line:key message as the command
// line; a run that gives up returns with r.completed False and r.failure saying why.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "signorini/core/error.hpp"
#include "signorini/core/log.hpp"
#include "signorini/io/deck.hpp"
#include "signorini/io/registry.hpp"
#include "signorini/io/results_writer.hpp"
#include "signorini/solver/analysis.hpp"

namespace py = pybind11;
using namespace signorini;

namespace {

py::array_t<double> matrix(Index rows, int cols, const std::function<double(Index, int)>& f) {
  py::array_t<double> a({static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(cols)});
  auto m = a.mutable_unchecked<2>();
  for (Index i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) m(i, j) = f(i, j);
  return a;
}

template <typename T>
py::array_t<T> column(const std::vector<T>& v) {
  py::array_t<T> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

// The deck as a file: a path as it is; a dict dumped to YAML (python3-yaml) in a temporary
// file, its relative mesh path made absolute from the current directory.
std::string deck_file(const py::object& deck, std::string& temporary) {
  if (!py::isinstance<py::dict>(deck)) return py::str(py::module_::import("os").attr("fspath")(deck));
  py::dict d = py::module_::import("copy").attr("deepcopy")(deck);
  if (d.contains("mesh") && py::isinstance<py::dict>(d["mesh"])) {
    py::dict mesh = d["mesh"];
    if (mesh.contains("file"))
      mesh["file"] = py::module_::import("os.path").attr("abspath")(mesh["file"]);
  }
  const std::string text = py::str(py::module_::import("yaml").attr("safe_dump")(d, py::arg("sort_keys") = false));
  namespace fs = std::filesystem;
  static int counter = 0;
  temporary = (fs::temp_directory_path() /
               ("signorini_py_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + ".yaml"))
                  .string();
  std::ofstream(temporary) << text;
  return temporary;
}

py::object run(const py::object& deck, const py::object& output, const py::object& progress) {
  std::string temporary;
  const std::string path = deck_file(deck, temporary);
  struct Remove {
    std::string f;
    ~Remove() {
      if (!f.empty()) std::filesystem::remove(f);
    }
  } remove{temporary};
  const Registry registry = default_registry();
  std::shared_ptr<Model> model;
  try {
    model = std::make_shared<Model>(read_deck(path, registry));
  } catch (const InputError& e) {
    if (temporary.empty()) throw;
    // A dict has no file or lines: the message names the dict and keeps the key path.
    std::string what = e.what();
    const size_t p = what.find(temporary);
    if (p != std::string::npos) {
      size_t end = p + temporary.size();
      while (end < what.size() && (what[end] == ':' || std::isdigit(static_cast<unsigned char>(what[end])))) ++end;
      while (end < what.size() && what[end] == ' ') ++end;
      what.replace(p, end - p, "deck (dict): ");
    }
    throw InputError("", "", what);
  }
  auto analysis = std::make_shared<Analysis>(*model);
  std::unique_ptr<ResultsWriter> writer;
  if (!output.is_none()) {
    writer = std::make_unique<ResultsWriter>(*model, py::str(py::module_::import("os").attr("fspath")(output)));
    writer->write_initial(*analysis);
  }
  analysis->on_increment([&](const Analysis& a, const IncrementRecord& r) {
    if (writer) writer->write_increment(a, r);
    if (!progress.is_none()) {
      py::gil_scoped_acquire gil;
      py::dict info;
      info["step"] = r.step + 1;
      info["increment"] = r.increment;
      info["time"] = r.time;
      info["iterations"] = r.iterations;
      progress(info);
    }
  });
  // The GIL is released while the analysis runs (other Python threads go on); the progress
  // callback takes it back.
  AnalysisSummary s;
  {
    py::gil_scoped_release release;
    s = analysis->run();
  }
  if (writer) writer->finish(*analysis, s, evaluate_checks(*analysis));

  // The result: numpy arrays of the last converged state.
  const Mesh& mesh = model->mesh;
  const int dim = model->settings.spatial_dim();
  const DofMap& dofs = analysis->dofs();
  const VecX& u = analysis->displacement();
  py::module_ types = py::module_::import("types");
  py::object result = types.attr("SimpleNamespace")();
  result.attr("completed") = s.completed;
  result.attr("failure") = s.failure;
  result.attr("increments") = s.increments.size();
  result.attr("iterations") = s.total_iterations;
  result.attr("coordinates") = matrix(mesh.num_nodes(), dim, [&](Index n, int i) { return mesh.nodes[n](i); });
  result.attr("displacement") = matrix(mesh.num_nodes(), dim, [&](Index n, int i) {
    const Index d = dofs.dof(n, i);
    return d < 0 ? 0.0 : u(d);
  });
  // Cell stress (Cauchy, Voigt order xx, yy, zz, xy, yz, xz), body by body in model order.
  std::vector<Vec6> stress;
  for (size_t b = 0; b < model->bodies.size(); ++b) {
    if (model->bodies[b]->rigid()) continue;
    const CellResults cr = model->bodies[b]->results(mesh.nodes, u, dofs, &analysis->history(b));
    stress.insert(stress.end(), cr.stress.begin(), cr.stress.end());
  }
  result.attr("stress") = matrix(static_cast<Index>(stress.size()), 6, [&](Index c, int i) { return stress[c](i); });
  py::dict reactions;
  for (const std::string& set : analysis->reaction_sets()) {
    const Vec3 r = analysis->reaction_sum(set);
    reactions[py::str(set)] = matrix(1, dim, [&](Index, int i) { return r(i); }).attr("reshape")(dim);
  }
  result.attr("reactions") = reactions;
  py::dict contact;
  for (const auto& c : analysis->contacts()) {
    const auto st = c->slave_states();
    std::vector<long long> node;
    std::vector<double> gap, pressure, slip;
    std::vector<int> status;
    for (const auto& ns : st) {
      node.push_back(static_cast<long long>(mesh.node_ids[ns.node]));
      gap.push_back(ns.gap);
      pressure.push_back(ns.pressure);
      status.push_back(ns.status);
      slip.push_back(ns.slip_accumulated);
    }
    py::object pair = types.attr("SimpleNamespace")();
    pair.attr("node") = column(node);
    pair.attr("gap") = column(gap);
    pair.attr("pressure") = column(pressure);
    pair.attr("status") = column(status);
    pair.attr("traction") =
        matrix(static_cast<Index>(st.size()), dim, [&](Index k, int i) { return st[static_cast<size_t>(k)].traction(i); });
    pair.attr("slip") = column(slip);
    const Vec3 f = c->slave_force();
    pair.attr("force") = matrix(1, dim, [&](Index, int i) { return f(i); }).attr("reshape")(dim);
    contact[py::str(c->label())] = pair;
  }
  result.attr("contact") = contact;
  return result;
}

}  // namespace

PYBIND11_MODULE(signorini, m) {
  m.doc() = "Signorini: finite element solver for contact mechanics";
  static py::exception<InputError> input_error(m, "InputError", PyExc_ValueError);
  static py::exception<SolverError> solver_error(m, "SolverError", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      input_error(e.what());
    } catch (const SolverError& e) {
      solver_error(e.what());
    }
  });
  m.def("run", &run, py::arg("deck"), py::arg("output") = py::none(), py::arg("progress") = py::none(),
        R"(Solve a deck and return the last converged state.

deck: a path to a YAML deck, or a dict of its sections (a relative mesh file is read from the
current directory). output: a directory for ParaView files, CSVs and summary.json, or None.
progress: called after each converged increment with {step, increment, time, iterations}.

The result has: completed (bool), failure (why a run gave up), increments, iterations,
coordinates and displacement (nodes x dim, mesh node order), stress (cells x 6, Cauchy,
xx yy zz xy yz xz, deformable bodies in deck order), reactions {node set: force}, and
contact {pair: node (mesh ids), gap, pressure, status (0 far, 1 open, 2 closed/stick,
3 slip), traction (nodes x dim, friction), slip (accumulated), force (the total contact
force on the slave side)}.
Raises signorini.InputError (a ValueError) for a bad deck, with file:line:key.)");
  m.def(
      "set_log_level", [](const std::string& level) {
        log::set_level(level == "debug" ? log::Level::debug : level == "warning" ? log::Level::warning
                                                                                 : log::Level::info);
      },
      py::arg("level"), "info (default), warning or debug");
}
