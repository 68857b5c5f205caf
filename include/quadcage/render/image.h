#pragma once
// An 8-bit RGB raster image, drawing primitives on it, and PNG files.

#include <cstdint>
#include <string>
#include <vector>

namespace quadcage::render {

/// An sRGB colour, 8 bits per channel.
struct Rgb {
    std::uint8_t r = 0, g = 0, b = 0;
    bool operator==(const Rgb& o) const { return r == o.r && g == o.g && b == o.b; }
    bool operator!=(const Rgb& o) const { return !(*this == o); }
};

/// Colour from channels in [0, 1] (clamped, rounded to nearest).
Rgb rgb_from_unit(double r, double g, double b);

/// A width x height RGB image, rows from top to bottom, pixels left to right.
class Image {
public:
    /// A blank image filled with `background`.
    /// \throw InvalidInput if width or height is not in [1, 32768].
    Image(int width, int height, Rgb background = {255, 255, 255});

    int width() const { return width_; }    ///< Pixels per row.
    int height() const { return height_; }  ///< Rows.
    /// Pixel (x, y); \pre 0 <= x < width, 0 <= y < height.
    Rgb at(int x, int y) const { return pixels_[static_cast<size_t>(y) * width_ + x]; }
    /// Sets pixel (x, y); coordinates outside the image are ignored.
    void set(int x, int y, Rgb c) {
        if (x >= 0 && y >= 0 && x < width_ && y < height_) pixels_[static_cast<size_t>(y) * width_ + x] = c;
    }
    /// Alpha-blends `c` over pixel (x, y) with coverage `alpha` in [0, 1]; outside pixels ignored.
    void blend(int x, int y, Rgb c, double alpha);
    /// Fills the rectangle [x0, x1) x [y0, y1) (clipped to the image).
    void fill_rect(int x0, int y0, int x1, int y1, Rgb c);
    /// Draws a line of width `width` pixels from (x0, y0) to (x1, y1), anti-aliased.
    void draw_line(double x0, double y0, double x1, double y1, Rgb c, double width = 1.0);
    /// Copies `src` with its top-left corner at (x, y) (clipped).
    void paste(const Image& src, int x, int y);
    /// Number of pixels whose colour differs from `c`.
    long long count_not(Rgb c) const;
    /// Number of pixels of exactly colour `c`.
    long long count(Rgb c) const;

    const std::vector<Rgb>& pixels() const { return pixels_; }  ///< Row-major, width * height.

private:
    int width_, height_;
    std::vector<Rgb> pixels_;
};

/// Box-filter downsampling by an integer `factor` (>= 1) in both directions (anti-aliasing of a
/// supersampled render). \pre the image size is a multiple of `factor`.
Image downsample(const Image& image, int factor);

/// The PNG encoding of `image` (8-bit RGB, no ancillary chunks, fixed compression: the same image
/// always gives the same bytes).
std::string encode_png(const Image& image);

/// Writes `image` as a PNG to `path` atomically (temporary file + rename).
/// \throw InvalidInput (naming `path`) if the file cannot be written.
void write_png(const std::string& path, const Image& image);

/// Reads an 8-bit (or 16-bit, reduced) RGB/RGBA/grey PNG; alpha is dropped.
/// \throw InvalidInput (naming `path`) if the file cannot be read or is not a PNG.
Image read_png(const std::string& path);

}  // namespace quadcage::render
