// A program that uses tagbench as an installed package: it renders a tag of a family into an 8-bit
// buffer (with padded rows, as a camera driver's buffer may have), detects it and checks the id and
// the corners against where the rendering put them. Built by the tests against an install in a
// temporary prefix, once through find_package (CMakeLists.txt here) and once through pkg-config:
//   c++ -std=c++20 consumer.cpp $(pkg-config --cflags --libs tagbench) -o consumer
// Usage: consumer FAMILY ID. Prints "FAMILY ID x0,y0 x1,y1 x2,y2 x3,y3" (corners TL, TR, BR, BL) and
// exits 0 when the detection is the rendered tag within 0.25 px (and the linked library's version is
// the headers'); 1 otherwise.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include <tagbench/detector.hpp>
#include <tagbench/family.hpp>
#include <tagbench/version.hpp>

int main(int argc, char** argv) try {
  if (argc != 3) {
    std::fprintf(stderr, "usage: consumer FAMILY ID\n");
    return 2;
  }
  const std::string family_name = argv[1];
  const int id = std::atoi(argv[2]);
  const tagbench::TagFamily family = tagbench::load_family(family_name);
  const tagbench::TagCells cells = tagbench::tag_cells(family, id);

  // k pixels per cell, a white margin of m pixels, rows padded to `stride` bytes.
  const int k = 12, m = 30;
  const int width = cells.n * k + 2 * m, height = width, stride = width + 13;
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(stride) * height, 255);
  for (int y = 0; y < cells.n * k; ++y)
    for (int x = 0; x < cells.n * k; ++x)
      pixels[static_cast<std::size_t>(y + m) * stride + (x + m)] = cells.at(y / k, x / k) ? 255 : 0;

  tagbench::DetectorOptions options;
  options.families = {family_name};
  const tagbench::Detector detector(options);
  tagbench::DetectorWorkspace workspace;
  const std::vector<tagbench::Detection> found =
      detector.detect(tagbench::ImageU8View{width, height, stride, pixels.data()}, workspace);

  // The black square spans cells 1 .. n-1; pixel centres are at integer coordinates, so a cell
  // edge at pixel boundary b lies at b - 0.5.
  const double lo = m + k - 0.5, hi = m + (cells.n - 1) * k - 0.5;
  const double expected[4][2] = {{lo, lo}, {hi, lo}, {hi, hi}, {lo, hi}};
  bool ok = found.size() == 1 && found[0].id == id;
  for (const tagbench::Detection& d : found) {
    std::printf("%s %d", d.family.c_str(), d.id);
    for (int i = 0; i < 4; ++i) {
      std::printf(" %.2f,%.2f", d.corners[i].x(), d.corners[i].y());
      ok = ok && std::abs(d.corners[i].x() - expected[i][0]) < 0.25 && std::abs(d.corners[i].y() - expected[i][1]) < 0.25;
    }
    std::printf("\n");
  }
  ok = ok && std::string(tagbench::version()) == TAGBENCH_VERSION_STRING;  // the library the headers describe
  std::printf("tagbench %s (headers %s): %s\n", tagbench::version(), TAGBENCH_VERSION_STRING,
              ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
} catch (const std::exception& e) {
  std::fprintf(stderr, "consumer: %s\n", e.what());
  return 1;
}
