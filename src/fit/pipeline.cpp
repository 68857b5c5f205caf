#include <chrono>
#include <utility>

#include "quadcage/core/errors.h"
#include "quadcage/fit/fit.h"

namespace quadcage::fit {

namespace {

// The relative RMS of fit_surface() at options.level, as a score to compare layouts by, not a fit
// to keep: the scheduled rounds only, as before FitOptions::extra_rounds, and no turned-over term,
// as before FitOptions::turned_over_weight, so the layouts the scores choose stay those they chose.
std::function<double(const layout::QuadLayout&)> rms_score(FitOptions options) {
    options.mode = FitMode::Level;
    options.extra_rounds = 0;
    options.turned_over_weight = kScoreTurnedOverWeight;
    options.progress = nullptr;
    if (const std::string e = options.validate(); !e.empty()) throw InvalidInput("fit options: " + e);
    return [options](const layout::QuadLayout& layout) {
        return fit_surface(layout, options).levels.back().relative.rms;
    };
}

}  // namespace

std::function<double(const layout::QuadLayout&)> level1_fit_score(FitOptions options) {
    options.level = 1;
    // The tangential weight it was measured with (FitOptions::tangential_weight was 0.02 then):
    // the scores, and so the S-cycles they choose, stay as they were.
    options.tangential_weight = kScoreTangentialWeight;
    // ... and fewer points: a ranking needs less than a fit to keep (kScorePointsPerFace).
    options.data_points_per_face = options.surface_samples_per_face = kScorePointsPerFace;
    options.error_samples = kScoreErrorSamples;
    return rms_score(std::move(options));
}

std::function<double(const layout::QuadLayout&)> level2_fit_score(FitOptions options) {
    options.level = 2;
    // The fit's own points, samples and weights: with level1_fit_score()'s fewer points, two
    // layouts of a body with 5 handles in a row whose level-2 fits were 2.6% apart scored 25%
    // apart, the wrong way round (README, "Ties broken at level 2").
    return rms_score(std::move(options));
}

CageFit fit_cage(const Mesh& mesh, const layout::QuadLayoutOptions& layout_options,
                 const FitOptions& fit_options, SCycleChoice choice) {
    if (const std::string e = fit_options.validate(); !e.empty()) throw InvalidInput("fit options: " + e);
    using Clock = std::chrono::steady_clock;
    CageFit out;
    const Clock::time_point t0 = Clock::now();
    layout::QuadLayoutOptions chosen_by_fit = layout_options;
    if (choice == SCycleChoice::Fit && !chosen_by_fit.score) chosen_by_fit.score = level1_fit_score();
    if (choice == SCycleChoice::Fit && !chosen_by_fit.tie_score && !layout_options.score)
        chosen_by_fit.tie_score = level2_fit_score();
    out.layout = layout::build_quad_layout(mesh, chosen_by_fit);
    const Clock::time_point t1 = Clock::now();
    out.fit = fit_surface(out.layout, fit_options);
    out.layout_seconds = std::chrono::duration<double>(t1 - t0).count();
    out.fit_seconds = std::chrono::duration<double>(Clock::now() - t1).count();
    return out;
}

}  // namespace quadcage::fit
