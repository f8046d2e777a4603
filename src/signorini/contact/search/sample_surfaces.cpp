#include "signorini/contact/search/sample_surfaces.hpp"

#include <cmath>
#include <numbers>

namespace signorini {

namespace {
Real wave(Real x, Real y) {
  return 0.05 * std::sin(2 * std::numbers::pi * x) * std::cos(2 * std::numbers::pi * y) + 0.1 * (x * x + y * y);
}
}  // namespace

SampleSurfaces sample_surfaces(Index slave_nodes, Index master_facets, Real gap, bool quads) {
  SampleSurfaces s;
  const Index ns = std::max<Index>(2, static_cast<Index>(std::lround(std::sqrt(static_cast<double>(slave_nodes)))));
  s.slave_nodes.resize(ns * ns);
#pragma omp parallel for schedule(static)
  for (Index j = 0; j < ns; ++j)
    for (Index i = 0; i < ns; ++i) {
      const Real x = static_cast<Real>(i) / (ns - 1), y = static_cast<Real>(j) / (ns - 1);
      s.slave_nodes[j * ns + i] = Vec3(x, y, wave(x, y) + gap);
    }
  // Master: a grid of (nm x nm) squares, two triangles each (or the squares themselves),
  // rotated by 7 degrees about the centre and enlarged so that it covers the slave sheet.
  const Index nm = std::max<Index>(1, static_cast<Index>(std::lround(std::sqrt(master_facets / (quads ? 1.0 : 2.0)))));
  const Real t = 7 * std::numbers::pi / 180, c = std::cos(t), sn = std::sin(t);
  auto vertex = [&](Index i, Index j) {
    const Real u = 1.3 * (static_cast<Real>(i) / nm - 0.5), v = 1.3 * (static_cast<Real>(j) / nm - 0.5);
    const Real x = 0.5 + c * u - sn * v, y = 0.5 + sn * u + c * v;
    return Vec3(x, y, wave(x, y));
  };
  s.master.corners = quads ? 4 : 3;
  s.master.points.resize(nm * nm * (quads ? 4 : 6));
#pragma omp parallel for schedule(static)
  for (Index j = 0; j < nm; ++j)
    for (Index i = 0; i < nm; ++i) {
      if (quads) {
        Vec3* p = s.master.points.data() + (j * nm + i) * 4;
        p[0] = vertex(i, j);
        p[1] = vertex(i + 1, j);
        p[2] = vertex(i + 1, j + 1);
        p[3] = vertex(i, j + 1);
        continue;
      }
      Vec3* p = s.master.points.data() + (j * nm + i) * 6;
      p[0] = vertex(i, j);
      p[1] = vertex(i + 1, j);
      p[2] = vertex(i + 1, j + 1);
      p[3] = vertex(i, j);
      p[4] = vertex(i + 1, j + 1);
      p[5] = vertex(i, j + 1);
    }
  return s;
}

}  // namespace signorini
