// FirstError (core/first_error.hpp): an exception thrown inside an OpenMP loop reaches the
// caller with its type and message, instead of ending the program (std::terminate). Before it,
// a mortar build whose segment clipping failed at a line search's trial point aborted the run
// with "terminate called after throwing an instance of 'signorini::Error'" (plane-strain Hertz
// cylinder, mortar, penalty, frictionless: docs/contact.md, Limits).
#include <gtest/gtest.h>

#include <atomic>
#include <string>
#include <vector>

#include "signorini/core/error.hpp"
#include "signorini/core/first_error.hpp"
#include "signorini/core/types.hpp"

using namespace signorini;

namespace {

// Ranks as a list of what each says: allgather returns them all, whatever `mine` is (the
// calling rank's entry is `said[rank]`).
class ListedRanks : public RankExchange {
 public:
  explicit ListedRanks(std::vector<std::string> said) : said_(std::move(said)) {}
  int rank() const override { return 0; }
  int size() const override { return static_cast<int>(said_.size()); }
  std::vector<std::string> allgather(const std::string&) const override { return said_; }
  void broadcast(std::string&, int) const override {}

 private:
  std::vector<std::string> said_;
};

}  // namespace

TEST(FirstError, ExceptionInAnOpenMPLoopReachesTheCallerWithItsType) {
  FirstError first;
  std::atomic<int> ran{0};
#pragma omp parallel for schedule(dynamic, 4)
  for (Index i = 0; i < 1000; ++i)
    first.run([&] {
      ++ran;
      if (i == 337) throw SolverError("cell 337 inverted");
    });
  EXPECT_GE(ran.load(), 1);
  try {
    first.rethrow();
    FAIL() << "the loop's exception was not rethrown";
  } catch (const SolverError& e) {
    EXPECT_EQ(std::string(e.what()), "cell 337 inverted");
  }
}

TEST(FirstError, NothingThrownNothingRethrown) {
  FirstError first;
  int sum = 0;
#pragma omp parallel for reduction(+ : sum)
  for (int i = 0; i < 100; ++i) first.run([&] { sum += i; });
  EXPECT_NO_THROW(first.rethrow());
  EXPECT_EQ(sum, 4950);
}

TEST(FirstError, CaptureInAHandlerKeepsAPlainError) {
  FirstError first;
#pragma omp parallel for
  for (int i = 0; i < 64; ++i) {
    try {
      if (i % 16 == 5) throw Error("facet " + std::to_string(i));
    } catch (...) {
      first.capture();
    }
  }
  try {
    first.rethrow();
    FAIL() << "not rethrown";
  } catch (const SolverError&) {
    FAIL() << "a plain Error came back as a SolverError";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("facet ", 0), 0u) << e.what();
  }
}

TEST(FirstError, RanksAgreeOnTheLowestFailingRank) {
  // This rank did not fail, rank 1 failed with a SolverError, rank 2 with an Error: every rank
  // throws rank 1's, a SolverError.
  const FirstError clean;
  try {
    clean.rethrow_agreed(ListedRanks({"", "Sa segment was lost", "Ebad facet"}));
    FAIL() << "no rank threw";
  } catch (const SolverError& e) {
    EXPECT_EQ(std::string(e.what()), "a segment was lost");
  }
  try {
    clean.rethrow_agreed(ListedRanks({"", "", "Ebad facet"}));
    FAIL() << "no rank threw";
  } catch (const SolverError&) {
    FAIL() << "an Error came back as a SolverError";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "bad facet");
  }
  EXPECT_NO_THROW(clean.rethrow_agreed(ListedRanks({"", ""})));
}
