#include "signorini/fem/history.hpp"

#include "signorini/fem/body.hpp"

#include <string>

#include "signorini/core/error.hpp"

namespace signorini {

QuadratureHistory::QuadratureHistory(const Body& body) {
  if (body.rigid()) return;
  const Material& m = body.material();
  per_point_ = m.history_size();
  names_ = m.history_names();
  Index offset = 0;
  for (size_t b = 0; b < body.blocks().size(); ++b) {
    block_offset_.push_back(offset);
    cells_.push_back(body.blocks()[b].size());
    per_element_.push_back(body.points_per_element(b) * per_point_);
    offset += body.blocks()[b].size() * per_element_.back();
  }
  whole_size_ = per_point_ == 0 ? 0 : offset;
  if (per_point_ == 0) return;
  committed_.resize(offset);
  for (Index k = 0; k < offset; k += per_point_) m.initialize_history(committed_.data() + k);
  trial_ = committed_;
}

void QuadratureHistory::hold_only(const std::vector<std::vector<char>>& held) {
  if (empty()) return;
  if (held.size() != per_element_.size()) throw Error("QuadratureHistory::hold_only: one mask per block expected");
  std::vector<std::vector<Index>> offsets(per_element_.size());
  std::vector<Real> committed, trial;
  for (size_t b = 0; b < per_element_.size(); ++b) {
    const Index cells = cells_[b];
    if (static_cast<Index>(held[b].size()) != cells) throw Error("QuadratureHistory::hold_only: a mask of the wrong size");
    offsets[b].assign(static_cast<size_t>(cells), -1);
    for (Index e = 0; e < cells; ++e) {
      if (!held[b][static_cast<size_t>(e)]) continue;
      const Index from = offset(b, e);  // the layout so far
      offsets[b][static_cast<size_t>(e)] = static_cast<Index>(committed.size());
      committed.insert(committed.end(), committed_.begin() + from, committed_.begin() + from + per_element_[b]);
      trial.insert(trial.end(), trial_.begin() + from, trial_.begin() + from + per_element_[b]);
    }
  }
  committed.shrink_to_fit();
  trial.shrink_to_fit();
  // Called again, the cells held now must have been held before (offset() throws otherwise).
  held_offset_ = std::move(offsets);
  committed_ = std::move(committed);
  trial_ = std::move(trial);
}

std::vector<Real> QuadratureHistory::whole_committed() const {
  if (held_offset_.empty()) return committed_;
  std::vector<Real> whole(static_cast<size_t>(whole_size_), 0.0);
  for (size_t b = 0; b < held_offset_.size(); ++b)
    for (size_t e = 0; e < held_offset_[b].size(); ++e)
      if (const Index k = held_offset_[b][e]; k >= 0)
        std::copy_n(committed_.begin() + k, per_element_[b],
                    whole.begin() + block_offset_[b] + static_cast<Index>(e) * per_element_[b]);
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
        std::copy_n(whole.begin() + block_offset_[b] + static_cast<Index>(e) * per_element_[b], per_element_[b],
                    committed_.begin() + k);
  trial_ = committed_;
}

void QuadratureHistory::throw_not_held(size_t block, Index element) const {
  throw Error("the quadrature-point history of cell " + std::to_string(element) + " of block " + std::to_string(block) +
              " is held by another MPI rank");
}

}  // namespace signorini
