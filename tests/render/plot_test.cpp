// Log-log plots: decade axes around the data, points where the axes say, legend, validation.

#include <gtest/gtest.h>

#include <cmath>

#include "quadcage/core/errors.h"
#include "quadcage/render/plot.h"

namespace {

using namespace quadcage::render;

TEST(PlotLogLog, AKnownSeriesLandsWhereTheLogAxesSay) {
    const std::vector<Series> s = {{"sphere", {10, 100, 1000}, {0.1, 0.01, 0.001}}};
    PlotOptions o;
    o.x_label = "control points";
    o.y_label = "relative RMS";
    const LogAxes a = log_log_axes(s, o);
    EXPECT_DOUBLE_EQ(a.x_lo, 10);
    EXPECT_DOUBLE_EQ(a.x_hi, 1000);
    EXPECT_DOUBLE_EQ(a.y_lo, 0.001);
    EXPECT_DOUBLE_EQ(a.y_hi, 0.1);
    const Image img = plot_log_log(s, o);
    const Rgb c = series_colour(0);
    // The middle point (100, 0.01) is the centre of the plot area; the ends are its corners.
    const int cx = (a.left + a.right) / 2, cy = (a.top + a.bottom) / 2;
    EXPECT_EQ(img.at(cx, cy), c);
    EXPECT_EQ(img.at(a.left + 1, a.top + 1), c);
    EXPECT_EQ(img.at(a.right - 1, a.bottom - 2), c);
    // Away from the line (the other diagonal) there is no series colour.
    EXPECT_NE(img.at(a.left + 20, a.bottom - 20), c);
    EXPECT_NE(img.at(a.right - 20, a.top + 20), c);
}

TEST(PlotLogLog, SeveralSeriesHaveTheirOwnColoursAndBadPointsAreSkipped) {
    const std::vector<Series> s = {{"a", {10, 100}, {1, 0.1}}, {"b", {10, 100, -1}, {0.5, 0.05, 0.1}}, {"c", {}, {}}};
    const Image img = plot_log_log(s);
    EXPECT_GT(img.count(series_colour(0)), 100);
    EXPECT_GT(img.count(series_colour(1)), 100);
    EXPECT_EQ(plot_log_log(s).pixels(), img.pixels());
    EXPECT_THROW(plot_log_log({{"bad", {1, 2}, {1}}}), quadcage::InvalidInput);
    PlotOptions tiny;
    tiny.width = 10;
    EXPECT_THROW(plot_log_log(s, tiny), quadcage::InvalidInput);
    // Nothing plottable: default decade axes, no throw.
    const LogAxes a = log_log_axes({{"z", {0}, {0}}});
    EXPECT_DOUBLE_EQ(a.x_lo, 1);
    EXPECT_DOUBLE_EQ(a.x_hi, 10);
}

}  // namespace
