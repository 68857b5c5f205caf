#pragma once
// Colours for patches and scalar fields, and the colour bar that labels a scalar map.

#include <string>
#include <vector>

#include "quadcage/render/image.h"

namespace quadcage::render {

/// Colour number `index` (>= 0) of an endless, deterministic palette: hues stepped by the golden
/// ratio of a turn (consecutive entries far apart), cycling through three saturation/value levels.
Rgb palette_colour(int index);

/// One colour per patch such that patches sharing an edge never get the same or a close colour:
/// patch p gets the first palette entry, starting at index p, whose distance (RGB Euclidean) to the
/// colours of its already coloured neighbours is at least `min_distance` (greedy in patch order, so
/// the result is deterministic). `adjacency[p]` lists the neighbours of patch p.
std::vector<Rgb> patch_colours(const std::vector<std::vector<int>>& adjacency, double min_distance = 90.0);

/// A perceptually ordered sequential map of t in [0, 1] (clamped): dark blue, teal, green, yellow
/// (piecewise linear through anchors resembling viridis).
Rgb sequential_colour(double t);

/// Tick positions for an axis over [lo, hi]: multiples of a "nice" step (1, 2 or 5 times a power of
/// ten) giving about `target` ticks, all inside [lo, hi]. \pre lo < hi, both finite.
std::vector<double> nice_ticks(double lo, double hi, int target = 5);

/// Formats a tick value compactly (up to 3 significant digits, exponent form for tiny/huge values).
std::string format_tick(double value);

/// Options for draw_colour_bar().
struct ColourBarOptions {
    double max_value = 1.0;         ///< Value at the top of the bar (the bottom is 0); > 0.
    std::string title;              ///< Drawn above the bar (e.g. "distance").
    double secondary_scale = 0.0;   ///< If > 0, each tick also shows value * secondary_scale ...
    std::string secondary_suffix;   ///< ... followed by this (e.g. "%" for percent of the diagonal).
    std::string secondary_title;    ///< Title of the secondary labels, drawn below the bar.
    Rgb text_colour{30, 30, 30};    ///< Labels and frame.
};

/// Draws a vertical colour bar of sequential_colour() from 0 (bottom) to options.max_value (top)
/// into the rectangle of width `w` and height `h` at (x, y): the bar, its frame, nice ticks labelled
/// with the value (and the secondary value), and the titles.
void draw_colour_bar(Image& image, int x, int y, int w, int h, const ColourBarOptions& options);

}  // namespace quadcage::render
