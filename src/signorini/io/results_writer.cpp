#include "signorini/io/results_writer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
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

bool more_engaged(const ContactInterface::SlaveState& a, const ContactInterface::SlaveState& b) {
  auto level = [](int status) { return std::min(status, static_cast<int>(ContactInterface::closed)); };
  if (level(a.status) != level(b.status)) return level(a.status) > level(b.status);
  if (level(a.status) == ContactInterface::closed) return a.pressure > b.pressure;
  return a.status == ContactInterface::open && a.gap < b.gap;
}

Real separating_radius(std::vector<std::pair<Real, bool>> pts) {
  std::sort(pts.begin(), pts.end());
  Index wrong = 0;  // threshold below every point: every inside point is on the wrong side
  for (auto& p : pts) wrong += p.second;
  if (wrong == 0) return 0;
  Index best = wrong;
  Real sum = 0;
  int count = 0;
  for (size_t k = 0; k < pts.size(); ++k) {
    wrong += pts[k].second ? -1 : 1;  // the threshold passes point k
    if (k + 1 < pts.size() && pts[k + 1].first == pts[k].first) continue;
    const Real t = k + 1 < pts.size() ? 0.5 * (pts[k].first + pts[k + 1].first) : pts[k].first;
    if (wrong < best) best = wrong, sum = 0, count = 0;
    if (wrong == best) sum += t, ++count;
  }
  return count ? sum / count : 0;
}

namespace {

// Radius of a contact zone (closed nodes, or the sticking ones among the closed) around
// `at` in 3D, in the plane normal to the pressure-weighted mean normal, separating the
// zone's nodes from the others (separating_radius). On an unstructured surface this uses
// every node around the rim, where a distance along one axis would hang on the one node
// nearest that axis.
template <class Inside>
Real zone_radius(const ConstraintSet& cs, const EnforcementOutput& st, const std::vector<Vec3>& x, const Vec3& at,
                 bool stick, Inside inside) {
  Vec3 n = Vec3::Zero();
  for (size_t j = 0; j < cs.size(); ++j)
    if (cs[j].kind != ConstraintKind::none && st.active[j]) n += st.pressure[j] * cs[j].weight * cs[j].normal;
  if (n.norm() == 0) return 0;
  n.normalize();
  std::vector<std::pair<Real, bool>> pts;
  for (size_t j = 0; j < cs.size(); ++j) {
    if (stick && !st.active[j]) continue;  // the stick zone is measured among the closed nodes
    Vec3 d = x[cs[j].slave] - at;
    d -= n * n.dot(d);
    pts.push_back({d.norm(), inside(j)});
  }
  return separating_radius(std::move(pts));
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
    } else if (c.kind == "reaction") {
      r.computed = a.reaction_sum(c.set)(c.component);
    } else {
      const ContactInterface* ci = nullptr;
      for (auto& x : a.contacts())
        if (!ci && x->settings().name == c.pair) ci = x.get();
      const auto& cs = ci->constraints();
      const auto& st = ci->state();
      const std::vector<Vec3> x = a.positions(a.displacement());
      if (c.kind == "contact_pressure_max" || c.kind == "contact_pressure") {
        // The reported nodal pressures, as written to the results (for mortar and two passes
        // they differ from the enforcement's multipliers, ContactInterface::set_reported_pressure).
        Real bd = std::numeric_limits<Real>::max();
        for (const ContactInterface::SlaveState& ns : ci->slave_states()) {
          if (c.kind == "contact_pressure_max") {
            r.computed = std::max(r.computed, ns.pressure);
            continue;
          }
          const Real d = (m.mesh.nodes[ns.node] - c.point).norm();
          if (d < bd) bd = d, r.computed = ns.pressure;
        }
      } else if (c.kind == "contact_force") {
        r.computed = ci->slave_force()(c.component);
      } else if (st.active.size() < cs.size()) {
        // No contact state yet: the run stopped after the search but before the pair's first
        // evaluation (a FatalModelError from the first assembly, e.g. the MPI owners' sums
        // check; that crashed `signorini run` here). No zone to measure: the check fails.
        r.computed = std::numeric_limits<Real>::quiet_NaN();
      } else {
        // Half-width: on each side of `at`, midway between the outermost closed node and the
        // nearest open one beyond (stick zone: the outermost sticking node and the nearest
        // closed node beyond that slips); the mean of the two sides when the zone spans both (a
        // zone shifted by the discretization), else the larger (half models).
        const bool stick = c.kind == "contact_stick_half_width";
        auto inside = [&](size_t j) {
          return stick ? st.active[j] && j < st.slip.size() && !st.slip[j] && cs[j].has_slip : st.active[j] != 0;
        };
        auto edge = [&](Real side) {
          Real closed = 0, open = std::numeric_limits<Real>::infinity();
          for (size_t j = 0; j < cs.size(); ++j) {
            const Real d = side * (x[cs[j].slave](c.component) - c.point(c.component));
            if (d >= 0 && inside(j)) closed = std::max(closed, d);
          }
          for (size_t j = 0; j < cs.size(); ++j) {
            const Real d = side * (x[cs[j].slave](c.component) - c.point(c.component));
            if (!inside(j) && (!stick || st.active[j]) && d > closed) open = std::min(open, d);
          }
          return std::isfinite(open) ? 0.5 * (closed + open) : closed;
        };
        if (c.component == Check::radial) {
          r.computed = zone_radius(cs, st, x, c.point, stick, inside);
        } else {
          // A half model (symmetry at `at`) has the zone on one side only: a node on the axis
          // gives the other side an edge near 0.
          const Real ep = edge(1), em = edge(-1);
          r.computed = std::min(ep, em) > 0.5 * std::max(ep, em) ? 0.5 * (ep + em) : std::max(ep, em);
        }
      }
    }
    r.error = c.expected != 0 ? std::abs(r.computed - c.expected) / std::abs(c.expected)
                              : std::abs(r.computed - c.expected);
    r.pass = r.error <= c.tolerance;
    out.push_back(r);
  }
  return out;
}

