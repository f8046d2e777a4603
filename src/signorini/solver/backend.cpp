#include "signorini/solver/backend.hpp"

#include "signorini/core/log.hpp"
#include "signorini/solver/condensed_solve.hpp"
#include "signorini/solver/linear_solver.hpp"

namespace signorini {

namespace {

class SerialBackend final : public AlgebraBackend {
 public:
  SerialBackend(std::string linear, bool three_d)
      : linear_name_(std::move(linear)), linear_(linear_name_, three_d), condensed_(three_d) {}
  std::string name() const override { return "serial"; }
  Index owned_begin() const override { return 0; }
  Index owned_end() const override { return rows(); }
  void build_pattern(const DofMap& dofs, const std::vector<const ElementBlock*>& cells,
                     const std::vector<std::vector<Index>>& couplings, Index total) override {
    system_.build_pattern(dofs, cells, couplings, total);
    linear_.reset();  // a new pattern needs a new symbolic analysis
  }
  Index rows() const override { return system_.matrix().rows(); }
  Index nonzeros() const override { return system_.nonzeros(); }
  void zero() override { system_.zero(); }
  GlobalMatrix& matrix() override { return system_; }
  bool missed() const override { return system_.missed(); }
  void multiply(const VecX& x, VecX& y) const override { y = system_.matrix() * x; }
  Real mean_abs_diagonal() const override { return system_.mean_abs_diagonal(); }
  void apply_dirichlet(const std::vector<char>& constrained, Real scale) override {
    system_.apply_dirichlet(constrained, scale);
  }
  std::string solve(const NewtonSolveRequest& q, const VecX& r, VecX& du) override {
    // Multiplier contact with the automatic solver: the condensed system when its structure
    // allows (condensed_solve.hpp); a solver chosen in the deck gets the whole system.
    if (q.is_multiplier && q.condense_contact && linear_name_ == "auto") {
      if (condensed_.solve(system_.matrix(), *q.is_multiplier, q.body_symmetric, r, du))
        return "condensed+" + condensed_.last_used();
      if (!condense_reported_) {
        log::info("    contact multipliers kept in the linear system (UMFPACK): {}", condensed_.why_not());
        condense_reported_ = true;
      }
    }
    linear_.solve(system_.matrix(), q.symmetric, r, du);
    return linear_.last_used();
  }

 private:
  std::string linear_name_;
  SparseSystem system_;
  AutoLinearSolver linear_;
  CondensedContactSolver condensed_;
  bool condense_reported_ = false;
};

}  // namespace

std::unique_ptr<AlgebraBackend> make_serial_backend(const std::string& linear, bool three_d) {
  return std::make_unique<SerialBackend>(linear, three_d);
}

}  // namespace signorini
