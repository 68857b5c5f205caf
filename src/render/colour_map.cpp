#include "quadcage/render/colour_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "quadcage/core/errors.h"
#include "quadcage/render/font.h"

namespace quadcage::render {
namespace {

Rgb hsv(double h, double s, double v) {
    h = (h - std::floor(h)) * 6.0;
    const int sector = static_cast<int>(h) % 6;
    const double f = h - std::floor(h);
    const double p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
    switch (sector) {
        case 0: return rgb_from_unit(v, t, p);
        case 1: return rgb_from_unit(q, v, p);
        case 2: return rgb_from_unit(p, v, t);
        case 3: return rgb_from_unit(p, q, v);
        case 4: return rgb_from_unit(t, p, v);
        default: return rgb_from_unit(v, p, q);
    }
}

double distance(Rgb a, Rgb b) {
    const double dr = a.r - b.r, dg = a.g - b.g, db = a.b - b.b;
    return std::sqrt(dr * dr + dg * dg + db * db);
}

}  // namespace

Rgb palette_colour(int index) {
    QC_CHECK(index >= 0, "palette_colour: negative index");
    constexpr double kGolden = 0.6180339887498949;
    static const double sat[3] = {0.55, 0.75, 0.40};
    static const double val[3] = {0.95, 0.80, 0.90};
    const int level = (index / 7) % 3;
    return hsv(0.08 + index * kGolden, sat[level], val[level]);
}

std::vector<Rgb> patch_colours(const std::vector<std::vector<int>>& adjacency, double min_distance) {
    const int n = static_cast<int>(adjacency.size());
    std::vector<Rgb> colours(n);
    std::vector<bool> done(n, false);
    for (int p = 0; p < n; ++p) {
        // Past 64 tries the closest-call wins: a patch with very many neighbours still gets a colour.
        int best = p;
        double best_gap = -1;
        for (int k = 0; k < 64; ++k) {
            const Rgb c = palette_colour(p + k);
            double gap = 1e9;
            for (int q : adjacency[p])
                if (q >= 0 && q < n && q != p && done[q]) gap = std::min(gap, distance(c, colours[q]));
            if (gap > best_gap) {
                best_gap = gap;
                best = p + k;
            }
            if (gap >= min_distance) break;
        }
        colours[p] = palette_colour(best);
        done[p] = true;
    }
    return colours;
}

Rgb sequential_colour(double t) {
    static const double anchors[][3] = {{0.267, 0.005, 0.329}, {0.230, 0.322, 0.546}, {0.128, 0.567, 0.551},
                                        {0.369, 0.789, 0.383}, {0.993, 0.906, 0.144}};
    constexpr int n = 5;
    if (!(t > 0)) t = 0;  // NaN -> 0
    t = std::min(t, 1.0) * (n - 1);
    const int i = std::min(static_cast<int>(t), n - 2);
    const double f = t - i;
    return rgb_from_unit(anchors[i][0] + (anchors[i + 1][0] - anchors[i][0]) * f,
                         anchors[i][1] + (anchors[i + 1][1] - anchors[i][1]) * f,
                         anchors[i][2] + (anchors[i + 1][2] - anchors[i][2]) * f);
}

std::vector<double> nice_ticks(double lo, double hi, int target) {
    QC_CHECK(std::isfinite(lo) && std::isfinite(hi) && lo < hi && target >= 1, "nice_ticks: bad range");
    const double raw = (hi - lo) / target;
    const double mag = std::pow(10.0, std::floor(std::log10(raw)));
    const double frac = raw / mag;
    const double step = (frac < 1.5 ? 1 : frac < 3.5 ? 2 : frac < 7.5 ? 5 : 10) * mag;
    std::vector<double> ticks;
    const long long first = static_cast<long long>(std::ceil(lo / step - 1e-9));
    for (long long k = first;; ++k) {
        const double v = k * step;
        if (v > hi + step * 1e-9) break;
        ticks.push_back(std::abs(v) < step * 1e-9 ? 0.0 : v);
    }
    return ticks;
}

std::string format_tick(double value) {
    char buf[32];
    const double a = std::abs(value);
    if (a != 0 && (a < 1e-3 || a >= 1e5)) std::snprintf(buf, sizeof buf, "%.2g", value);
    else std::snprintf(buf, sizeof buf, "%.3g", value);
    return buf;
}

void draw_colour_bar(Image& image, int x, int y, int w, int h, const ColourBarOptions& o) {
    QC_CHECK(o.max_value > 0 && std::isfinite(o.max_value), "draw_colour_bar: max_value must be positive");
    const int line = text_line_height(1);
    const int bar_w = std::max(12, w / 6);
    const int top = y + line + 4, bottom = y + h - (o.secondary_title.empty() ? 4 : line + 8);
    if (bottom - top < 10) return;
    draw_text(image, x, y, o.title, o.text_colour);
    for (int py = top; py < bottom; ++py) {
        const double t = 1.0 - (py - top + 0.5) / (bottom - top);
        image.fill_rect(x, py, x + bar_w, py + 1, sequential_colour(t));
    }
    // Frame.
    image.fill_rect(x - 1, top - 1, x + bar_w + 1, top, o.text_colour);
    image.fill_rect(x - 1, bottom, x + bar_w + 1, bottom + 1, o.text_colour);
    image.fill_rect(x - 1, top - 1, x, bottom + 1, o.text_colour);
    image.fill_rect(x + bar_w, top - 1, x + bar_w + 1, bottom + 1, o.text_colour);
    for (double v : nice_ticks(0.0, o.max_value, 5)) {
        const int py = bottom - static_cast<int>(std::lround(v / o.max_value * (bottom - top)));
        image.fill_rect(x + bar_w, py, x + bar_w + 5, py + 1, o.text_colour);
        std::string label = format_tick(v);
        if (o.secondary_scale > 0) label += "  " + format_tick(v * o.secondary_scale) + o.secondary_suffix;
        draw_text(image, x + bar_w + 8, py - 4, label, o.text_colour);
    }
    if (!o.secondary_title.empty()) draw_text(image, x, bottom + 6, o.secondary_title, o.text_colour);
}

}  // namespace quadcage::render
