#include "signorini/fem/history.hpp"

#include "signorini/fem/body.hpp"

#include <string>

#include "signorini/core/error.hpp"

namespace signorini {

QuadratureHistory::QuadratureHistory(const Body& body, const std::vector<std::vector<char>>* held) {
  if (body.rigid()) return;
  const Material& m = body.material();
  per_point_ = m.history_size();
  names_ = m.history_names();
  if (per_point_ == 0) return;  // nothing to hold
  if (held && held->size() != body.blocks().size())
    throw Error("QuadratureHistory: one mask of held cells per block expected");
  Index whole = 0, stored = 0;
  for (size_t b = 0; b < body.blocks().size(); ++b) {
    const Index cells = body.blocks()[b].size();
    // The whole layout spans the whole body's cells (after Body::keep_cells, more than held here).
    block_offset_.push_back(whole);
    per_element_.push_back(body.points_per_element(b) * per_point_);
    whole += body.whole_cells(b) * per_element_.back();
    if (!held) {
      if (body.whole_cells(b) != cells) throw Error("QuadratureHistory: a share of a body's cells needs its mask");
      continue;
    }
    if (static_cast<Index>((*held)[b].size()) != cells) throw Error("QuadratureHistory: a mask of the wrong size");
    whole_index_.emplace_back();
    for (Index e = 0; e < cells; ++e) whole_index_.back().push_back(body.whole_index(b, e));
    held_offset_.emplace_back(static_cast<size_t>(cells), -1);
    for (Index e = 0; e < cells; ++e)
      if ((*held)[b][static_cast<size_t>(e)]) {
        held_offset_.back()[static_cast<size_t>(e)] = stored;
        stored += per_element_.back();
      }
  }
  whole_size_ = whole;
  committed_.resize(static_cast<size_t>(held ? stored : whole));
  for (size_t k = 0; k < committed_.size(); k += static_cast<size_t>(per_point_))
    m.initialize_history(committed_.data() + k);
  trial_ = committed_;
}

std::vector<Real> QuadratureHistory::whole_committed() const {
  if (held_offset_.empty()) return committed_;
  std::vector<Real> whole(static_cast<size_t>(whole_size_), 0.0);
  for (size_t b = 0; b < held_offset_.size(); ++b)
    for (size_t e = 0; e < held_offset_[b].size(); ++e)
      if (const Index k = held_offset_[b][e]; k >= 0)
        std::copy_n(committed_.begin() + k, per_element_[b],
                    whole.begin() + block_offset_[b] + whole_index_[b][e] * per_element_[b]);
  return whole;
}

void QuadratureHistory::restore(const std::vector<Real>& whole) {
  if (static_cast<Index>(whole.size()) != whole_size_)
    throw Error("QuadratureHistory::restore: " + std::to_string(whole.size()) + " values for a history of " +
                std::to_string(whole_size_));
  if (held_offset_.empty()) {
    committed_ = trial_ = whole;
    return;
  }
  for (size_t b = 0; b < held_offset_.size(); ++b)
    for (size_t e = 0; e < held_offset_[b].size(); ++e)
      if (const Index k = held_offset_[b][e]; k >= 0)
        std::copy_n(whole.begin() + block_offset_[b] + whole_index_[b][e] * per_element_[b], per_element_[b],
                    committed_.begin() + k);
  trial_ = committed_;
}

void QuadratureHistory::throw_not_held(size_t block, Index element) const {
  throw Error("the quadrature-point history of cell " + std::to_string(element) + " of block " + std::to_string(block) +
              " is held by another MPI rank");
}

}  // namespace signorini
