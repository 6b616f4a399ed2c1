// Golden 30-frame enhanced-epipolar SLAM trace (issue 17, Modules A + C): walking_xyz rendered
// with --low-light and yolo-like masks, the method with golden/epi_30f/epi_golden.yaml
// (configs/epi.yaml with 500 features and 10 BOA iterations). See method_golden.h.
#include "method_golden.h"

TEST_CASE("epi golden: 30-frame low-light walking_xyz trace is unchanged", "[cli][golden]") {
  dynref::test::CheckMethodGolden("epi", "golden/epi_30f", "epi_golden.yaml", false, "yolo-like", true);
}
