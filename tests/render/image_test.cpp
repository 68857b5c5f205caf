// Images: PNG round trip and determinism, atomic writing, the bitmap font, downsampling.

#include <gtest/gtest.h>

#include <filesystem>
#include <unistd.h>

#include "quadcage/core/errors.h"
#include "quadcage/render/font.h"
#include "quadcage/render/image.h"

namespace {

namespace fs = std::filesystem;
using namespace quadcage::render;

Image pattern() {
    Image img(37, 23, {10, 20, 30});
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x)
            if ((x + y) % 3 == 0) img.set(x, y, {static_cast<std::uint8_t>(x * 6), static_cast<std::uint8_t>(y * 10), 200});
    return img;
}

TEST(Png, RoundTripIsExactAndEncodingDeterministic) {
    const fs::path p = fs::temp_directory_path() / ("quadcage_png_test_" + std::to_string(::getpid()) + ".png");
    const Image img = pattern();
    write_png(p.string(), img);
    EXPECT_FALSE(fs::exists(p.string() + ".tmp"));
    const Image back = read_png(p.string());
    EXPECT_EQ(back.width(), 37);
    EXPECT_EQ(back.height(), 23);
    EXPECT_EQ(back.pixels(), img.pixels());
    EXPECT_EQ(encode_png(img), encode_png(pattern()));
    EXPECT_EQ(encode_png(img).substr(1, 3), "PNG");
    fs::remove(p);
    EXPECT_THROW(read_png(p.string()), quadcage::InvalidInput);
    EXPECT_THROW(write_png("/nonexistent-dir/x.png", img), quadcage::InvalidInput);
}

TEST(Font, TextInksInsideItsBox) {
    Image img(200, 40);
    const std::string text = "RMS 1.5e-3 % ok";
    draw_text(img, 10, 5, text, {0, 0, 0});
    const int w = text_width(text);
    EXPECT_EQ(w, static_cast<int>(text.size()) * 6 - 1);
    long long inside = 0;
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x)
            if (img.at(x, y) != Rgb{255, 255, 255}) {
                EXPECT_TRUE(x >= 10 && x < 10 + w && y >= 5 && y < 5 + 9) << x << "," << y;
                ++inside;
            }
    EXPECT_GT(inside, 60);
    // Different characters, different ink; unknown bytes draw as '?'.
    Image a(20, 12), b(20, 12), q(20, 12), u(20, 12);
    draw_text(a, 0, 0, "1", {0, 0, 0});
    draw_text(b, 0, 0, "7", {0, 0, 0});
    draw_text(q, 0, 0, "?", {0, 0, 0});
    draw_text(u, 0, 0, "\x01", {0, 0, 0});
    EXPECT_NE(a.pixels(), b.pixels());
    EXPECT_EQ(q.pixels(), u.pixels());
}

TEST(Image, DownsampleAveragesAndBadSizesThrow) {
    Image img(4, 2, {0, 0, 0});
    img.set(0, 0, {255, 255, 255});
    img.set(1, 1, {255, 255, 255});
    const Image d = downsample(img, 2);
    EXPECT_EQ(d.width(), 2);
    EXPECT_EQ(d.at(0, 0), (Rgb{128, 128, 128}));
    EXPECT_EQ(d.at(1, 0), (Rgb{0, 0, 0}));
    EXPECT_THROW(Image(0, 5), quadcage::InvalidInput);
}

}  // namespace