ResultsWriter::ResultsWriter(const Model& model, std::string directory, int rank)
    : model_(model), dir_(std::move(directory)), shared_(rank == 0) {
  if (!shared_) return;
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) throw Error("cannot create the output directory '" + dir_ + "': " + ec.message());
  // Old VTU files of a previous run would mix with this one's in ParaView.
  for (auto& e : std::filesystem::directory_iterator(dir_))
    if (((e.path().extension() == ".vtu" || e.path().extension() == ".pvtu") &&
         e.path().filename().string().rfind("increment_", 0) == 0) ||
        ((e.path().extension() == ".csv" || e.path().extension() == ".vtu" || e.path().extension() == ".pvd") &&
         e.path().filename().string().rfind("contact_", 0) == 0))
      std::filesystem::remove(e.path(), ec);
  csv_ = "step,increment,time,fraction,set,fx,fy,fz\n";
}

void ResultsWriter::write_vtu(const Analysis& a, Real time, int step, int inc) {
  const Model& m = model_;
  // Under mpirun with the cells shared out, each rank evaluates and writes the piece of its
  // own cells, and rank 0 a .pvtu that joins the pieces; otherwise rank 0 writes one .vtu.
  const bool pieces = a.ranks() > 1 && a.owned_cells(0) != nullptr;
  if (!pieces && !shared_) return;
  const DofMap& dofs = a.dofs();
  const int dim = dofs.dofs_per_node();
  VtuData d;
  d.points = &m.mesh.nodes;
  VtuField disp{"displacement", 3, std::vector<Real>(3 * m.mesh.num_nodes(), 0.0), {}};
  VtuField reac{"reaction_force", 3, std::vector<Real>(3 * m.mesh.num_nodes(), 0.0), {}};
  // A turning rigid body's nodes are not at their DOFs' translation alone: their displacement
  // is the current position less the reference one (the others' is their DOFs', exactly).
  const std::vector<Vec3> xcur = a.turning_bodies().empty() ? std::vector<Vec3>() : a.positions(a.displacement());
  for (Index n = 0; n < m.mesh.num_nodes(); ++n)
    for (int i = 0; i < dim; ++i) {
      const Index k = dofs.dof(n, i);
      if (k < 0) continue;
      disp.values[3 * n + i] = a.node_turns(n) ? xcur[n](i) - m.mesh.nodes[n](i) : a.displacement()(k);
      reac.values[3 * n + i] = a.reactions()(k);
    }
  // The ids the mesh file gives the nodes and cells (Gmsh tags), for finding them in ParaView.
  VtuField node_id{"node_id", 1, std::vector<Real>(m.mesh.num_nodes(), 0.0), {}};
  for (Index n = 0; n < m.mesh.num_nodes(); ++n) node_id.values[n] = static_cast<Real>(m.mesh.node_ids[n]);
  // Moved, not copied: at 1.4M DOFs each whole-mesh field is tens of MB.
  d.point_fields.push_back(std::move(disp));
  d.point_fields.push_back(std::move(reac));
  d.point_fields.push_back(std::move(node_id));
  if (!a.contacts().empty()) {
    // Contact state on the slave nodes (status: -1 not a slave node, 0 no master within
    // reach, 1 open, 2 closed); pressure positive in compression; the gap NaN where it has no
    // value (not a slave node, or no master within reach: until session 69 written as 0, a
    // touching node's gap, where the CSV and the Python module said nan). A slave node of several
    // pairs: the pair where it is most engaged (more_engaged; until session 69 the last pair's,
    // which hid a node closed on the first plate of examples/tube_crush behind the second's
    // "far").
    const Real none = std::numeric_limits<Real>::quiet_NaN();
    VtuField gap{"contact_gap", 1, std::vector<Real>(m.mesh.num_nodes(), none), {}};
    VtuField pres{"contact_pressure", 1, std::vector<Real>(m.mesh.num_nodes(), 0.0), {}};
    VtuField status{"contact_status", 1, std::vector<Real>(m.mesh.num_nodes(), -1.0), {}};
    for (auto& c : a.contacts())
      for (const auto& ns : c->slave_states()) {
        const Index n = ns.node;
        const ContactInterface::SlaveState shown{n, static_cast<int>(status.values[n]), gap.values[n], pres.values[n]};
        if (shown.status >= 0 && !more_engaged(ns, shown)) continue;
        gap.values[n] = ns.status ? ns.gap : none;
        pres.values[n] = ns.pressure;
        status.values[n] = ns.status;
      }
    d.point_fields.push_back(std::move(gap));
    d.point_fields.push_back(std::move(pres));
    d.point_fields.push_back(std::move(status));
  }
  // The cells written: all, or this rank's piece.
  auto kept = [&](size_t bi, size_t blk, Index e) {
    const auto* owned = pieces ? a.owned_cells(bi) : nullptr;
    return !owned || (*owned)[blk][e];
  };
  // ParaView's symmetric tensor order: XX, YY, ZZ, XY, YZ, XZ (ours: 11 22 33 23 13 12).
  const int order[6] = {0, 1, 2, 5, 3, 4};
  const std::vector<std::string> names{"XX", "YY", "ZZ", "XY", "YZ", "XZ"};
  VtuField stress{"stress", 6, {}, names}, strain{"strain", 6, {}, names}, vm{"von_mises", 1, {}, {}},
      body{"body", 1, {}, {}}, cell_id{"cell_id", 1, {}, {}};
  size_t written = 0;  // cells
  for (size_t bi = 0; bi < m.bodies.size(); ++bi)
    for (size_t blk = 0; blk < m.bodies[bi]->blocks().size(); ++blk)
      for (Index e = 0; e < m.bodies[bi]->blocks()[blk].size(); ++e) written += kept(bi, blk, e);
  for (VtuField* f : {&stress, &strain, &vm, &body, &cell_id}) f->values.reserve(written * f->components);
  for (size_t bi = 0; bi < m.bodies.size(); ++bi) {
    const Body& b = *m.bodies[bi];
    CellResults r = b.results(m.mesh.nodes, a.displacement(), dofs, &a.history(bi), pieces ? a.owned_cells(bi) : nullptr);
    size_t c = 0;  // r holds the kept cells only, in this order
    for (size_t blk = 0; blk < b.blocks().size(); ++blk)
      for (Index e = 0; e < b.blocks()[blk].size(); ++e) {
        if (!kept(bi, blk, e)) continue;
        for (int k = 0; k < 6; ++k) {
          stress.values.push_back(r.stress[c](order[k]));
          strain.values.push_back(r.strain[c](order[k]));
        }
        vm.values.push_back(r.von_mises[c]);
        body.values.push_back(static_cast<Real>(bi));
        cell_id.values.push_back(static_cast<Real>(b.blocks()[blk].ids[e]));
        ++c;
      }
  }
  for (VtuField* f : {&stress, &strain, &vm, &body, &cell_id}) d.cell_fields.push_back(std::move(*f));
  // The materials' history variables by their names (per cell, the mean over its quadrature
  // points of the committed state; 0 in the cells of bodies whose material has no such value).
  std::vector<std::string> hnames;
  for (size_t bi = 0; bi < m.bodies.size(); ++bi)
    for (const std::string& n : a.history(bi).names())
      if (std::find(hnames.begin(), hnames.end(), n) == hnames.end()) hnames.push_back(n);
  for (const std::string& hn : hnames) {
    VtuField f{hn, 1, {}, {}};
    for (size_t bi = 0; bi < m.bodies.size(); ++bi) {
      const QuadratureHistory& h = a.history(bi);
      const auto& names = h.names();
      const auto k = std::find(names.begin(), names.end(), hn);
      const Body& b = *m.bodies[bi];
      for (size_t blk = 0; blk < b.blocks().size(); ++blk) {
        const Index nq = b.points_per_element(blk);
        for (Index e = 0; e < b.blocks()[blk].size(); ++e) {
          if (!kept(bi, blk, e)) continue;
          Real mean = 0;
          if (k != names.end() && !h.empty()) {
            const Real* v = h.committed(blk, e);
            for (Index q = 0; q < nq; ++q) mean += v[q * h.per_point() + (k - names.begin())];
            mean /= static_cast<Real>(nq);
          }
          f.values.push_back(mean);
        }
      }
    }
    d.cell_fields.push_back(std::move(f));
  }
  const std::string stem = fmt::format("increment_{:02d}_{:04d}", step + 1, inc);
  std::string name = stem + ".vtu";
  if (!pieces) {
    for (auto& b : m.bodies)
      for (auto& blk : b->blocks()) d.cells.push_back(&blk);
    write_vtu_file(dir_ + "/" + name, d);
  } else {
    // This rank's piece: its cells, and the nodes they use numbered in order (rank 0's piece
    // also carries the nodes that no cell uses, such as a rigid body's reference node).
    std::vector<Index> local(m.mesh.num_nodes(), -1);
    std::vector<Vec3> pts;
    std::vector<Index> global;
    auto use = [&](Index n) {
      if (local[n] >= 0) return;
      local[n] = static_cast<Index>(pts.size());
      pts.push_back(m.mesh.nodes[n]);
      global.push_back(n);
    };
    std::vector<ElementBlock> blocks;
    for (size_t bi = 0; bi < m.bodies.size(); ++bi)
      for (size_t blk = 0; blk < m.bodies[bi]->blocks().size(); ++blk) {
        const ElementBlock& src = m.bodies[bi]->blocks()[blk];
        ElementBlock piece{src.type, {}, {}};
        const int nn = src.nodes_per_element();
        for (Index e = 0; e < src.size(); ++e) {
          if (!kept(bi, blk, e)) continue;
          for (int k = 0; k < nn; ++k) {
            use(src.element(e)[k]);
            piece.conn.push_back(local[src.element(e)[k]]);
          }
          piece.ids.push_back(src.ids[e]);
        }
        if (piece.size()) blocks.push_back(std::move(piece));
      }
    // (the ranks hold their own cells only: the analysis kept the nodes in no cell of the mesh)
    if (a.rank() == 0)
      for (Index n : *a.cellless_nodes()) use(n);
    for (VtuField& f : d.point_fields) {
      std::vector<Real> v;
      v.reserve(global.size() * f.components);
      for (Index n : global) v.insert(v.end(), f.values.begin() + n * f.components, f.values.begin() + (n + 1) * f.components);
      f.values = std::move(v);
    }
    d.points = &pts;
    for (auto& b : blocks) d.cells.push_back(&b);
    // A write that fails on one rank stops them all, with its message; and no rank goes on
    // (rank 0 to list the piece in the .pvd) before every piece is on disk.
    std::string failure;
    try {
      write_vtu_file(fmt::format("{}/{}_{}.vtu", dir_, stem, a.rank()), d);
    } catch (const std::exception& e) {
      failure = e.what();
    }
    if (a.any_rank_failed(failure)) throw Error(failure);
    name = stem + ".pvtu";
    if (shared_) {
      std::vector<std::string> files;
      for (int r = 0; r < a.ranks(); ++r) files.push_back(fmt::format("{}_{}.vtu", stem, r));
      write_file_atomically(dir_ + "/" + name, pvtu_text(d, files));
    }
  }
  pvd_.emplace_back(time, name);
  if (!shared_) return;
  write_file_atomically(pvd_path(), pvd_text(pvd_));
  if (step >= 0) write_contact_vtu(a, time, step, inc);
}

