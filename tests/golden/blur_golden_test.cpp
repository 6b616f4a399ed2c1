// Golden 30-frame motion-blur SLAM trace (issue 15): walking_xyz rendered with --blur and
// sparseinst-like masks (which drop and shrink fast people under blur), the method with
// golden/blur_30f/blur_golden.yaml (configs/blur.yaml with 600 features). See method_golden.h.
#include "method_golden.h"

TEST_CASE("blur golden: 30-frame blurred walking_xyz trace is unchanged", "[cli][golden]") {
  dynref::test::CheckMethodGolden("blur", "golden/blur_30f", "blur_golden.yaml", true, "sparseinst-like");
}
