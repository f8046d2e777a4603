#include "signorini/fem/surface_load.hpp"

#include <numbers>

#include "signorini/fem/quadrature.hpp"
#include "signorini/fem/shape.hpp"

namespace signorini {

void add_facet_load(const FacetLoad& load, const AnalysisSettings& settings, const std::vector<Vec3>& X,
                    const VecX& u, const DofMap& dofs, Real scale, VecX& fext, GlobalMatrix* matrix) {
  if (scale == 0 || !load.facets) return;
  const int dim = dofs.dofs_per_node();
  const bool axi = settings.dimension == Dimension::axisymmetric;
  const bool current = load.is_pressure && load.follower;
  for (const ElementBlock& b : *load.facets) {
    const ElementInfo& info = element_info(b.type);
    const QuadratureRule rule = quadrature_rule(b.type, 2 * info.order + (axi ? 1 : 0));
    const int nn = info.num_nodes;
    std::vector<VecX> Ns;
    std::vector<MatX> dNs;
    for (auto& q : rule) {
      VecX N;
      MatX dN;
      shape_functions(b.type, q.xi, N, dN);
      Ns.push_back(N);
      dNs.push_back(dN);
    }
    std::vector<Index> edofs(nn * dim);
    for (Index e = 0; e < b.size(); ++e) {
      const Index* c = b.element(e);
      std::vector<Vec3> x(nn);
      for (int a = 0; a < nn; ++a) {
        x[a] = X[c[a]];
        for (int i = 0; i < dim; ++i) {
          edofs[a * dim + i] = dofs.dof(c[a], i);
          if (current && edofs[a * dim + i] >= 0) x[a](i) += u(edofs[a * dim + i]);
        }
      }
      VecX fe = VecX::Zero(nn * dim);
      MatX ke = MatX::Zero(nn * dim, nn * dim);  // d fe / d x
      for (size_t q = 0; q < rule.size(); ++q) {
        const VecX& N = Ns[q];
        const MatX& dN = dNs[q];
        const Real w = rule[q].weight;
        Real r = 0;
        for (int a = 0; a < nn; ++a) r += N(a) * x[a](0);
        const Real factor = axi ? 2 * std::numbers::pi * r : (dim == 2 ? settings.thickness : 1.0);
        // Area vector n da / dxi (outward): 2D (t_y, -t_x); 3D a1 x a2.
        Vec3 a1 = Vec3::Zero(), a2 = Vec3::Zero();
        for (int a = 0; a < nn; ++a) {
          a1 += dN(a, 0) * x[a];
          if (dim == 3) a2 += dN(a, 1) * x[a];
        }
        Vec3 nda = dim == 2 ? Vec3(a1(1), -a1(0), 0) : Vec3(a1.cross(a2));
        Vec3 t;
        if (load.is_pressure) t = -load.pressure * nda;
        else t = load.traction * nda.norm();
        for (int a = 0; a < nn; ++a)
          for (int i = 0; i < dim; ++i) fe(a * dim + i) += scale * N(a) * t(i) * factor * w;
        if (current && matrix) {
          for (int bnode = 0; bnode < nn; ++bnode) {
            // d(nda)/dx_b as a 3x3 matrix (columns: components of x_b).
            Mat3 dn = Mat3::Zero();
            if (dim == 2) {
              dn(0, 1) = dN(bnode, 0);
              dn(1, 0) = -dN(bnode, 0);
            } else {
              dn = -dN(bnode, 0) * cross_matrix(a2) + dN(bnode, 1) * cross_matrix(a1);
            }
            for (int a = 0; a < nn; ++a)
              for (int i = 0; i < dim; ++i)
                for (int k = 0; k < dim; ++k) {
                  Real v = -load.pressure * dn(i, k) * factor;
                  if (axi && k == 0) v += t(i) * 2 * std::numbers::pi * N(bnode);
                  ke(a * dim + i, bnode * dim + k) += scale * N(a) * v * w;
                }
          }
        }
      }
      for (int k = 0; k < nn * dim; ++k)
        if (edofs[k] >= 0) fext(edofs[k]) += fe(k);
      if (current && matrix) {
        MatX minus = -ke;
        matrix->add(edofs.data(), nn * dim, minus);
      }
    }
  }
}

Real facet_set_area(const std::vector<ElementBlock>& facets, const AnalysisSettings& settings,
                    const std::vector<Vec3>& X) {
  // The area is the x-force of a unit traction (1, 0, 0) on a copy of the facet set.
  std::vector<const ElementBlock*> cells;
  for (auto& b : facets) cells.push_back(&b);
  DofMap dofs(static_cast<Index>(X.size()), settings.spatial_dim(), cells);
  VecX f = VecX::Zero(dofs.num_dofs()), u = VecX::Zero(dofs.num_dofs());
  FacetLoad l{&facets, Vec3(1, 0, 0), 0, false, false};
  add_facet_load(l, settings, X, u, dofs, 1.0, f, nullptr);
  Real s = 0;
  for (Index i = 0; i < f.size(); i += dofs.dofs_per_node()) s += f(i);
  return s;
}

}  // namespace signorini
