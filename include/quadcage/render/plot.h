#pragma once
// Log-log line plots (several series, legend, axes with decade ticks) as images.

#include <string>
#include <vector>

#include "quadcage/render/image.h"

namespace quadcage::render {

/// One line of a plot: points (x[i], y[i]) joined in the given order. Points with a non-positive
/// or non-finite coordinate cannot be shown on log axes and are skipped.
struct Series {
    std::string name;       ///< Legend entry.
    std::vector<double> x;  ///< Same length as y.
    std::vector<double> y;
};

/// Options for plot_log_log().
struct PlotOptions {
    int width = 900;            ///< Pixels; at least 200.
    int height = 600;           ///< Pixels; at least 150.
    std::string title;          ///< Above the plot area.
    std::string x_label;        ///< Below the x axis.
    std::string y_label;        ///< Left of the y axis (vertical text).
    std::string validate() const;  ///< Empty if valid, else what is wrong.
};

/// Where the data go: the plot area in pixels and the axis ranges (whole decades around the data).
struct LogAxes {
    int left = 0, top = 0, right = 0, bottom = 0;  ///< Plot area [left, right] x [top, bottom].
    double x_lo = 1, x_hi = 10, y_lo = 1, y_hi = 10;  ///< Axis ranges (powers of ten).
    double px(double x) const;  ///< Pixel column of data value x.
    double py(double y) const;  ///< Pixel row of data value y.
};

/// The axes plot_log_log() uses for `series` (ranges widened to whole decades; [1, 10] when no point
/// is plottable).
LogAxes log_log_axes(const std::vector<Series>& series, const PlotOptions& options = {});

/// Colour of series number i in plots (deterministic, well separated for the first 10).
Rgb series_colour(int index);

/// Draws the series as lines with dot markers on log-log axes, with decade ticks and labels, light
/// grid lines, axis titles and a legend (to the right of the plot area). Deterministic.
/// \throw InvalidInput if options are invalid or a series has x and y of different lengths.
Image plot_log_log(const std::vector<Series>& series, const PlotOptions& options = {});

}  // namespace quadcage::render
