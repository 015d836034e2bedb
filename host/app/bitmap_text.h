#pragma once
// Text drawn into RGB images (the legends of false-colour pictures, the labels of calculation-grid
// pictures, app/grid_picture.h): a 5 x 7 pixel font of digits, lower- and upper-case letters and
// the signs units, numbers and names need (. , ; : - + / ( ) [ ] = ^ % < > _ ! ? ' * #), each glyph
// pixel drawn as scale x scale image pixels, advancing 6 glyph pixels per character. Characters
// without a glyph are drawn as an outlined box, so a missing one shows.
#include <string>

#include <glm/vec3.hpp>

#include "core/image.h"

namespace nf::app {

struct TextStyle {
  int scale = 2;           // image pixels per glyph pixel
  glm::vec3 colour{1.0f};  // linear display values in [0, 1]
};

// Width and height in image pixels of `text` in one line.
int text_width(const std::string& text, const TextStyle& style = {});
int text_height(const TextStyle& style = {});
// Draws `text` with its top-left corner at (x, y) (pixels outside the image are skipped). The
// image must have 3 channels.
void draw_text(Image& image, int x, int y, const std::string& text, const TextStyle& style = {});
// True when every character of `text` has a glyph.
bool has_glyphs(const std::string& text);

}  // namespace nf::app
