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
  // initialize_history (a rigid body or a material without history: empty). With `held`
  // (partitioned assembly over MPI ranks, issue 15: per block, a rank's own cells) only those
  // cells' values are stored; the others take no memory, and asking for them is an error.
  explicit QuadratureHistory(const Body& body, const std::vector<std::vector<char>>* held = nullptr);

  int per_point() const { return per_point_; }
  bool empty() const { return committed_.empty(); }
  // The first value of the element's first point in block b (nullptr when empty).
  const Real* committed(size_t block, Index element) const {
    return empty() ? nullptr : committed_.data() + offset(block, element);
  }
  Real* trial(size_t block, Index element) { return empty() ? nullptr : trial_.data() + offset(block, element); }
  // Whether the values of cell `element` of block b are held here (all cells unless `held`
  // said otherwise).
  bool holds(size_t block, Index element) const {
    return held_offset_.empty() || held_offset_[block][static_cast<size_t>(element)] >= 0;
  }
  const std::vector<std::string>& names() const { return names_; }

  void commit() { committed_ = trial_; }  // the increment converged
  void revert() { trial_ = committed_; }  // the increment is cut back, or starts
  // The values held here (with `held`, only those of the held cells, in cell order).
  const std::vector<Real>& committed_values() const { return committed_; }

  // The committed state in the layout of the whole body (every cell): the held cells' values,
  // zeros elsewhere, so that a sum over the ranks gives every cell its owner's (a restart file).
  std::vector<Real> whole_committed() const;
  // The size of that layout.
  Index whole_size() const { return whole_size_; }
  // A restart: the committed (and trial) state read back in the whole layout (whole_size()
  // values), of which the held cells' are kept.
  void restore(const std::vector<Real>& whole);

 private:
  Index offset(size_t block, Index element) const {
    if (held_offset_.empty()) return block_offset_[block] + element * per_element_[block];
    const Index k = held_offset_[block][static_cast<size_t>(element)];
    if (k < 0) throw_not_held(block, element);
    return k;
  }
  [[noreturn]] void throw_not_held(size_t block, Index element) const;
  int per_point_ = 0;
  Index whole_size_ = 0;
  std::vector<Index> block_offset_, per_element_;  // the whole layout
  std::vector<std::vector<Index>> held_offset_;    // with `held`: each cell's first value, -1 if not held
  std::vector<std::vector<Index>> whole_index_;    // each cell's place in the whole body (Body::whole_index)
  std::vector<Real> committed_, trial_;
  std::vector<std::string> names_;
};

}  // namespace signorini
