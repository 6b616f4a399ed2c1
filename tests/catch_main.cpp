#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
#include <opencv2/core.hpp>

int main(int argc, char* argv[]) {
  cv::setNumThreads(0);
  return Catch::Session().run(argc, argv);
}
