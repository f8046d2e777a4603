#include "signorini/app/bench_search.hpp"

#include <fmt/format.h>
#include <omp.h>

#include "signorini/contact/search/sample_surfaces.hpp"
#include "signorini/core/log.hpp"

namespace signorini {

int bench_search(const BenchSearchOptions& o) {
  log::Timer tg;
  SampleSurfaces s = sample_surfaces(o.slave_nodes, o.master_facets);
  const Real h = s.master.mean_edge_length();
  // Automatic detection distance: twice the mean master edge length.
  const Real dmax = 2 * h;
  fmt::print("search benchmark: {} slave nodes, {} master triangles (mean edge {:.3g}), d_max = {:.3g}, {} threads\n",
             s.slave_nodes.size(), s.master.size(), h, dmax, omp_get_max_threads());
  fmt::print("  surfaces generated in {:.3f} s\n", tg.seconds());
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
