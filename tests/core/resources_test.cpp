// core/resources.h (issue 37 item 7): the one place that says where configs/ and models/ are.
#include <catch2/catch.hpp>
#include <cstdlib>

#include "core/resources.h"
#include "test_support.h"

TEST_CASE("resources: a build-tree executable uses the source tree, DYNREF_DATA_DIR overrides") {
  ::unsetenv("DYNREF_DATA_DIR");
  // This test executable has no ../share/dynref beside it: the source tree it was built from.
  CHECK(dynref::ResourceDir() == std::string(DYNREF_SOURCE_DIR));
  CHECK(dynref::ResourcePath("configs/orb.yaml") == dynref::test::SourcePath("configs/orb.yaml"));
  CHECK(dynref::test::FileExists(dynref::ResourcePath("configs/orb.yaml")));
  CHECK_FALSE(dynref::ExecutableDir().empty());
  ::setenv("DYNREF_DATA_DIR", "/opt/somewhere/share/dynref", 1);
  CHECK(dynref::ResourcePath("models/nanodet.onnx") == "/opt/somewhere/share/dynref/models/nanodet.onnx");
  ::unsetenv("DYNREF_DATA_DIR");
}
