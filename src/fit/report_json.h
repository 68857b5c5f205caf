#pragma once
// FitReport as a JSON object (private to src/fit). A template over the JSON type: nlohmann's
// ordered_json keeps the insertion order below (FitReport::to_json(), write_fit_outputs()), and
// nlohmann::json sorts the keys (the report.json of `quadcage fit`, ComponentFitReport).

#include <nlohmann/json.hpp>

#include "quadcage/fit/outputs.h"

namespace quadcage::fit::detail {

template <class Json>
Json stats_object(const DistanceStats& s) {
    Json j;
    j["rms"] = s.rms;
    j["mean"] = s.mean;
    j["max"] = s.max;
    return j;
}

template <class Json>
Json error_object(const FitError& e) {
    Json j;
    j["input_to_surface"] = stats_object<Json>(e.input_to_surface);
    j["surface_to_input"] = stats_object<Json>(e.surface_to_input);
    j["rms"] = e.rms;
    j["hausdorff"] = e.hausdorff;
    return j;
}

template <class Json>
Json level_object(const LevelReport& l) {
    Json j;
    j["level"] = l.level;
    j["control_points"] = l.control_points;
    j["absolute"] = error_object<Json>(l.absolute);
    j["relative"] = error_object<Json>(l.relative);
    j["within_tolerance"] = l.within_tolerance;
    j["iterations"] = l.iterations;
    j["solver_iterations"] = l.solver_iterations;
    j["stop_reason"] = l.stop_reason;
    Json seconds;
    seconds["parameterization"] = l.seconds.parameterization;
    seconds["evaluation"] = l.seconds.evaluation;
    seconds["closest_points"] = l.seconds.closest_points;
    seconds["solve"] = l.seconds.solve;
    seconds["total"] = l.seconds.total;
    j["seconds"] = seconds;
    if (l.unfitted_relative_rms >= 0) {
        Json u;
        u["rms"] = l.unfitted_relative_rms;
        u["hausdorff"] = l.unfitted_relative_hausdorff;
        j["unfitted_relative"] = u;
    }
    return j;
}

/// Every field of `r` into the object `report` (which may already hold other keys).
template <class Json>
void put_fit_report(const FitReport& r, Json& report) {
    report["mode"] = r.mode == FitMode::Level ? "level" : "tolerance";
    if (r.mode == FitMode::Level) report["requested_level"] = r.requested_level;
    else report["max_level"] = r.max_level;
    report["tolerance"] = r.tolerance;
    report["tolerance_met"] = r.tolerance_met;
    report["level"] = r.level;
    report["message"] = r.message;
    report["diagonal"] = r.diagonal;
    Json levels = Json::array();
    for (const LevelReport& l : r.levels) levels.push_back(level_object<Json>(l));
    report["levels"] = levels;
    if (r.rejected_level) report["rejected_level"] = level_object<Json>(*r.rejected_level);
    if (r.fitted_cage) {
        Json c;
        c["vertices"] = r.fitted_cage->vertices;
        c["quads"] = r.fitted_cage->quads;
        c["level0_faces"] = r.fitted_cage->level0_faces;
        report["fitted_cage"] = c;
    }
    report["irregular_level"] = r.irregular_level;
    Json weights;
    weights["surface_to_input"] = r.weights.surface_to_input;
    weights["tangential"] = r.weights.tangential;
    weights["turned_over"] = r.weights.turned_over;
    report["weights"] = weights;
    if (r.limit_tessellation) {
        const TessellationChoice& t = *r.limit_tessellation;
        Json j;
        j["segments_per_face"] = t.segments;
        j["triangles"] = t.triangles;
        j["rms_error"] = t.rms_error;
        j["max_error"] = t.max_error;
        j["target"] = t.target;
        j["met"] = t.met;
        if (t.folded_area_fraction >= 0) j["folded_area_fraction"] = t.folded_area_fraction;
        if (t.input_folded_area_fraction >= 0) j["input_folded_area_fraction"] = t.input_folded_area_fraction;
        if (t.inverted_area_fraction >= 0) j["inverted_area_fraction"] = t.inverted_area_fraction;
        report["limit_tessellation"] = j;
    }
}

}  // namespace quadcage::fit::detail
