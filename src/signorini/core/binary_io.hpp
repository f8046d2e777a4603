// Plain binary serialization for restart files: trivially copyable values as their bytes,
// vectors as a count then their elements. Reads check the stream and throw Error on a
// short or corrupt file (the caller adds the file name).
#pragma once
#include <cstdint>
#include <istream>
#include <ostream>
#include <string>
#include <type_traits>
#include <vector>

#include "signorini/core/error.hpp"
#include "signorini/core/types.hpp"

namespace signorini::binary {

template <typename T>
void put(std::ostream& os, const T& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  os.write(reinterpret_cast<const char*>(&v), sizeof(T));
}

template <typename T>
T get(std::istream& is) {
  static_assert(std::is_trivially_copyable_v<T>);
  T v{};
  if (!is.read(reinterpret_cast<char*>(&v), sizeof(T))) throw Error("the file ends early (truncated?)");
  return v;
}

template <typename T>
void put_vector(std::ostream& os, const std::vector<T>& v) {
  put<std::int64_t>(os, static_cast<std::int64_t>(v.size()));
  if (!v.empty()) os.write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(T)));
}

// A vector of exactly `expected` elements (-1: any count up to 1e9).
template <typename T>
std::vector<T> get_vector(std::istream& is, std::int64_t expected, const char* what) {
  const auto n = get<std::int64_t>(is);
  if (expected >= 0 && n != expected)
    throw Error(std::string(what) + ": " + std::to_string(n) + " values in the file, the model has " +
                std::to_string(expected));
  if (n < 0 || n > 1000000000) throw Error(std::string(what) + ": corrupt count");
  std::vector<T> v(static_cast<size_t>(n));
  if (n > 0 && !is.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(n * sizeof(T))))
    throw Error("the file ends early (truncated?)");
  return v;
}

inline void put_vec3(std::ostream& os, const Vec3& v) {
  for (int i = 0; i < 3; ++i) put<Real>(os, v(i));
}
inline Vec3 get_vec3(std::istream& is) {
  Vec3 v;
  for (int i = 0; i < 3; ++i) v(i) = get<Real>(is);
  return v;
}

inline void put_vec(std::ostream& os, const VecX& v) { put_vector(os, std::vector<Real>(v.data(), v.data() + v.size())); }
inline VecX get_vec(std::istream& is, Index expected, const char* what) {
  const std::vector<Real> v = get_vector<Real>(is, expected, what);
  return Eigen::Map<const VecX>(v.data(), static_cast<Index>(v.size()));
}

}  // namespace signorini::binary