void ResultsWriter::write_initial(const Analysis& a) {
  // Rank 0 has emptied the folder of a previous run's files before any rank writes a piece.
  std::string none;
  a.any_rank_failed(none);
  if (shared_) write_file_atomically(dir_ + "/reactions.csv", csv_);
  // The state the run starts from: undeformed, or a restart's (at the time it was written).
  if (model_.output.vtu != "none") write_vtu(a, static_cast<Real>(a.first_step()), -1, 0);
  if (shared_) write_json(a, a.summary(), "running", {});
}

void ResultsWriter::write_increment(const Analysis& a, const IncrementRecord& rec) {
  if (shared_) write_tables(a, rec);
  const bool step_end = rec.fraction >= 1.0;
  if (model_.output.vtu == "every_increment" || (model_.output.vtu == "last" && step_end))
    write_vtu(a, rec.time, rec.step, rec.increment);
  last_record_ = rec;
  have_last_ = true;
  if (shared_) write_json(a, a.summary(), "running", {});
}

void ResultsWriter::write_tables(const Analysis& a, const IncrementRecord& rec) {
  for (auto& set : a.reaction_sets()) {
    Vec3 r = a.reaction_sum(set);
    csv_ += fmt::format("{},{},{:.10g},{:.10g},{},{:.10e},{:.10e},{:.10e}\n", rec.step + 1, rec.increment, rec.time,
                        rec.fraction, set, r(0), r(1), r(2));
  }
  for (const auto& st : rec.contact)
    csv_ += fmt::format("{},{},{:.10g},{:.10g},contact:{},{:.10e},{:.10e},{:.10e}\n", rec.step + 1, rec.increment,
                        rec.time, rec.fraction, st.label, st.force(0), st.force(1), st.force(2));
  for (const auto& c : a.contacts())
    if (c->rigid()) {
      // The force that holds or moves the obstacle along its prescribed components.
      const Vec3 r = a.obstacle_reaction(*c);
      csv_ += fmt::format("{},{},{:.10g},{:.10g},obstacle:{},{:.10e},{:.10e},{:.10e}\n", rec.step + 1, rec.increment,
                          rec.time, rec.fraction, c->settings().name, r(0), r(1), r(2));
      // A turning obstacle: the moment that holds or turns it (plane problems: about z, a
      // vector along z), where its rotation is prescribed or held.
      if (c->num_obstacle_dofs() > model_.settings.spatial_dim()) {
        const Vec3 mo = a.obstacle_moment(*c);
        csv_ += fmt::format("{},{},{:.10g},{:.10g},obstacle_moment:{},{:.10e},{:.10e},{:.10e}\n", rec.step + 1,
                            rec.increment, rec.time, rec.fraction, c->settings().name, mo(0), mo(1), mo(2));
      }
    }
  // A turning rigid body: the moment on its rotation (prescribed or held) about its reference node.
  for (size_t b : a.turning_bodies()) {
    const std::string& name = model_.bodies[b]->name();
    const Vec3 mo = a.body_moment(name);
    csv_ += fmt::format("{},{},{:.10g},{:.10g},body_moment:{},{:.10e},{:.10e},{:.10e}\n", rec.step + 1, rec.increment,
                        rec.time, rec.fraction, name, mo(0), mo(1), mo(2));
  }
  write_file_atomically(dir_ + "/reactions.csv", csv_);
  write_contact_csv(a, rec);
}

