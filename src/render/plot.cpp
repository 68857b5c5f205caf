#include "quadcage/render/plot.h"

#include <algorithm>
#include <cmath>

#include "quadcage/core/errors.h"
#include "quadcage/render/colour_map.h"
#include "quadcage/render/font.h"

namespace quadcage::render {
namespace {

constexpr int kLegendWidth = 190;
const Rgb kInk{30, 30, 30};
const Rgb kGrid{225, 225, 225};

bool plottable(double x, double y) { return x > 0 && y > 0 && std::isfinite(x) && std::isfinite(y); }

std::string decade_label(int e) {
    if (e >= 0 && e <= 4) {
        std::string s = "1";
        s.append(static_cast<size_t>(e), '0');
        return s;
    }
    if (e < 0 && e >= -3) return "0." + std::string(static_cast<size_t>(-e - 1), '0') + "1";
    return "1e" + std::to_string(e);
}

}  // namespace

std::string PlotOptions::validate() const {
    if (width < 200 || height < 150 || width > 16384 || height > 16384)
        return "plot size must be at least 200x150 and at most 16384 per side";
    return {};
}

double LogAxes::px(double x) const {
    return left + (std::log10(x) - std::log10(x_lo)) / (std::log10(x_hi) - std::log10(x_lo)) * (right - left);
}

double LogAxes::py(double y) const {
    return bottom - (std::log10(y) - std::log10(y_lo)) / (std::log10(y_hi) - std::log10(y_lo)) * (bottom - top);
}

Rgb series_colour(int index) {
    static const Rgb fixed[] = {{31, 119, 180}, {255, 127, 14}, {44, 160, 44},  {214, 39, 40},  {148, 103, 189},
                                {140, 86, 75},  {227, 119, 194}, {127, 127, 127}, {188, 189, 34}, {23, 190, 207}};
    if (index >= 0 && index < 10) return fixed[index];
    return palette_colour(index);
}

LogAxes log_log_axes(const std::vector<Series>& series, const PlotOptions& o) {
    LogAxes a;
    a.left = 70;
    a.top = 36;
    a.right = o.width - kLegendWidth - 20;
    a.bottom = o.height - 50;
    double xmin = HUGE_VAL, xmax = -HUGE_VAL, ymin = HUGE_VAL, ymax = -HUGE_VAL;
    for (const Series& s : series)
        for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
            if (plottable(s.x[i], s.y[i])) {
                xmin = std::min(xmin, s.x[i]);
                xmax = std::max(xmax, s.x[i]);
                ymin = std::min(ymin, s.y[i]);
                ymax = std::max(ymax, s.y[i]);
            }
    auto decades = [](double lo, double hi, double& out_lo, double& out_hi) {
        if (!(lo <= hi)) {
            out_lo = 1;
            out_hi = 10;
            return;
        }
        int e0 = static_cast<int>(std::floor(std::log10(lo) + 1e-12));
        int e1 = static_cast<int>(std::ceil(std::log10(hi) - 1e-12));
        if (e1 <= e0) e1 = e0 + 1;
        out_lo = std::pow(10.0, e0);
        out_hi = std::pow(10.0, e1);
    };
    decades(xmin, xmax, a.x_lo, a.x_hi);
    decades(ymin, ymax, a.y_lo, a.y_hi);
    return a;
}

Image plot_log_log(const std::vector<Series>& series, const PlotOptions& o) {
    if (const std::string e = o.validate(); !e.empty()) throw InvalidInput("plot options: " + e);
    for (const Series& s : series)
        if (s.x.size() != s.y.size())
            throw InvalidInput("plot: series '" + s.name + "' has " + std::to_string(s.x.size()) + " x values and " +
                               std::to_string(s.y.size()) + " y values");
    Image img(o.width, o.height);
    const LogAxes a = log_log_axes(series, o);
    const int ex0 = static_cast<int>(std::lround(std::log10(a.x_lo))), ex1 = static_cast<int>(std::lround(std::log10(a.x_hi)));
    const int ey0 = static_cast<int>(std::lround(std::log10(a.y_lo))), ey1 = static_cast<int>(std::lround(std::log10(a.y_hi)));

    // Grid: decades solid, 2..9 between them lighter.
    for (int e = ex0; e <= ex1; ++e)
        for (int m = 1; m <= 9 && (e < ex1 || m == 1); ++m) {
            const int x = static_cast<int>(std::lround(a.px(m * std::pow(10.0, e))));
            img.fill_rect(x, a.top, x + 1, a.bottom, m == 1 ? kGrid : Rgb{242, 242, 242});
        }
    for (int e = ey0; e <= ey1; ++e)
        for (int m = 1; m <= 9 && (e < ey1 || m == 1); ++m) {
            const int y = static_cast<int>(std::lround(a.py(m * std::pow(10.0, e))));
            img.fill_rect(a.left, y, a.right, y + 1, m == 1 ? kGrid : Rgb{242, 242, 242});
        }
    // Axes, ticks and labels.
    img.fill_rect(a.left, a.bottom, a.right + 1, a.bottom + 1, kInk);
    img.fill_rect(a.left, a.top, a.left + 1, a.bottom + 1, kInk);
    for (int e = ex0; e <= ex1; ++e) {
        const int x = static_cast<int>(std::lround(a.px(std::pow(10.0, e))));
        img.fill_rect(x, a.bottom, x + 1, a.bottom + 6, kInk);
        const std::string l = decade_label(e);
        draw_text(img, x - text_width(l) / 2, a.bottom + 10, l, kInk);
    }
    for (int e = ey0; e <= ey1; ++e) {
        const int y = static_cast<int>(std::lround(a.py(std::pow(10.0, e))));
        img.fill_rect(a.left - 6, y, a.left, y + 1, kInk);
        const std::string l = decade_label(e);
        draw_text(img, a.left - 10 - text_width(l), y - 4, l, kInk);
    }
    draw_text(img, (a.left + a.right - text_width(o.x_label)) / 2, a.bottom + 28, o.x_label, kInk);
    draw_text_vertical(img, 8, (a.top + a.bottom - text_width(o.y_label)) / 2, o.y_label, kInk);
    draw_text(img, (a.left + a.right - text_width(o.title, 2)) / 2, 8, o.title, kInk, 2);

    // Data.
    for (size_t k = 0; k < series.size(); ++k) {
        const Series& s = series[k];
        const Rgb c = series_colour(static_cast<int>(k));
        bool have_prev = false;
        double prev_x = 0, prev_y = 0;
        for (size_t i = 0; i < s.x.size(); ++i) {
            if (!plottable(s.x[i], s.y[i])) {
                have_prev = false;
                continue;
            }
            const double x = a.px(s.x[i]), y = a.py(s.y[i]);
            if (have_prev) img.draw_line(prev_x, prev_y, x, y, c, 2.0);
            prev_x = x;
            prev_y = y;
            have_prev = true;
        }
        for (size_t i = 0; i < s.x.size(); ++i)
            if (plottable(s.x[i], s.y[i])) {
                const double x = a.px(s.x[i]), y = a.py(s.y[i]);
                img.draw_line(x, y, x, y, c, 8.0);
            }
    }
    // Legend (names cut to fit).
    const int lx = a.right + 20;
    int ly = a.top;
    for (size_t k = 0; k < series.size() && ly + 12 < o.height; ++k) {
        const Rgb c = series_colour(static_cast<int>(k));
        img.draw_line(lx, ly + 4, lx + 22, ly + 4, c, 2.0);
        img.draw_line(lx + 11, ly + 4, lx + 11, ly + 4, c, 7.0);
        std::string name = series[k].name;
        const size_t room = static_cast<size_t>((kLegendWidth - 30) / 6);
        if (name.size() > room) name = name.substr(0, room - 2) + "..";
        draw_text(img, lx + 28, ly, name, kInk);
        ly += 16;
    }
    return img;
}

}  // namespace quadcage::render
