// Errors carry context (file, line, key) so that the command line can print one clear
// message. Input errors (the user's) and solver failures (the problem's) are separate types.
#pragma once
#include <stdexcept>
#include <string>

namespace signorini {

// Generic error with a message that is already meant for the user.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An error in the user's input: deck, mesh or command line. `where` is "file:line" or
// "file" when no line is known; `key` is the dotted path of the deck key, if any.
class InputError : public Error {
 public:
  InputError(std::string where, std::string key, const std::string& what);
  const std::string& where() const { return where_; }
  const std::string& key() const { return key_; }
  // The message without the where and key in front (what() has them).
  const std::string& message() const { return message_; }

 private:
  std::string where_;
  std::string key_;
  std::string message_;
};

// The analysis could not go on (Newton diverged below the minimum increment, singular
// system, ...). The message says why.
class SolverError : public Error {
 public:
  using Error::Error;
};

// A failure no cutback can cure (a singular model, a solver unfit for the system): the
// analysis stops at once.
class FatalModelError : public SolverError {
 public:
  using SolverError::SolverError;
};

// A factorization that ran out of memory, or of its library's integers: not a singular model,
// and a smaller increment would not make the system smaller, so the analysis stops at once.
class SolverResourceError : public FatalModelError {
 public:
  using FatalModelError::FatalModelError;
};

}  // namespace signorini
