// Editing a deck's text in a test.
#pragma once
#include <gtest/gtest.h>

#include <string>

namespace signorini::test {

// Replaces the first occurrence of `from` in a deck's text by `to`; a deck without it fails
// the test (the deck it edits changed).
inline void replace_in_text(std::string& text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
}

}  // namespace signorini::test
