// Golden 30-frame semantic trace (issue 16): walking_xyz, semantic mapping with
// golden/semantic_30f/semantic_golden.yaml (configs/semantic.yaml with 300 features, every 8th
// pixel, no intermediate clouds). See method_golden.h.
#include "method_golden.h"

TEST_CASE("semantic golden: 30-frame walking_xyz trace is unchanged", "[cli][golden]") {
  dynref::test::CheckMethodGolden("semantic", "golden/semantic_30f", "semantic_golden.yaml");
}
