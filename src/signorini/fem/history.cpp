#include "signorini/fem/history.hpp"

#include "signorini/fem/body.hpp"

namespace signorini {

QuadratureHistory::QuadratureHistory(const Body& body) {
  if (body.rigid()) return;
  const Material& m = body.material();
  per_point_ = m.history_size();
  names_ = m.history_names();
  Index offset = 0;
  for (size_t b = 0; b < body.blocks().size(); ++b) {
    block_offset_.push_back(offset);
    per_element_.push_back(body.points_per_element(b) * per_point_);
    offset += body.blocks()[b].size() * per_element_.back();
  }
  if (per_point_ == 0) return;
  committed_.resize(offset);
  for (Index k = 0; k < offset; k += per_point_) m.initialize_history(committed_.data() + k);
  trial_ = committed_;
}

}  // namespace signorini
