// The quadrature-point history of one body (a material's internal variables: plastic strain,
// F_p, hardening): the committed state of the last converged increment and the trial state of
// the current one, laid out block after block, element after element, point after point.
// Owned by the analysis (one per body), initialised by the material (a multiplicative plastic
// F_p starts at I, not at 0), with the material's names for output.
#pragma once
#include <algorithm>
#include <string>
#include <vector>

#include "signorini/core/types.hpp"

namespace signorini {

class Body;

class QuadratureHistory {
 public:
  QuadratureHistory() = default;
  // Sized for the body's blocks and quadrature rules, every point set by the material's
  // initialize_history (a rigid body or a material without history: empty).
  explicit QuadratureHistory(const Body& body);

  int per_point() const { return per_point_; }
  bool empty() const { return committed_.empty(); }
  // The first value of the element's first point in block b (nullptr when empty).
  const Real* committed(size_t block, Index element) const {
    return empty() ? nullptr : committed_.data() + offset(block, element);
  }
  Real* trial(size_t block, Index element) { return empty() ? nullptr : trial_.data() + offset(block, element); }
  const std::vector<std::string>& names() const { return names_; }

  void commit() { committed_ = trial_; }  // the increment converged
  void revert() { trial_ = committed_; }  // the increment is cut back, or starts
  const std::vector<Real>& committed_values() const { return committed_; }
  // Partitioned assembly: the trial values of the cells that this rank did not assemble set
  // to zero (owned[block][element]), so that a sum over the ranks gives every cell its owner's.
  void keep_cells(const std::vector<std::vector<char>>& owned) {
    for (size_t b = 0; b < owned.size() && b < per_element_.size(); ++b)
      for (Index e = 0; e < static_cast<Index>(owned[b].size()); ++e)
        if (!owned[b][e]) std::fill_n(trial_.begin() + offset(b, e), per_element_[b], 0.0);
  }
  std::vector<Real>& trial_values() { return trial_; }
  // A restart: the committed (and trial) state read back; the size must match.
  void restore(const std::vector<Real>& committed) {
    committed_ = trial_ = committed;
  }

 private:
  Index offset(size_t block, Index element) const { return block_offset_[block] + element * per_element_[block]; }
  int per_point_ = 0;
  std::vector<Index> block_offset_, per_element_;
  std::vector<Real> committed_, trial_;
  std::vector<std::string> names_;
};

}  // namespace signorini
