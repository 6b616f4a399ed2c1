// core/parallel.h: every task runs once whatever the thread count, outputs land in their own
// slots, and the reported error is the lowest failing task's, independent of scheduling.
#include <catch2/catch.hpp>

#include <stdexcept>
#include <string>
#include <vector>

#include "core/parallel.h"

TEST_CASE("parallel: ParallelFor runs each task once into its own slot for 1..8 threads") {
  for (int threads = 1; threads <= 8; ++threads) {
    std::vector<int> out(37, -1), runs(37, 0);
    dynref::ParallelFor(37, threads, [&](int i) {
      out[static_cast<size_t>(i)] = i * i;
      ++runs[static_cast<size_t>(i)];
    });
    for (int i = 0; i < 37; ++i) {
      CHECK(out[static_cast<size_t>(i)] == i * i);
      CHECK(runs[static_cast<size_t>(i)] == 1);
    }
  }
  int calls = 0;
  dynref::ParallelFor(0, 4, [&](int) { ++calls; });
  CHECK(calls == 0);
}

TEST_CASE("parallel: the lowest failing task's exception is rethrown after all tasks ran") {
  for (int threads : {1, 2, 4}) {
    std::vector<int> done(10, 0);
    try {
      dynref::ParallelFor(10, threads, [&](int i) {
        done[static_cast<size_t>(i)] = 1;
        if (i == 7 || i == 3) throw std::runtime_error("task " + std::to_string(i));
      });
      FAIL("no exception");
    } catch (const std::runtime_error& e) {
      CHECK(std::string(e.what()) == "task 3");
    }
    if (threads > 1)  // the workers finish every other task before rethrowing
      for (int d : done) CHECK(d == 1);
  }
}