namespace {
std::string file_label(const std::string& label) {
  std::string name;
  for (char ch : label) name += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
  while (!name.empty() && name.back() == '_') name.pop_back();
  return name;
}
}  // namespace

void ResultsWriter::write_contact_vtu(const Analysis& a, Real time, int step, int inc) {
  const std::vector<Vec3> x = a.positions(a.displacement());
  for (auto& c : a.contacts()) {
    const std::string name = file_label(c->label());
    // The interface's own settings: master and slave are swapped for a second pass.
    const auto& facets = model_.mesh.facet_sets.at(c->settings().slave);
    // Points: the slave nodes, in current coordinates.
    std::vector<Index> local(model_.mesh.num_nodes(), -1);
    std::vector<Vec3> pts;
    for (const auto& b : facets)
      for (Index n : b.conn)
        if (local[n] < 0) {
          local[n] = static_cast<Index>(pts.size());
          pts.push_back(x[n]);
        }
    std::vector<ElementBlock> blocks = facets;
    for (auto& b : blocks)
      for (auto& n : b.conn) n = local[n];
    VtuData d;
    d.points = &pts;
    for (auto& b : blocks) d.cells.push_back(&b);
    const Real none = std::numeric_limits<Real>::quiet_NaN();  // a gap without value: no master within reach
    VtuField gap{"gap", 1, std::vector<Real>(pts.size(), none), {}};
    VtuField pres{"pressure", 1, std::vector<Real>(pts.size(), 0.0), {}};
    VtuField status{"status", 1, std::vector<Real>(pts.size(), 0.0), {}};
    VtuField id{"node_id", 1, std::vector<Real>(pts.size(), 0.0), {}};
    for (const auto& ns : c->slave_states()) {
      const Index k = local[ns.node];
      if (k < 0) continue;
      gap.values[k] = ns.status ? ns.gap : none;
      pres.values[k] = ns.pressure;
      status.values[k] = ns.status;
    }
    for (Index n = 0; n < model_.mesh.num_nodes(); ++n)
      if (local[n] >= 0) id.values[local[n]] = static_cast<Real>(model_.mesh.node_ids[n]);
    d.point_fields = {gap, pres, status, id};
    const std::string file = fmt::format("contact_{}_{:02d}_{:04d}.vtu", name, step + 1, inc);
    write_vtu_file(dir_ + "/" + file, d);
    auto& list = contact_pvd_[name];
    list.emplace_back(time, file);
    write_file_atomically(dir_ + "/contact_" + name + ".pvd", pvd_text(list));
  }
}

