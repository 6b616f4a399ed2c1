#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
#include <opencv2/core.hpp>

#include "test_support.h"

int main(int argc, char* argv[]) {
  cv::setNumThreads(0);
  const int failed = Catch::Session().run(argc, argv);
  // A passing process removes its scratch folders; a failing one keeps them for inspection.
  if (failed == 0) dynref::test::RemoveScratchDirs();
  return failed;
}
