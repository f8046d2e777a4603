#include "signorini/fem/model.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace signorini {

std::vector<std::string> unsymmetric_tangent_reasons(const Model& model) {
  std::vector<std::string> why;
  for (const ContactPairSettings& cs : model.contacts) {
    if (cs.friction != "none") why.push_back(fmt::format("friction in contact pair '{}'", cs.name));
    else if (cs.method == "nitsche" && cs.nitsche_theta != 1)
      why.push_back(fmt::format("Nitsche's method with theta {} in contact pair '{}'", cs.nitsche_theta, cs.name));
  }
  for (const Step& s : model.steps)
    for (const Load& l : s.loads) {
      std::string r;
      if (l.kind == LoadKind::pressure && model.settings.finite_strain) r = "follower pressure (finite strain)";
      else if (l.moment && model.settings.spatial_dim() == 3) r = "a moment in 3D";
      if (r.empty()) continue;
      r += fmt::format(" in step '{}'", s.name);
      if (why.empty() || why.back() != r) why.push_back(r);
    }
  return why;
}

std::string symmetric_solver_refusal(const Model& model, bool unsymmetric) {
  const std::string& type = model.linear_solver.type;
  if (!is_symmetric_only_solver(type)) return "";
  std::vector<std::string> why = unsymmetric_tangent_reasons(model);
  if (why.empty() && !unsymmetric) return "";
  if (why.empty()) why.push_back("an unsymmetric tangent");
  return fmt::format("linear solver {} takes symmetric systems only, and this model's are unsymmetric ({}): use auto, "
                     "umfpack{}",
                     type, fmt::join(why, "; "), petsc_available() ? " or mumps" : " or eigen_lu");
}

}  // namespace signorini
