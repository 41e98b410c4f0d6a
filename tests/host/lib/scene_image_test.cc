// Tissues from greyscale PGM images: P2 and P5 (one and two bytes a pixel) to the same map with
// the image's top row at the largest y, and every bad image named by what is wrong where.
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "palpa/host/scene_image.h"

#include "CppUTest/TestHarness.h"
#include "text_checks.h"

namespace ph = palpa::host;

namespace {

const ph::ImageScale kScale{"img", "kPa", 0.5, 10, 30};

std::string RefusedImage(const std::string& bytes, const ph::ImageScale& scale = kScale) {
  const auto m = ph::ParseTissueImage(bytes, scale, "map.pgm");
  CHECK_TEXT(!m.ok(), "accepted");
  return m.message;
}

}  // namespace

TEST_GROUP(SceneImage){};

TEST(SceneImage, GreyBecomesStiffnessWithTheTopRowAtTheLargestY) {
  // 3 × 2: top row black, grey, white; bottom row white, black, white.
  const std::string p2 = "P2\n# a comment\n3 2\n4\n0 2 4\n4 0 4\n";
  const auto m = ph::ParseTissueImage(p2, kScale, "map.pgm");
  CHECK_TEXT(m.ok(), m.message.c_str());
  LONGS_EQUAL(3, m.value.nx);
  LONGS_EQUAL(2, m.value.ny);
  DOUBLES_EQUAL(0.5, m.value.pitch_x_mm, 0);
  STRCMP_EQUAL("kPa", m.value.unit.c_str());
  DOUBLES_EQUAL(10, m.value.At(0, 1), 1e-12);  // top-left: black, at y = 0.5 mm
  DOUBLES_EQUAL(20, m.value.At(1, 1), 1e-12);
  DOUBLES_EQUAL(30, m.value.At(0, 0), 1e-12);  // bottom-left: white, at y = 0
  // The same image as P5, one byte a pixel, and two bytes a pixel (maxval above 255).
  const std::string p5 = std::string("P5 3 2 4\n") + std::string("\0\2\4\4\0\4", 6);
  const auto b = ph::ParseTissueImage(p5, kScale, "map.pgm");
  CHECK_TEXT(b.ok(), b.message.c_str());
  CHECK(b.value.values == m.value.values);
  const std::string wide =
      std::string("P5\n3 2\n1000\n") + std::string("\0\0\1\xF4\3\xE8\3\xE8\0\0\3\xE8", 12);
  const auto w = ph::ParseTissueImage(wide, kScale, "map.pgm");
  CHECK_TEXT(w.ok(), w.message.c_str());
  CHECK(w.value.values == m.value.values);
}

TEST(SceneImage, EveryBadImageIsNamed) {
  CHECK_STARTS(RefusedImage("P6 3 2 255\n"),
               "map.pgm: not a greyscale PGM image (it starts \"P6\"");
  CHECK_STARTS(RefusedImage("\x89PNG"), "map.pgm: not a greyscale PGM image");
  CHECK_STARTS(RefusedImage("P2 1 2 4\n0\n0\n"), "map.pgm: header: width 1 is not 2 … 1024");
  CHECK_STARTS(RefusedImage("P2 3 2000 4\n"), "map.pgm: header: height 2000 is not 2 … 1024");
  CHECK_STARTS(RefusedImage("P2 3 2 0\n"), "map.pgm: header: maxval 0 is not 1 … 65535");
  CHECK_STARTS(RefusedImage("P2 3 x 4\n"), "map.pgm: header: height -1");
  CHECK_STARTS(RefusedImage("P2 3 2 4\n0 2 4\n4 9 4\n"),
               "map.pgm: pixel (1, 1): 9 is above the maxval 4");
  CHECK_STARTS(RefusedImage("P2 3 2 4\n0 2 4\n4 0\n"),
               "map.pgm: pixel (2, 1): missing or not a number");
  CHECK_STARTS(RefusedImage("P2 3 2 4\n0 2 4\n4 0 -4\n"), "map.pgm: pixel (2, 1): missing");
  CHECK_STARTS(RefusedImage(std::string("P5 3 2 4\n") + std::string("\0\2\4\4", 4)),
               "map.pgm: 4 bytes of pixels, expected 6");
  CHECK_STARTS(RefusedImage(std::string("P5 3 2 4\n") + std::string("\0\2\4\4\5\4", 6)),
               "map.pgm: pixel (1, 1): 5 is above the maxval 4");
  CHECK_STARTS(RefusedImage("P2 3 2 4\n0 2 4\n4 0 4\n", {"i", "kPa", 0, 10, 30}),
               "map.pgm: the scale's mm per pixel 0 is not in (0, 1000]");
}

TEST(SceneImage, ImagesAreReadWithinTheirCap) {
  char pattern[] = "/tmp/palpa-image-XXXXXX";
  const std::string dir = mkdtemp(pattern);
  const std::string path = dir + "/map.pgm";
  std::ofstream(path) << "P2 2 2 1\n0 1\n1 0\n";
  CHECK(ph::LoadTissueImage(path, kScale).ok());
  CHECK(truncate(path.c_str(), ph::kTissueImageLimits.max_bytes + 1) == 0);
  CHECK_STARTS(ph::LoadTissueImage(path, kScale).message, path + ": larger than the 8 MiB limit");
  CHECK(std::system(("rm -rf " + dir).c_str()) == 0);
}
