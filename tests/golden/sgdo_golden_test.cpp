// Golden 30-frame sgdo trace (issue 6): walking_xyz, SGDO-SLAM with golden/sgdo_30f/sgdo_golden.yaml
// (configs/sgdo.yaml with 300 features, no dense map). See method_golden.h.
#include "method_golden.h"

TEST_CASE("sgdo golden: 30-frame walking_xyz trace is unchanged", "[cli][golden]") {
  dynref::test::CheckMethodGolden("sgdo", "golden/sgdo_30f", "sgdo_golden.yaml");
}
