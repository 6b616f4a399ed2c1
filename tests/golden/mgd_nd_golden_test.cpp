// Golden 30-frame mgd-nd trace (issue 13): walking_xyz, points + lines + planes without dynamic
// modelling (golden/mgd_nd_30f/mgd_nd_golden.yaml). Every line and plane residual of pose-only
// optimisation and local BA, every frame line / plane geometry record. See method_golden.h.
#include "method_golden.h"

TEST_CASE("mgd-nd golden: 30-frame walking_xyz trace with line and plane residuals is unchanged", "[cli][golden]") {
  dynref::test::CheckMethodGolden("mgd-nd", "golden/mgd_nd_30f", "mgd_nd_golden.yaml");
}
