#include "signorini/io/results_writer.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <limits>

#include "signorini/core/error.hpp"
#include "signorini/core/log.hpp"
#include "signorini/io/atomic_file.hpp"
#include "signorini/io/vtu_writer.hpp"

namespace signorini {

namespace {

std::string json_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '"': o += "\\\""; break;
      case '\\': o += "\\\\"; break;
      case '\n': o += "\\n"; break;
      case '\t': o += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) o += fmt::format("\\u{:04x}", c);
        else o += c;
    }
  }
  return o;
}

std::string json_number(Real v) {
  if (!std::isfinite(v)) return "null";
  return fmt::format("{:.10g}", v);
}

}  // namespace

std::vector<CheckResult> evaluate_checks(const Analysis& a) {
  std::vector<CheckResult> out;
  const Model& m = a.model();
  for (const Check& c : m.checks) {
    CheckResult r{c};
    if (c.kind == "displacement") {
      Index best = -1;
      Real bd = std::numeric_limits<Real>::max();
      for (Index n = 0; n < m.mesh.num_nodes(); ++n) {
        if (!a.dofs().has_dofs(n)) continue;
        Real d = (m.mesh.nodes[n] - c.point).norm();
        if (d < bd) bd = d, best = n;
      }
      r.computed = best >= 0 ? a.displacement()(a.dofs().dof(best, c.component)) : 0;
    } else {
      r.computed = a.reaction_sum(c.set)(c.component);
    }
    r.error = c.expected != 0 ? std::abs(r.computed - c.expected) / std::abs(c.expected)
                              : std::abs(r.computed - c.expected);
    r.pass = r.error <= c.tolerance;
    out.push_back(r);
  }
  return out;
}

ResultsWriter::ResultsWriter(const Model& model, std::string directory) : model_(model), dir_(std::move(directory)) {
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) throw Error("cannot create the output directory '" + dir_ + "': " + ec.message());
  // Old VTU files of a previous run would mix with this one's in ParaView.
  for (auto& e : std::filesystem::directory_iterator(dir_))
    if (e.path().extension() == ".vtu" && e.path().filename().string().rfind("increment_", 0) == 0)
      std::filesystem::remove(e.path(), ec);
  csv_ = "step,increment,time,fraction,set,fx,fy,fz\n";
}

void ResultsWriter::write_vtu(const Analysis& a, Real time, int step, int inc) {
  const Model& m = model_;
  const DofMap& dofs = a.dofs();
  const int dim = dofs.dofs_per_node();
  VtuData d;
  d.points = &m.mesh.nodes;
  VtuField disp{"displacement", 3, std::vector<Real>(3 * m.mesh.num_nodes(), 0.0), {}};
  VtuField reac{"reaction_force", 3, std::vector<Real>(3 * m.mesh.num_nodes(), 0.0), {}};
  for (Index n = 0; n < m.mesh.num_nodes(); ++n)
    for (int i = 0; i < dim; ++i) {
      const Index k = dofs.dof(n, i);
      if (k < 0) continue;
      disp.values[3 * n + i] = a.displacement()(k);
      reac.values[3 * n + i] = a.reactions()(k);
    }
  d.point_fields = {disp, reac};
  // ParaView's symmetric tensor order: XX, YY, ZZ, XY, YZ, XZ (ours: 11 22 33 23 13 12).
  const int order[6] = {0, 1, 2, 5, 3, 4};
  const std::vector<std::string> names{"XX", "YY", "ZZ", "XY", "YZ", "XZ"};
  VtuField stress{"stress", 6, {}, names}, strain{"strain", 6, {}, names}, vm{"von_mises", 1, {}, {}},
      body{"body", 1, {}, {}};
  for (size_t bi = 0; bi < m.bodies.size(); ++bi) {
    const Body& b = *m.bodies[bi];
    CellResults r = b.results(m.mesh.nodes, a.displacement(), dofs);
    for (size_t e = 0; e < r.stress.size(); ++e) {
      for (int k = 0; k < 6; ++k) {
        stress.values.push_back(r.stress[e](order[k]));
        strain.values.push_back(r.strain[e](order[k]));
      }
      vm.values.push_back(r.von_mises[e]);
      body.values.push_back(static_cast<Real>(bi));
    }
    for (auto& blk : b.blocks()) d.cells.push_back(&blk);
  }
  d.cell_fields = {stress, strain, vm, body};
  const std::string name = fmt::format("increment_{:02d}_{:04d}.vtu", step + 1, inc);
  write_file_atomically(dir_ + "/" + name, vtu_text(d));
  pvd_.emplace_back(time, name);
  write_file_atomically(pvd_path(), pvd_text(pvd_));
}