void ResultsWriter::write_contact_csv(const Analysis& a, const IncrementRecord& rec) {
  const std::vector<Vec3> x = a.positions(a.displacement());
  for (auto& c : a.contacts()) {
    const std::string name = file_label(c->label());
    // With friction: the tangential traction on the slave node, its slip in this increment and
    // accumulated, and closed nodes as stick or slip.
    const bool fr = c->frictional();
    std::string text = fr ? "node,x,y,z,gap,pressure,status,traction_x,traction_y,traction_z,slip_increment,"
                            "slip_accumulated\n"
                          : "node,x,y,z,gap,pressure,status\n";
    static const char* const names[] = {"far", "open", "closed", "slip"};
    for (const auto& ns : c->slave_states()) {
      const Index n = ns.node;
      text += fmt::format("{},{:.10e},{:.10e},{:.10e},{},{:.10e},{}", model_.mesh.node_ids[n], x[n](0), x[n](1),
                          x[n](2), ns.status ? fmt::format("{:.10e}", ns.gap) : std::string("nan"), ns.pressure,
                          fr && ns.status == 2 ? "stick" : names[ns.status]);
      if (fr)
        text += fmt::format(",{:.10e},{:.10e},{:.10e},{:.10e},{:.10e}", ns.traction(0), ns.traction(1), ns.traction(2),
                            ns.slip_increment, ns.slip_accumulated);
      text += "\n";
    }
    write_file_atomically(fmt::format("{}/contact_{}_{:02d}_{:04d}.csv", dir_, name, rec.step + 1, rec.increment), text);
  }
}

