// tg-view-png-check: test helper that checks a screenshot. Exits 0 when FILE is a readable PNG
// of the expected size (when given) whose pixels are not all the same colour, 1 otherwise.
//
//   tg-view-png-check FILE [WIDTH HEIGHT]
#include <stb_image.h>

#include <cstdlib>
#include <iostream>
#include <set>
#include <string>

int main(int argc, char** argv) {
  if (argc != 2 && argc != 4) {
    std::cerr << "usage: tg-view-png-check FILE [WIDTH HEIGHT]\n";
    return 2;
  }
  int w = 0, h = 0, channels = 0;
  unsigned char* pixels = stbi_load(argv[1], &w, &h, &channels, 3);
  if (!pixels) {
    std::cerr << argv[1] << ": cannot read PNG: " << stbi_failure_reason() << "\n";
    return 1;
  }
  int code = 0;
  if (argc == 4 && (w != std::atoi(argv[2]) || h != std::atoi(argv[3]))) {
    std::cerr << argv[1] << ": " << w << "x" << h << ", expected " << argv[2] << "x" << argv[3]
              << "\n";
    code = 1;
  }
  // A scene shows many colours; a blank, cleared or failed read-back shows one or two.
  std::set<unsigned> colours;
  for (int i = 0; i < w * h; ++i)
    colours.insert(static_cast<unsigned>(pixels[3 * i]) << 16 |
                   static_cast<unsigned>(pixels[3 * i + 1]) << 8 | pixels[3 * i + 2]);
  stbi_image_free(pixels);
  if (colours.size() < 16) {
    std::cerr << argv[1] << ": only " << colours.size() << " distinct colours\n";
    code = 1;
  }
  if (code == 0)
    std::cout << argv[1] << ": " << w << "x" << h << ", " << colours.size() << " colours\n";
  return code;
}
