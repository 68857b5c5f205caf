#pragma once
// A built-in 5x7 bitmap font (printable ASCII, with descenders) for labels on rendered images.

#include <string>

#include "quadcage/render/image.h"

namespace quadcage::render {

/// Height of one text line in pixels at `scale` (glyph cell plus spacing).
int text_line_height(int scale = 1);

/// Width in pixels of `text` drawn at `scale` (6 * scale per character; no kerning).
int text_width(const std::string& text, int scale = 1);

/// Draws `text` with its top-left corner at (x, y), each font pixel a `scale` x `scale` square.
/// Characters outside printable ASCII are drawn as '?'. Pixels outside the image are clipped.
void draw_text(Image& image, int x, int y, const std::string& text, Rgb colour, int scale = 1);

/// Draws `text` rotated 90 degrees counter-clockwise (reading bottom to top) with the top-left corner
/// of its bounding box at (x, y); for vertical axis titles.
void draw_text_vertical(Image& image, int x, int y, const std::string& text, Rgb colour, int scale = 1);

}  // namespace quadcage::render
