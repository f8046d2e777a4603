// Exceptions inside OpenMP parallel loops. An exception that leaves a thread's structured block
// ends the program (std::terminate, "terminate called after throwing ..."): the user would see
// an abort and a stack trace instead of the error's message, and the analysis could not cut
// back. FirstError runs each iteration's body, keeps the first exception any thread threw and
// skips the body once one is kept; rethrow() throws it on the calling thread after the loop.
//
//   FirstError first;
//   #pragma omp parallel for
//   for (Index e = 0; e < n; ++e) first.run([&] { work(e); });
//   first.rethrow();
#pragma once

#include <atomic>
#include <exception>
#include <mutex>
#include <string>

#include "signorini/core/error.hpp"
#include "signorini/core/rank_exchange.hpp"

namespace signorini {

class FirstError {
 public:
  template <class F>
  void run(F&& body) noexcept {
    if (failed_.load(std::memory_order_relaxed)) return;
    try {
      body();
    } catch (...) {
      capture();
    }
  }
  // In a catch handler inside the loop (for a body with `continue`s of its own).
  void capture() noexcept {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!error_) error_ = std::current_exception();
    failed_.store(true, std::memory_order_relaxed);
  }
  void rethrow() const {
    if (error_) std::rethrow_exception(error_);
  }
  // Collective (every rank calls it at the same point): each rank throws the lowest failing
  // rank's error, a SolverError where it was one (Newton then shortens its step or cuts back),
  // else an Error; none when no rank failed. For work shared out over the ranks, whose failure
  // on one rank would otherwise leave the others waiting in the next exchange.
  void rethrow_agreed(const RankExchange& ex) const {
    std::string mine;
    if (error_) {
      try {
        std::rethrow_exception(error_);
      } catch (const SolverError& e) {
        mine = std::string("S") + e.what();
      } catch (const std::exception& e) {
        mine = std::string("E") + e.what();
      } catch (...) {
        mine = "Eunknown error";
      }
    }
    for (const std::string& f : ex.allgather(mine)) {
      if (f.empty()) continue;
      if (f[0] == 'S') throw SolverError(f.substr(1));
      throw Error(f.substr(1));
    }
  }

 private:
  std::atomic<bool> failed_{false};
  std::mutex mutex_;
  std::exception_ptr error_;
};

}  // namespace signorini
