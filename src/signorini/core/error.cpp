#include "signorini/core/error.hpp"

namespace signorini {

static std::string compose(const std::string& where, const std::string& key,
                           const std::string& what) {
  std::string s;
  if (!where.empty()) s += where + ": ";
  if (!key.empty()) s += "'" + key + "': ";
  return s + what;
}

InputError::InputError(std::string where, std::string key, const std::string& what)
    : Error(compose(where, key, what)), where_(std::move(where)), key_(std::move(key)), message_(what) {}

}  // namespace signorini
