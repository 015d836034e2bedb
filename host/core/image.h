#pragma once
// A linear float image, interleaved channels, rows top to bottom.
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace nf {

struct Image {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<float> pixels;  // width * height * channels

  Image() = default;
  Image(int w, int h, int c) : width(w), height(h), channels(c), pixels(static_cast<std::size_t>(w) * h * c, 0.0f) {}
  float& at(int x, int y, int c) { return pixels[(static_cast<std::size_t>(y) * width + x) * channels + c]; }
  float at(int x, int y, int c) const { return pixels[(static_cast<std::size_t>(y) * width + x) * channels + c]; }
};

// String metadata written into (and read back from) the file's header.
using ImageAttributes = std::vector<std::pair<std::string, std::string>>;

}  // namespace nf
