#include "signorini/app/bench_search.hpp"

#include <fmt/format.h>
#include <array>
#include <omp.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>

#include "signorini/contact/search/sample_surfaces.hpp"
#include "signorini/core/error.hpp"
#include "signorini/core/log.hpp"
#include "signorini/mesh/gmsh_reader.hpp"

namespace signorini {

namespace {

// The surfaces as Gmsh 2.2 ASCII files: the slave nodes as points (element type 15), the
// master facets with their corners merged into shared nodes.
void write_surfaces(const SampleSurfaces& s, const std::string& dir) {
  namespace fs = std::filesystem;
  fs::create_directories(dir);
  auto open = [&](const std::string& name) {
    const std::string p = (fs::path(dir) / name).string();
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(p.c_str(), "w"), &std::fclose);
    if (!f) throw InputError(p, "", "cannot write");
    std::fprintf(f.get(), "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n");
    return f;
  };
  {
    auto f = open("slave.msh");
    const size_t n = s.slave_nodes.size();
    std::fprintf(f.get(), "$Nodes\n%zu\n", n);
    for (size_t i = 0; i < n; ++i)
      std::fprintf(f.get(), "%zu %.17g %.17g %.17g\n", i + 1, s.slave_nodes[i](0), s.slave_nodes[i](1), s.slave_nodes[i](2));
    std::fprintf(f.get(), "$EndNodes\n$Elements\n%zu\n", n);
    for (size_t i = 0; i < n; ++i) std::fprintf(f.get(), "%zu 15 2 0 1 %zu\n", i + 1, i + 1);
    std::fprintf(f.get(), "$EndElements\n");
  }
  {
    auto f = open("master.msh");
    std::map<std::array<double, 3>, size_t> id;
    std::vector<size_t> conn;
    std::vector<const Vec3*> order;
    for (const Vec3& p : s.master.points) {
      auto [it, fresh] = id.emplace(std::array<double, 3>{p(0), p(1), p(2)}, id.size() + 1);
      if (fresh) order.push_back(&p);
      conn.push_back(it->second);
    }
    std::fprintf(f.get(), "$Nodes\n%zu\n", order.size());
    for (size_t i = 0; i < order.size(); ++i)
      std::fprintf(f.get(), "%zu %.17g %.17g %.17g\n", i + 1, (*order[i])(0), (*order[i])(1), (*order[i])(2));
    const int c = s.master.corners;
    const size_t m = static_cast<size_t>(s.master.size());
    std::fprintf(f.get(), "$EndNodes\n$Elements\n%zu\n", m);
    for (size_t e = 0; e < m; ++e) {
      std::fprintf(f.get(), "%zu %d 2 0 1", e + 1, c == 3 ? 2 : 3);
      for (int k = 0; k < c; ++k) std::fprintf(f.get(), " %zu", conn[e * c + k]);
      std::fprintf(f.get(), "\n");
    }
    std::fprintf(f.get(), "$EndElements\n");
  }
}

// The surfaces of two .msh files: every node of the first, every facet of the second
// (quadrilaterals split in two triangles when the file mixes them with triangles).
SampleSurfaces read_surfaces(const std::string& slave, const std::string& master) {
  SampleSurfaces s;
  s.slave_nodes = read_surface_file(slave).nodes;
  SurfaceFile m = read_surface_file(master);
  if (m.triangles.empty() && m.quads.empty()) throw InputError(master, "", "no triangles or quadrilaterals");
  if (m.triangles.empty()) {
    s.master.corners = 4;
    s.master.points = std::move(m.quads);
  } else {
    s.master.corners = 3;
    s.master.points = std::move(m.triangles);
    for (size_t q = 0; q + 3 < m.quads.size(); q += 4)
      for (int k : {0, 1, 2, 0, 2, 3}) s.master.points.push_back(m.quads[q + k]);
  }
  return s;
}

}  // namespace

int bench_search(const BenchSearchOptions& o) {
  log::Timer tg;
  const bool files = !o.slave_file.empty() || !o.master_file.empty();
  if (files && (o.slave_file.empty() || o.master_file.empty()))
    throw InputError("bench search", "", "--slave and --master go together");
  SampleSurfaces s = files ? read_surfaces(o.slave_file, o.master_file) : sample_surfaces(o.slave_nodes, o.master_facets, o.gap, o.quads);
  if (!o.write_dir.empty()) {
    write_surfaces(s, o.write_dir);
    fmt::print("surfaces written to {}/slave.msh and {}/master.msh\n", o.write_dir, o.write_dir);
  }
  const Real h = s.master.mean_edge_length();
  // Automatic detection distance: twice the mean master edge length.
  const Real dmax = 2 * h;
  fmt::print("search benchmark: {} slave nodes, {} master {} (mean edge {:.3g}), d_max = {:.3g}, {} threads\n",
             s.slave_nodes.size(), s.master.size(),
             s.master.corners == 4 ? "quadrilaterals" : s.master.corners == 3 ? "triangles" : "segments", h, dmax,
             omp_get_max_threads());
  fmt::print("  surfaces {} in {:.3f} s\n", files ? "read from " + o.slave_file + " and " + o.master_file : "generated",
             tg.seconds());
  // Reference answers on an evenly spread subset.
  std::vector<Vec3> subset;
  const Index n = static_cast<Index>(s.slave_nodes.size());
  const Index step = std::max<Index>(1, n / std::max<Index>(1, o.check_subset));
  for (Index i = 0; i < n; i += step) subset.push_back(s.slave_nodes[i]);
  std::vector<SearchHit> ref;
  {
    auto all = make_search("all_to_all");
    log::Timer t;
    all->build(s.master);
    all->closest(subset, dmax, ref);
    const double sec = t.seconds();
    fmt::print("  {:<12} {:>8} nodes: {:8.3f} s  ({:.3g} s per node; the whole set would take {:.3g} h)\n",
               "all_to_all", subset.size(), sec, sec / subset.size(), sec / subset.size() * n / 3600);
  }
  std::vector<std::string> methods = o.method.empty() ? std::vector<std::string>{"bucket_grid", "bvh"}
                                                      : std::vector<std::string>{o.method};
  int status = 0;
  for (const auto& m : methods) {
    if (m == "all_to_all") continue;
    auto search = make_search(m);
    std::vector<SearchHit> hits;
    for (int rep = 0; rep < o.repeats; ++rep) {
      log::Timer tb;
      search->build(s.master);
      const double build = tb.seconds();
      log::Timer tq;
      search->closest(s.slave_nodes, dmax, hits);
      const double query = tq.seconds();
      Index found = 0;
      for (auto& hit : hits) found += hit.facet >= 0;
      fmt::print("  {:<12} {}: build {:.3f} s + query {:.3f} s = {:.3f} s, {} of {} slave nodes within d_max\n", m,
                 rep == 0 ? "first pass " : "re-detection", build, query, build + query, found, n);
    }
    Index wrong = 0;
    for (size_t k = 0; k < subset.size(); ++k) {
      const SearchHit& a = ref[k];
      const SearchHit& b = hits[k * step];
      if ((a.facet < 0) != (b.facet < 0) || (a.facet >= 0 && std::abs(a.distance - b.distance) > 1e-14)) ++wrong;
    }
    fmt::print("  {:<12} agrees with all_to_all on {} of {} checked nodes\n", m, subset.size() - wrong, subset.size());
    if (wrong) status = 1;
  }
  fmt::print("  peak memory {:.0f} MiB\n", log::peak_memory_mib());
  return status;
}

}  // namespace signorini
