// Golden 30-frame mgd trace (issue 14): walking_xyz, MGD-SLAM with golden/mgd_30f/mgd_golden.yaml
// (configs/mgd.yaml with 300 features). See method_golden.h.
#include "method_golden.h"

TEST_CASE("mgd golden: 30-frame walking_xyz trace is unchanged", "[cli][golden]") {
  dynref::test::CheckMethodGolden("mgd", "golden/mgd_30f", "mgd_golden.yaml");
}