void ResultsWriter::finish(const Analysis& a, const AnalysisSummary& s, const std::vector<CheckResult>& checks) {
  // With vtu: last, a failed run still leaves its last converged state on disk.
  if (!s.completed && model_.output.vtu == "last" && have_last_ && last_record_.fraction < 1.0)
    write_vtu(a, last_record_.time, last_record_.step, last_record_.increment);
  if (!shared_) return;
  write_json(a, s, s.completed ? "completed" : s.interrupted ? "interrupted" : "failed", checks);
}

void ResultsWriter::record_error(const Analysis& a, const std::string& why) noexcept {
  if (!shared_) return;
  try {
    AnalysisSummary s = a.summary();
    s.failure = why;
    write_json(a, s, "failed", {});
  } catch (...) {
  }
}

void ResultsWriter::write_json(const Analysis& a, const AnalysisSummary& s, const std::string& status,
                               const std::vector<CheckResult>& checks) {
  const Model& m = model_;
  std::string j = "{\n";
  j += fmt::format("  \"title\": \"{}\",\n  \"deck\": \"{}\",\n  \"status\": \"{}\",\n", json_escape(m.title),
                   json_escape(m.deck_path), status);
  j += fmt::format("  \"failure\": {},\n", s.failure.empty() ? "null" : "\"" + json_escape(s.failure) + "\"");
  j += "  \"warnings\": [";
  for (size_t i = 0; i < s.warnings.size(); ++i) j += fmt::format("{}\"{}\"", i ? ", " : "", json_escape(s.warnings[i]));
  j += "],\n";
  j += fmt::format("  \"analysis\": {{\"dimension\": \"{}\", \"kinematics\": \"{}\"}},\n",
                   to_string(m.settings.dimension), m.settings.finite_strain ? "finite_strain" : "small_strain");
  j += fmt::format("  \"nodes\": {},\n  \"cells\": {},\n  \"dofs\": {},\n", m.mesh.num_nodes(), m.mesh.num_cells(),
                   a.dofs().num_dofs());
  // Converged increments' iterations, and those of the attempts that were cut back.
  j += fmt::format("  \"total_iterations\": {},\n  \"failed_iterations\": {},\n", s.total_iterations,
                   s.failed_iterations);
  j += fmt::format("  \"timings\": {{\"assembly_s\": {}, \"contact_s\": {}, \"linear_solve_s\": {}, \"total_s\": {}}},\n",
                   json_number(s.assembly_seconds), json_number(s.contact_seconds), json_number(s.solve_seconds),
                   json_number(log::elapsed()));
  j += fmt::format("  \"tangents\": {{\"evaluated\": {}, \"linear_bodies_assembled\": {}}},\n", s.tangent_evaluations,
                   s.linear_tangent_assemblies);
  j += fmt::format("  \"peak_memory_mib\": {},\n", json_number(log::peak_memory_mib()));
  if (a.first_step() > 0) j += fmt::format("  \"restarted_after_step\": {},\n", a.first_step());
  j += fmt::format("  \"algebra\": \"{}\",\n", json_escape(a.algebra()));
  j += fmt::format("  \"contact_evaluation\": \"{}\",\n", json_escape(a.contact_evaluation()));
  j += fmt::format("  \"mpi_ranks\": {},\n  \"linear\": {{\"type\": \"{}\", \"rtol\": {}, \"options\": \"{}\"}},\n",
                   parallel_ranks(), m.linear_solver.type, json_number(m.linear_solver.rtol),
                   json_escape(m.linear_solver.options));
  j += "  \"increments\": [";
  for (size_t i = 0; i < s.increments.size(); ++i) {
    const auto& r = s.increments[i];
    j += fmt::format("{}\n    {{\"step\": {}, \"increment\": {}, \"time\": {}, \"iterations\": {}, \"cutbacks\": {}, "
                     "\"failed_iterations\": {}, \"uzawa_updates\": {}, \"seconds\": {}, \"linear_solver\": \"{}\", "
                     "\"residuals\": [",
                     i ? "," : "", r.step + 1, r.increment, json_number(r.time), r.iterations, r.cutbacks,
                     r.failed_iterations,
                     r.uzawa_updates, json_number(r.seconds), r.linear_solver);
    for (size_t k = 0; k < r.residuals.size(); ++k) j += (k ? ", " : "") + json_number(r.residuals[k]);
    j += "]";
    if (!r.linear_method.empty()) j += fmt::format(", \"linear_method\": \"{}\"", json_escape(r.linear_method));
    if (std::any_of(r.krylov_iterations.begin(), r.krylov_iterations.end(), [](int k) { return k > 0; })) {
      j += ", \"krylov_iterations\": [";
      for (size_t k = 0; k < r.krylov_iterations.size(); ++k) j += (k ? ", " : "") + std::to_string(r.krylov_iterations[k]);
      j += "]";
      if (std::any_of(r.krylov_rtol.begin(), r.krylov_rtol.end(), [](Real t) { return t > 0; })) {
        j += ", \"krylov_rtol\": [";
        for (size_t k = 0; k < r.krylov_rtol.size(); ++k) j += (k ? ", " : "") + json_number(r.krylov_rtol[k]);
        j += "]";
      }
    }
    if (r.stabilization_ratio > 0) j += fmt::format(", \"stabilization_ratio\": {}", json_number(r.stabilization_ratio));
    if (r.pseudo_transient) j += ", \"pseudo_transient\": true";
    if (r.stagnated) j += fmt::format(", \"stagnated\": true, \"stagnated_residual\": {}", json_number(r.stagnated_residual));
    if (!r.contact.empty()) {
      j += ", \"contact\": [";
      for (size_t k = 0; k < r.contact.size(); ++k) {
        const auto& c = r.contact[k];
        j += fmt::format("{}{{\"pair\": \"{}\", \"active\": {}, \"changes\": {}, \"frozen\": {}, "
                         "\"stick\": {}, \"slip\": {}, \"stick_slip_changes\": {}, \"max_penetration\": {}, "
                         "\"force\": [{}, {}, {}]}}",
                         k ? ", " : "", json_escape(c.label), c.active, c.changes, c.frozen, c.sticking, c.slipping,
                         c.stick_slip_changes,
                         json_number(c.max_penetration), json_number(c.force(0)), json_number(c.force(1)),
                         json_number(c.force(2)));
      }
      j += "]";
    }
    j += "}";
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
