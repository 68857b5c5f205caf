#include "quadcage/render/image.h"

#include <algorithm>
#include <cmath>
#include <png.h>

#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"

namespace quadcage::render {
namespace {

std::uint8_t to_byte(double v) {
    return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0));
}

}  // namespace

Rgb rgb_from_unit(double r, double g, double b) { return {to_byte(r), to_byte(g), to_byte(b)}; }

Image::Image(int width, int height, Rgb background) : width_(width), height_(height) {
    if (width < 1 || height < 1 || width > 32768 || height > 32768)
        throw InvalidInput("image size " + std::to_string(width) + "x" + std::to_string(height) +
                           " is out of range (1..32768 per side)");
    pixels_.assign(static_cast<size_t>(width) * height, background);
}

void Image::blend(int x, int y, Rgb c, double alpha) {
    if (x < 0 || y < 0 || x >= width_ || y >= height_ || alpha <= 0) return;
    const double a = std::min(alpha, 1.0);
    Rgb& p = pixels_[static_cast<size_t>(y) * width_ + x];
    auto mix = [a](std::uint8_t under, std::uint8_t over) {
        return static_cast<std::uint8_t>(std::lround(under + (over - under) * a));
    };
    p = {mix(p.r, c.r), mix(p.g, c.g), mix(p.b, c.b)};
}

void Image::fill_rect(int x0, int y0, int x1, int y1, Rgb c) {
    x0 = std::max(x0, 0);
    y0 = std::max(y0, 0);
    x1 = std::min(x1, width_);
    y1 = std::min(y1, height_);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) pixels_[static_cast<size_t>(y) * width_ + x] = c;
}

void Image::draw_line(double x0, double y0, double x1, double y1, Rgb c, double width) {
    // Coverage from the distance of each pixel centre to the segment: a one-pixel soft edge.
    const double half = width / 2;
    const int xa = static_cast<int>(std::floor(std::min(x0, x1) - half - 1));
    const int xb = static_cast<int>(std::ceil(std::max(x0, x1) + half + 1));
    const int ya = static_cast<int>(std::floor(std::min(y0, y1) - half - 1));
    const int yb = static_cast<int>(std::ceil(std::max(y0, y1) + half + 1));
    const double dx = x1 - x0, dy = y1 - y0, len2 = dx * dx + dy * dy;
    for (int y = std::max(ya, 0); y <= std::min(yb, height_ - 1); ++y) {
        for (int x = std::max(xa, 0); x <= std::min(xb, width_ - 1); ++x) {
            const double px = x + 0.5 - x0, py = y + 0.5 - y0;
            const double t = len2 > 0 ? std::clamp((px * dx + py * dy) / len2, 0.0, 1.0) : 0.0;
            const double ex = px - t * dx, ey = py - t * dy;
            const double d = std::sqrt(ex * ex + ey * ey);
            blend(x, y, c, std::clamp(half + 0.5 - d, 0.0, 1.0));
        }
    }
}

void Image::paste(const Image& src, int x, int y) {
    for (int j = 0; j < src.height(); ++j)
        for (int i = 0; i < src.width(); ++i) set(x + i, y + j, src.at(i, j));
}

long long Image::count_not(Rgb c) const {
    return static_cast<long long>(std::count_if(pixels_.begin(), pixels_.end(), [&](Rgb p) { return p != c; }));
}

long long Image::count(Rgb c) const {
    return static_cast<long long>(std::count(pixels_.begin(), pixels_.end(), c));
}

Image downsample(const Image& image, int factor) {
    QC_CHECK(factor >= 1 && image.width() % factor == 0 && image.height() % factor == 0,
             "downsample: size not a multiple of the factor");
    if (factor == 1) return image;
    Image out(image.width() / factor, image.height() / factor);
    const int n = factor * factor;
    for (int y = 0; y < out.height(); ++y) {
        for (int x = 0; x < out.width(); ++x) {
            int r = 0, g = 0, b = 0;
            for (int j = 0; j < factor; ++j)
                for (int i = 0; i < factor; ++i) {
                    const Rgb p = image.at(x * factor + i, y * factor + j);
                    r += p.r;
                    g += p.g;
                    b += p.b;
                }
            out.set(x, y, {static_cast<std::uint8_t>((r + n / 2) / n), static_cast<std::uint8_t>((g + n / 2) / n),
                           static_cast<std::uint8_t>((b + n / 2) / n)});
        }
    }
    return out;
}

std::string encode_png(const Image& image) {
    // libpng's simplified API: no setjmp, and nothing time-dependent in the output.
    png_image png{};
    png.version = PNG_IMAGE_VERSION;
    png.width = static_cast<png_uint_32>(image.width());
    png.height = static_cast<png_uint_32>(image.height());
    png.format = PNG_FORMAT_RGB;
    static_assert(sizeof(Rgb) == 3, "Rgb must be packed");
    const void* buffer = image.pixels().data();
    png_alloc_size_t size = 0;
    if (!png_image_write_to_memory(&png, nullptr, &size, 0, buffer, 0, nullptr))
        throw InternalError(std::string("PNG encoding failed: ") + png.message);
    std::string out(size, '\0');
    if (!png_image_write_to_memory(&png, out.data(), &size, 0, buffer, 0, nullptr))
        throw InternalError(std::string("PNG encoding failed: ") + png.message);
    out.resize(size);
    return out;
}

void write_png(const std::string& path, const Image& image) { write_text_file(path, encode_png(image)); }

Image read_png(const std::string& path) {
    png_image png{};
    png.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&png, path.c_str()))
        throw InvalidInput(path + ": cannot read as PNG (" + png.message + ")");
    png.format = PNG_FORMAT_RGB;
    if (png.width < 1 || png.height < 1 || png.width > 32768 || png.height > 32768) {
        png_image_free(&png);
        throw InvalidInput(path + ": PNG size out of range");
    }
    Image out(static_cast<int>(png.width), static_cast<int>(png.height));
    std::vector<Rgb> buffer(static_cast<size_t>(png.width) * png.height);
    if (!png_image_finish_read(&png, nullptr, buffer.data(), 0, nullptr))
        throw InvalidInput(path + ": cannot decode PNG (" + png.message + ")");
    for (int y = 0; y < out.height(); ++y)
        for (int x = 0; x < out.width(); ++x) out.set(x, y, buffer[static_cast<size_t>(y) * out.width() + x]);
    return out;
}

}  // namespace quadcage::render