void ResultsWriter::write_initial(const Analysis& a) {
  write_file_atomically(dir_ + "/reactions.csv", csv_);
  if (model_.output.vtu != "none") write_vtu(a, 0.0, -1, 0);
  write_json(a, a.summary(), "running", {});
}

void ResultsWriter::write_increment(const Analysis& a, const IncrementRecord& rec) {
  for (auto& set : a.reaction_sets()) {
    Vec3 r = a.reaction_sum(set);
    csv_ += fmt::format("{},{},{:.10g},{:.10g},{},{:.10e},{:.10e},{:.10e}\n", rec.step + 1, rec.increment, rec.time,
                        rec.fraction, set, r(0), r(1), r(2));
  }
  write_file_atomically(dir_ + "/reactions.csv", csv_);
  const bool step_end = rec.fraction >= 1.0;
  if (model_.output.vtu == "every_increment" || (model_.output.vtu == "last" && step_end))
    write_vtu(a, rec.time, rec.step, rec.increment);
  last_record_ = rec;
  have_last_ = true;
  write_json(a, a.summary(), "running", {});
}

void ResultsWriter::finish(const Analysis& a, const AnalysisSummary& s, const std::vector<CheckResult>& checks) {
  // With vtu: last, a failed run still leaves its last converged state on disk.
  if (!s.completed && model_.output.vtu == "last" && have_last_ && last_record_.fraction < 1.0)
    write_vtu(a, last_record_.time, last_record_.step, last_record_.increment);
  write_json(a, s, s.completed ? "completed" : "failed", checks);
}

void ResultsWriter::write_json(const Analysis& a, const AnalysisSummary& s, const std::string& status,
                               const std::vector<CheckResult>& checks) {
  const Model& m = model_;
  std::string j = "{\n";
  j += fmt::format("  \"title\": \"{}\",\n  \"deck\": \"{}\",\n  \"status\": \"{}\",\n", json_escape(m.title),
                   json_escape(m.deck_path), status);
  j += fmt::format("  \"failure\": {},\n", s.failure.empty() ? "null" : "\"" + json_escape(s.failure) + "\"");
  j += fmt::format("  \"analysis\": {{\"dimension\": \"{}\", \"kinematics\": \"{}\"}},\n",
                   to_string(m.settings.dimension), m.settings.finite_strain ? "finite_strain" : "small_strain");
  j += fmt::format("  \"nodes\": {},\n  \"cells\": {},\n  \"dofs\": {},\n", m.mesh.num_nodes(), m.mesh.num_cells(),
                   a.dofs().num_dofs());
  j += fmt::format("  \"total_iterations\": {},\n", s.total_iterations);
  j += fmt::format("  \"timings\": {{\"assembly_s\": {}, \"linear_solve_s\": {}, \"total_s\": {}}},\n",
                   json_number(s.assembly_seconds), json_number(s.solve_seconds), json_number(log::elapsed()));
  j += fmt::format("  \"peak_memory_mib\": {},\n", json_number(log::peak_memory_mib()));
  j += "  \"increments\": [";
  for (size_t i = 0; i < s.increments.size(); ++i) {
    const auto& r = s.increments[i];
    j += fmt::format("{}\n    {{\"step\": {}, \"increment\": {}, \"time\": {}, \"iterations\": {}, \"cutbacks\": {}, "
                     "\"seconds\": {}, \"linear_solver\": \"{}\", \"residuals\": [",
                     i ? "," : "", r.step + 1, r.increment, json_number(r.time), r.iterations, r.cutbacks,
                     json_number(r.seconds), r.linear_solver);
    for (size_t k = 0; k < r.residuals.size(); ++k) j += (k ? ", " : "") + json_number(r.residuals[k]);
    j += "]}";
  }
  j += "\n  ],\n  \"checks\": [";
  for (size_t i = 0; i < checks.size(); ++i) {
    const auto& c = checks[i];
    j += fmt::format("{}\n    {{\"name\": \"{}\", \"computed\": {}, \"expected\": {}, \"error\": {}, \"tolerance\": {}, "
                     "\"pass\": {}, \"reference\": \"{}\"}}",
                     i ? "," : "", json_escape(c.check.name), json_number(c.computed), json_number(c.check.expected),
                     json_number(c.error), json_number(c.check.tolerance), c.pass ? "true" : "false",
                     json_escape(c.check.reference));
  }
  j += "\n  ]\n}\n";
  write_file_atomically(dir_ + "/summary.json", j);
}

}  // namespace signorini
