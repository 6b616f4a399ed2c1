#include <catch2/catch.hpp>

#include <fstream>

#include "core/error.h"
#include "io/camera.h"
#include "test_support.h"

using namespace dynref;

TEST_CASE("camera: presets carry the published calibrations") {
  const Camera fr1 = CameraPreset("tum_fr1");
  CHECK(fr1.fx == 517.3);
  CHECK(fr1.fy == 516.5);
  CHECK(fr1.cx == 318.6);
  CHECK(fr1.cy == 255.3);
  CHECK(fr1.k1 == 0.2624);
  CHECK(fr1.k2 == -0.9531);
  CHECK(fr1.p1 == -0.0054);
  CHECK(fr1.p2 == 0.0026);
  CHECK(fr1.k3 == 1.1633);
  CHECK(fr1.depth_factor == 5000.0);
  const Camera fr2 = CameraPreset("tum_fr2");
  CHECK(fr2.fx == 520.9);
  CHECK(fr2.cy == 249.7);
  CHECK(fr2.k3 == 0.9172);
  const Camera fr3 = CameraPreset("tum_fr3");
  CHECK(fr3.fx == 535.4);
  CHECK(!fr3.HasDistortion());
  const Camera bonn = CameraPreset("bonn");
  CHECK(bonn.fx == 542.822841);
  CHECK(bonn.fy == 542.576870);
  CHECK(bonn.cx == 315.593520);
  CHECK(bonn.cy == 237.756098);
  CHECK(bonn.k1 == 0.039903);
  CHECK(bonn.k2 == -0.099343);
  CHECK(bonn.p1 == -0.000730);
  CHECK(bonn.p2 == -0.000144);
  CHECK(bonn.k3 == 0.0);
  CHECK(bonn.depth_factor == 5000.0);
  const Camera syn = CameraPreset("synthetic");
  CHECK(syn.fx == 535.4);
  CHECK(syn.fy == 539.2);
  CHECK(syn.cx == 320.1);
  CHECK(syn.cy == 247.6);
  CHECK(!syn.HasDistortion());
  CHECK(syn.width == 640);
  CHECK(syn.height == 480);
  CHECK_THROWS_AS(CameraPreset("tum_fr4"), InputError);
  CHECK(IsCameraPresetName("bonn"));
  CHECK(!IsCameraPresetName("Bonn"));
}

TEST_CASE("camera: ORB-SLAM2 YAML round trip and missing keys") {
  const std::string dir = test::ScratchDir("io_camera_yaml");
  Camera c = CameraPreset("tum_fr2");
  c.width = 320;
  c.height = 240;
  c.cx = 160.5;  // the principal point must lie inside the (smaller) image
  c.cy = 120.25;
  c.bf = 41.5;
  c.th_depth = 35.0;
  c.depth_factor = 1000.0;
  WriteOrbSlamCameraYaml(c, dir + "/camera.yaml");
  const Camera r = ReadOrbSlamCameraYaml(dir + "/camera.yaml");
  CHECK(r.fx == c.fx);
  CHECK(r.fy == c.fy);
  CHECK(r.cx == c.cx);
  CHECK(r.cy == c.cy);
  CHECK(r.k1 == c.k1);
  CHECK(r.k2 == c.k2);
  CHECK(r.p1 == c.p1);
  CHECK(r.p2 == c.p2);
  CHECK(r.k3 == c.k3);
  CHECK(r.width == 320);
  CHECK(r.height == 240);
  CHECK(r.bf == 41.5);
  CHECK(r.th_depth == 35.0);
  CHECK(r.depth_factor == 1000.0);

  // An ORB-SLAM2 TUM1.yaml as distributed (no width/height keys would also be accepted).
  {
    std::ofstream f(dir + "/TUM1.yaml");
    f << "%YAML:1.0\nCamera.fx: 517.306408\nCamera.fy: 516.469215\nCamera.cx: 318.643040\n"
         "Camera.cy: 255.313989\nCamera.k1: 0.262383\nCamera.k2: -0.953104\n"
         "Camera.p1: -0.005358\nCamera.p2: 0.002628\nCamera.k3: 1.163314\n"
         "Camera.width: 640\nCamera.height: 480\nCamera.fps: 30.0\nCamera.bf: 40.0\n"
         "Camera.RGB: 1\nThDepth: 40.0\nDepthMapFactor: 5000.0\n";
  }
  const Camera t1 = ReadOrbSlamCameraYaml(dir + "/TUM1.yaml");
  CHECK(t1.fx == 517.306408);
  CHECK(t1.k3 == 1.163314);
  CHECK(t1.depth_factor == 5000.0);

  {
    std::ofstream f(dir + "/nofx.yaml");
    f << "%YAML:1.0\nCamera.fy: 516.5\nCamera.cx: 318.6\nCamera.cy: 255.3\nCamera.k1: 0\n"
         "Camera.k2: 0\nCamera.p1: 0\nCamera.p2: 0\nDepthMapFactor: 5000.0\n";
  }
  try {
    ReadOrbSlamCameraYaml(dir + "/nofx.yaml");
    FAIL("no error for a missing key");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("nofx.yaml") != std::string::npos);
    CHECK(std::string(e.what()).find("Camera.fx") != std::string::npos);
  }
  CHECK_THROWS_AS(ReadOrbSlamCameraYaml(dir + "/missing.yaml"), InputError);
}

TEST_CASE("camera: ORB-SLAM2 YAML out-of-range values and duplicate keys name file and line") {
  const std::string dir = test::ScratchDir("io_camera_yaml_bad");
  // ORB-SLAM2 TUM1.yaml, one key a line: Camera.cx is line 4, Camera.fps line 13.
  const std::string good =
      "%YAML:1.0\nCamera.fx: 517.3\nCamera.fy: 516.5\nCamera.cx: 318.6\nCamera.cy: 255.3\n"
      "Camera.k1: 0\nCamera.k2: 0\nCamera.p1: 0\nCamera.p2: 0\nCamera.k3: 0\n"
      "Camera.width: 640\nCamera.height: 480\nCamera.fps: 30.0\nCamera.bf: 40.0\n"
      "Camera.RGB: 1\nThDepth: 40.0\nDepthMapFactor: 5000.0\n";
  const std::string ok = test::WriteText(dir + "/ok.yaml", good);
  CHECK(ReadOrbSlamCameraYaml(ok).cx == 318.6);
  struct Case {
    std::string from, to, fragment;
  };
  const Case cases[] = {
      {"Camera.bf: 40.0", "Camera.bf: -1", ":14: Camera.bf must be positive"},
      {"Camera.cx: 318.6", "Camera.cx: 5000", ":4: Camera.cx must lie inside the image"},
      {"Camera.cx: 318.6", "Camera.cx: -0.5", ":4: Camera.cx must lie inside the image"},
      {"Camera.cy: 255.3", "Camera.cy: 480", ":5: Camera.cy must lie inside the image"},
      {"Camera.RGB: 1", "Camera.RGB: 7", ":15: Camera.RGB must be 0 (BGR) or 1 (RGB)"},
      {"Camera.fps: 30.0", "Camera.fps: 0", ":13: Camera.fps must be positive"},
      {"Camera.width: 640", "Camera.width: 1e12", ":11: Camera.width must be an integer"},
      {"Camera.fy: 516.5", "Camera.fy: 0", ":3: Camera.fy must be positive"},
      // Issue 37: ThDepth -1 was accepted; every value has an upper bound too.
      {"ThDepth: 40.0", "ThDepth: -1", ":16: ThDepth must be positive"},
      {"ThDepth: 40.0", "ThDepth: 0", ":16: ThDepth must be positive"},
      {"ThDepth: 40.0", "ThDepth: 1e308", ":16: ThDepth must be positive (close points are nearer than ThDepth baselines) and at most 10000.0, got 1e+308"},
      {"Camera.fx: 517.3", "Camera.fx: 1e300", ":2: Camera.fx must be positive and at most 1000000"},
      {"DepthMapFactor: 5000.0", "DepthMapFactor: 5000.0\nCamera.fx: 600.0",
       ":18: duplicate key 'Camera.fx' (first given at line 2)"},
  };
  int n = 0;
  for (const Case& c : cases) {
    std::string text = good;
    REQUIRE(text.find(c.from) != std::string::npos);
    text.replace(text.find(c.from), c.from.size(), c.to);
    const std::string path = test::WriteText(dir + "/bad" + std::to_string(n++) + ".yaml", text);
    INFO(c.to);
    try {
      ReadOrbSlamCameraYaml(path);
      FAIL("no error");
    } catch (const InputError& e) {
      CHECK(std::string(e.what()).find(path + c.fragment) != std::string::npos);
    }
  }
  using Catch::Matchers::Contains;
  CHECK_THROWS_WITH(ReadOrbSlamCameraYaml(dir),
                    Contains(dir + ": camera YAML is not a regular file"));
  CHECK_THROWS_WITH(ReadOrbSlamCameraYaml(dir + "/nope.yaml"),
                    Contains(dir + "/nope.yaml: camera YAML not found"));
}

TEST_CASE("camera: a YAML whose top level is a list or a scalar is refused by name (fuzz finding)") {
  const std::string dir = test::ScratchDir("camera_yaml_top_level");
  // Found by scripts/fuzz.sh: cv::FileStorage asserted isMap() in operator[] on these.
  for (const std::string& text : {std::string("%YAML:1.0\n- Camera.fx: 535.4\n- Camera.fy: 539.2\n"),
                                 std::string("%YAML:1.0\n--- 42\n"), std::string("%YAML:1.0\n[1, 2, 3]\n")}) {
    INFO(text);
    const std::string path = test::WriteText(dir + "/top.yaml", text);
    try {
      ReadOrbSlamCameraYaml(path);
      FAIL("no error");
    } catch (const InputError& e) {
      CHECK(std::string(e.what()).find(path) != std::string::npos);
    }
  }
}
