#include "quadcage/bench/tables.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "quadcage/core/io.h"

namespace quadcage::bench {
namespace {

using nlohmann::json;

const std::string kMissing = "-";

std::string fmt(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

std::string cell(const std::optional<int>& v) { return v ? std::to_string(*v) : kMissing; }
std::string cell(const std::optional<double>& v, const char* format) {
    return v && std::isfinite(*v) ? fmt(format, *v) : kMissing;
}
std::string cell(const std::optional<bool>& v) { return v ? (*v ? "yes" : "no") : kMissing; }
std::string cell(const std::string& s) { return s.empty() ? kMissing : s; }

std::string degrees_cell(const std::map<int, int>& d) {
    std::string s;
    for (const auto& [degree, count] : d) s += (s.empty() ? "" : " ") + std::to_string(degree) + ":" + std::to_string(count);
    return cell(s);
}

template <class T>
json opt(const std::optional<T>& v) {
    if (!v) return nullptr;
    if constexpr (std::is_floating_point_v<T>) {
        if (!std::isfinite(*v)) return nullptr;
    }
    return json(*v);
}
json opt(const std::string& s) { return s.empty() ? json(nullptr) : json(s); }

const PeerResult* peer_at(const MeshResult& m, int level) {
    for (const PeerResult& p : m.peers)
        if (p.level == level) return &p;
    return nullptr;
}

std::string ratio_cell(const std::optional<double>& ratio, const std::string& note) {
    return ratio ? fmt("%.3g", *ratio) : note.empty() ? kMissing : note;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Rows of one mesh: one per level, or one with level "-" when the mesh stopped before the fits.
struct Row {
    const MeshResult* mesh;
    const LevelResult* level;  // null: the mesh row
};

std::vector<Row> rows_of(const BenchResult& r) {
    std::vector<Row> rows;
    for (const MeshResult& m : r.meshes) {
        const bool stopped_early = m.stage == "info" || m.stage == "layout" || m.stage == "input";
        if (m.levels.empty() || stopped_early) {
            rows.push_back({&m, nullptr});
        } else {
            for (const LevelResult& l : m.levels) rows.push_back({&m, &l});
        }
    }
    return rows;
}

std::string row_status(const Row& row) { return row.level ? row.level->status : row.mesh->status; }
std::string row_reason(const Row& row) { return row.level ? row.level->reason : row.mesh->reason; }
std::string row_stage(const Row& row) {
    if (!row.level) return row.mesh->stage;
    return row.level->status == "ok" || row.level->status == "-" ? "" : "fit";
}

std::string csv_quote(const std::string& s) {
    if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) {
        if (c == '"') q += '"';
        q += c;
    }
    return q + "\"";
}

std::string md_escape(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '|') out += "\\|";
        else if (c == '\n' || c == '\r') out += ' ';
        else out += c;
    }
    return out;
}

std::string md_row(const std::vector<std::string>& cells) {
    std::string s = "|";
    for (const std::string& c : cells) s += " " + md_escape(c) + " |";
    return s + "\n";
}

std::string md_rule(size_t n, size_t text_columns) {
    std::string s = "|";
    for (size_t i = 0; i < n; ++i) s += i < text_columns ? "---|" : "---:|";
    return s + "\n";
}

}  // namespace

PeerComparison compare_with_peer(const LevelResult& ours, const PeerResult* peer) {
    PeerComparison c;
    if (!peer || peer->status == "-") {
        c.note = "n/a (no peer)";
        return c;
    }
    // The status up to its first ':' ("failed", "fit failed", "not installed"): the details are in
    // the status columns.
    const auto head = [](const std::string& status) { return status.substr(0, status.find(':')); };
    if (peer->status != "ok") {
        c.note = "n/a (peer " + head(peer->status) + ")";
        return c;
    }
    if (ours.status != "ok") {
        c.note = "n/a (our fit " + head(ours.status) + ")";
        return c;
    }
    if (!ours.control_points || !peer->control_points || !ours.relative_rms || !peer->relative_rms ||
        !ours.relative_hausdorff || !peer->relative_hausdorff || !(*peer->relative_rms > 0) ||
        !(*peer->relative_hausdorff > 0)) {
        c.note = "n/a (a figure is missing)";
        return c;
    }
    const int a = *ours.control_points, b = *peer->control_points;
    if (a <= 0 || b <= 0 || std::max(a, b) > kPeerCountTolerance * std::min(a, b)) {
        c.note = "n/a (" + std::to_string(a) + " vs " + std::to_string(b) + " control points)";
        return c;
    }
    c.rms_ratio = *ours.relative_rms / *peer->relative_rms;
    c.hausdorff_ratio = *ours.relative_hausdorff / *peer->relative_hausdorff;
    return c;
}

BenchSummary summarize(const BenchResult& r) {
    BenchSummary s;
    s.meshes = static_cast<int>(r.meshes.size());
    s.wall_seconds = r.wall_seconds;
    for (const MeshResult& m : r.meshes) {
        if (m.status == "ok") ++s.ok;
        else if (m.status == "rejected") ++s.rejected;
        else ++s.failed;
        if (m.triangles) s.triangles += *m.triangles;
        if (m.layout_seconds) s.layout_seconds += *m.layout_seconds;
        for (const LevelResult& l : m.levels)
            if (l.fit_seconds) s.fit_seconds += *l.fit_seconds;
    }
    std::vector<double> rms, hausdorff;
    for (const MeshResult& m : r.meshes)
        for (const LevelResult& l : m.levels) {
            const PeerComparison c = compare_with_peer(l, peer_at(m, l.level));
            if (!c.counted()) continue;
            rms.push_back(*c.rms_ratio);
            hausdorff.push_back(*c.hausdorff_ratio);
        }
    s.peer_rows = static_cast<int>(rms.size());
    if (!rms.empty()) {
        s.rms_ratio_worst = *std::max_element(rms.begin(), rms.end());
        s.rms_ratio_median = median(rms);
        s.hausdorff_ratio_worst = *std::max_element(hausdorff.begin(), hausdorff.end());
        s.hausdorff_ratio_median = median(hausdorff);
    }
    return s;
}

std::string summary_line(const BenchResult& r) {
    const BenchSummary s = summarize(r);
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "bench: %d mesh%s: %d ok, %d rejected, %d failed; %lld triangles; layout %.1f s, fit %.1f s, "
                  "wall %.1f s",
                  s.meshes, s.meshes == 1 ? "" : "es", s.ok, s.rejected, s.failed, s.triangles, s.layout_seconds,
                  s.fit_seconds, s.wall_seconds);
    std::string line = buf;
    bool peer_ran = false;
    for (const MeshResult& m : r.meshes)
        for (const PeerResult& p : m.peers) peer_ran = peer_ran || !p.attempts.empty();
    if (s.peer_rows > 0) {
        std::snprintf(buf, sizeof buf,
                      "; ours / QuadriFlow over %d row%s: RMS worst %.3g median %.3g, Hausdorff worst %.3g median %.3g",
                      s.peer_rows, s.peer_rows == 1 ? "" : "s", *s.rms_ratio_worst, *s.rms_ratio_median,
                      *s.hausdorff_ratio_worst, *s.hausdorff_ratio_median);
        line += buf;
    } else if (peer_ran) {
        line += "; ours / QuadriFlow: no row at equal control points";
    }
    return line;
}

std::vector<std::string> table_columns() {
    std::vector<std::string> c = {"name",          "file",           "status",     "stage",          "reason",
                                  "triangles",     "components",     "genus",      "minimal_quads",  "quads",
                                  "corners",       "corners_by_degree", "verified", "layout_s",      "level",
                                  "control_points", "relative_rms",  "relative_hausdorff", "fit_s",  "peak_mib"};
    for (const char* f : {"peer_status", "peer_target_faces", "peer_attempts", "peer_faces", "peer_irregular",
                          "peer_control_points", "peer_relative_rms", "peer_relative_hausdorff", "peer_fit_s",
                          "peer_quadriflow_s", "rms_ratio", "hausdorff_ratio", "ratio_note"})
        c.push_back(f);
    c.push_back("wall_s");
    return c;
}

std::vector<std::vector<std::string>> table_rows(const BenchResult& r) {
    std::vector<std::vector<std::string>> out;
    for (const Row& row : rows_of(r)) {
        const MeshResult& m = *row.mesh;
        const LevelResult* l = row.level;
        std::optional<double> peak = m.peak_memory_mib;
        if (l && l->peak_memory_mib) peak = std::max(peak.value_or(0.0), *l->peak_memory_mib);
        std::vector<std::string> c = {m.input.name,
                                      m.input.path,
                                      cell(row_status(row)),
                                      cell(row_stage(row)),
                                      cell(row_reason(row)),
                                      cell(m.triangles),
                                      cell(m.components),
                                      cell(m.genus),
                                      cell(m.minimal_quads),
                                      cell(m.quads),
                                      cell(m.corners),
                                      degrees_cell(m.corner_degrees),
                                      cell(m.verified),
                                      cell(m.layout_seconds, "%.3f"),
                                      l ? std::to_string(l->level) : kMissing,
                                      l ? cell(l->control_points) : kMissing,
                                      l ? cell(l->relative_rms, "%.4g") : kMissing,
                                      l ? cell(l->relative_hausdorff, "%.4g") : kMissing,
                                      l ? cell(l->fit_seconds, "%.3f") : kMissing,
                                      cell(peak, "%.1f")};
        const PeerResult* p = l ? peer_at(m, l->level) : nullptr;
        if (p) {
            const PeerComparison cmp = compare_with_peer(*l, p);
            c.insert(c.end(), {cell(p->status), cell(p->target_faces), std::to_string(p->attempts.size()), cell(p->faces),
                               cell(p->irregular_vertices), cell(p->control_points), cell(p->relative_rms, "%.4g"),
                               cell(p->relative_hausdorff, "%.4g"), cell(p->fit_seconds, "%.3f"),
                               cell(p->quadriflow_seconds, "%.2f"), cell(cmp.rms_ratio, "%.4g"),
                               cell(cmp.hausdorff_ratio, "%.4g"), cell(cmp.note)});
        } else {
            c.insert(c.end(), 13, kMissing);
        }
        c.push_back(fmt("%.2f", m.wall_seconds));
        out.push_back(std::move(c));
    }
    return out;
}

std::string bench_csv(const BenchResult& r) {
    std::string s;
    auto line = [&s](const std::vector<std::string>& cells) {
        for (size_t i = 0; i < cells.size(); ++i) s += (i ? "," : "") + csv_quote(cells[i]);
        s += "\n";
    };
    line(table_columns());
    for (const auto& row : table_rows(r)) line(row);
    return s;
}

std::string bench_json(const BenchResult& r) {
    const BenchSummary s = summarize(r);
    json j;
    j["summary"] = {{"meshes", s.meshes},
                    {"ok", s.ok},
                    {"rejected", s.rejected},
                    {"failed", s.failed},
                    {"triangles", s.triangles},
                    {"layout_seconds", s.layout_seconds},
                    {"fit_seconds", s.fit_seconds},
                    {"wall_seconds", s.wall_seconds},
                    {"peer_ratios",
                     {{"rows", s.peer_rows},
                      {"rms", {{"worst", opt(s.rms_ratio_worst)}, {"median", opt(s.rms_ratio_median)}}},
                      {"hausdorff", {{"worst", opt(s.hausdorff_ratio_worst)}, {"median", opt(s.hausdorff_ratio_median)}}}}},
                    {"line", summary_line(r)}};
    j["levels"] = r.levels;
    j["layout_flags"] = r.layout_flags;
    j["fit_rounds"] = r.fit_rounds > 0 ? json(r.fit_rounds) : json(nullptr);
    j["turned_over_weight"] = r.turned_over_weight ? json(*r.turned_over_weight) : json(nullptr);
    j["plot"] = opt(r.plot_png);
    json meshes = json::array();
    for (const MeshResult& m : r.meshes) {
        json jm;
        jm["name"] = m.input.name;
        jm["file"] = m.input.path;
        jm["folder"] = "meshes/" + m.input.dir_name;
        jm["status"] = m.status;
        jm["stage"] = opt(m.stage);
        jm["reason"] = opt(m.reason);
        jm["triangles"] = opt(m.triangles);
        jm["components"] = opt(m.components);
        jm["genus"] = opt(m.genus);
        jm["minimal_quads"] = opt(m.minimal_quads);
        jm["quads"] = opt(m.quads);
        jm["corners"] = opt(m.corners);
        jm["edges"] = opt(m.edges);
        json degrees = json::object();
        for (const auto& [d, n] : m.corner_degrees) degrees[std::to_string(d)] = n;
        jm["corner_degrees"] = degrees;
        jm["verified"] = opt(m.verified);
        jm["layout_seconds"] = opt(m.layout_seconds);
        jm["peak_memory_mib"] = opt(m.peak_memory_mib);
        jm["layout_png"] = opt(m.layout_png);
        jm["wall_seconds"] = m.wall_seconds;
        json levels = json::array();
        for (const LevelResult& l : m.levels)
            levels.push_back({{"level", l.level},
                              {"status", l.status},
                              {"reason", opt(l.reason)},
                              {"control_points", opt(l.control_points)},
                              {"relative_rms", opt(l.relative_rms)},
                              {"relative_hausdorff", opt(l.relative_hausdorff)},
                              {"fit_seconds", opt(l.fit_seconds)},
                              {"peak_memory_mib", opt(l.peak_memory_mib)},
                              {"deviation_png", opt(l.deviation_png)}});
        jm["levels"] = levels;
        json peers = json::array();
        for (const PeerResult& p : m.peers) {
            json attempts = json::array();
            for (const PeerAttempt& a : p.attempts)
                attempts.push_back({{"target_faces", a.target_faces},
                                    {"seed", a.seed},
                                    {"outcome", a.outcome},
                                    {"faces", opt(a.faces)},
                                    {"quads", opt(a.quads)},
                                    {"vertices", opt(a.vertices)},
                                    {"genus", opt(a.genus)},
                                    {"seconds", opt(a.seconds)}});
            const LevelResult* ours = nullptr;
            for (const LevelResult& l : m.levels)
                if (l.level == p.level) ours = &l;
            const PeerComparison c = ours ? compare_with_peer(*ours, &p) : PeerComparison{{}, {}, "n/a (no fit of ours)"};
            peers.push_back({{"tool", "quadriflow"},
                             {"level", p.level},
                             {"target_faces", opt(p.target_faces)},
                             {"status", p.status},
                             {"attempts", attempts},
                             {"cage", opt(p.cage)},
                             {"faces", opt(p.faces)},
                             {"quads", opt(p.quads)},
                             {"irregular_vertices", opt(p.irregular_vertices)},
                             {"control_points", opt(p.control_points)},
                             {"relative_rms", opt(p.relative_rms)},
                             {"relative_hausdorff", opt(p.relative_hausdorff)},
                             {"fit_seconds", opt(p.fit_seconds)},
                             {"quadriflow_seconds", opt(p.quadriflow_seconds)},
                             {"rms_ratio", opt(c.rms_ratio)},
                             {"hausdorff_ratio", opt(c.hausdorff_ratio)},
                             {"ratio_note", opt(c.note)}});
        }
        jm["peer"] = peers;
        jm["notes"] = m.notes;
        meshes.push_back(jm);
    }
    j["meshes"] = meshes;
    return j.dump(2) + "\n";
}

std::string bench_markdown(const BenchResult& r) {
    std::string md = "# quadcage bench\n\n" + summary_line(r) + "\n\n";
    std::string levels;
    for (int l : r.levels) levels += (levels.empty() ? "" : ", ") + std::to_string(l);
    md += "Levels: " + (levels.empty() ? std::string("none") : levels) +
          ". Relative RMS and Hausdorff distances are over the bounding-box diagonal; peak memory is the largest "
          "resident set of the mesh's layout and fit processes; seconds as the stages report them.\n\n";
    if (!r.layout_flags.empty()) {
        std::string flags;
        for (const std::string& f : r.layout_flags) flags += (flags.empty() ? "" : " ") + f;
        md += "Our layouts were made with `" + flags +
              "` (on the layout and on every fit of ours, not on the peer's).\n\n";
    }
    if (r.fit_rounds > 0)
        md += "Every fit, ours and the peer's, took at most " + std::to_string(r.fit_rounds) +
              " rounds a level (`--rounds " + std::to_string(r.fit_rounds) + "`).\n\n";
    if (r.turned_over_weight)
        md += std::string("Every fit, ours and the peer's, ran with `--turned-over-weight ") +
              fmt("%g", *r.turned_over_weight) + "`" +
              (*r.turned_over_weight > 0 ? "" : " (no term against pleats)") + ".\n\n";
    if (!r.plot_png.empty()) md += "![relative RMS against control points, log-log](" + r.plot_png + ")\n\n";
    else md += "(No plot: no fit reported control points and an RMS.)\n\n";

    md += "## Results\n\n";
    const std::vector<std::string> head = {"name", "level", "status", "triangles", "components", "genus",
                                           "quads", "corners by degree", "verified", "layout s", "control points",
                                           "rel. RMS", "rel. Hausdorff", "fit s", "peak MiB"};
    md += md_row(head) + md_rule(head.size(), 3);
    for (const Row& row : rows_of(r)) {
        const MeshResult& m = *row.mesh;
        const LevelResult* l = row.level;
        std::string status = row_status(row);
        if (!row_reason(row).empty()) status += ": " + row_reason(row);
        if (!row_stage(row).empty()) status += " (" + row_stage(row) + ")";
        std::optional<double> peak = m.peak_memory_mib;
        if (l && l->peak_memory_mib) peak = std::max(peak.value_or(0.0), *l->peak_memory_mib);
        md += md_row({m.input.name, l ? std::to_string(l->level) : kMissing, status, cell(m.triangles),
                      cell(m.components), cell(m.genus), cell(m.quads), degrees_cell(m.corner_degrees),
                      cell(m.verified), cell(m.layout_seconds, "%.2f"), l ? cell(l->control_points) : kMissing,
                      l ? cell(l->relative_rms, "%.3g") : kMissing, l ? cell(l->relative_hausdorff, "%.3g") : kMissing,
                      l ? cell(l->fit_seconds, "%.2f") : kMissing, cell(peak, "%.0f")});
    }

    md += "\n## Peer: QuadriFlow cages fitted by our fitter\n\n"
          "At each level K, QuadriFlow (Blender) remeshes the input at our level-K control-face count (quads x 4^K, "
          "which is our control points + 2g - 2, so that the remesh's vertices match our control points), and "
          "`quadcage fit --cage REMESH --level 0` fits the remesh's own vertices. Ratios are ours / peer (below 1: "
          "ours is closer to the input); they count only when the two control-point counts are within 10% of each "
          "other. Irregular: remesh vertices of valence other than 4.\n\n";
    const std::vector<std::string> phead = {"name", "level", "control points (ours / peer)", "rel. RMS (ours / peer)",
                                            "rel. Hausdorff (ours / peer)", "RMS ratio", "Hausdorff ratio",
                                            "peer status", "target faces", "attempts", "peer faces", "irregular",
                                            "peer fit s", "QuadriFlow s"};
    md += md_row(phead) + md_rule(phead.size(), 2);
    bool any_peer = false, any_failed_attempt = false;
    for (const MeshResult& m : r.meshes)
        for (const LevelResult& l : m.levels) {
            const PeerResult* p = peer_at(m, l.level);
            if (!p) continue;
            any_peer = true;
            const PeerComparison c = compare_with_peer(l, p);
            md += md_row({m.input.name, std::to_string(l.level), cell(l.control_points) + " / " + cell(p->control_points),
                          cell(l.relative_rms, "%.3g") + " / " + cell(p->relative_rms, "%.3g"),
                          cell(l.relative_hausdorff, "%.3g") + " / " + cell(p->relative_hausdorff, "%.3g"),
                          ratio_cell(c.rms_ratio, c.note), ratio_cell(c.hausdorff_ratio, c.note), cell(p->status),
                          cell(p->target_faces), std::to_string(p->attempts.size()), cell(p->faces),
                          cell(p->irregular_vertices), cell(p->fit_seconds, "%.2f"),
                          cell(p->quadriflow_seconds, "%.2f")});
            for (const PeerAttempt& a : p->attempts) any_failed_attempt = any_failed_attempt || a.outcome != "ok";
        }
    if (!any_peer) md += md_row({"(no peer: no level ran)", "", "", "", "", "", "", "", "", "", "", "", "", ""});
    if (any_failed_attempt) {
        md += "\nQuadriFlow attempts not fitted as they were (target faces, seed: outcome):\n\n";
        for (const MeshResult& m : r.meshes)
            for (const PeerResult& p : m.peers)
                for (const PeerAttempt& a : p.attempts)
                    if (a.outcome != "ok")
                        md += "- " + md_escape(m.input.name) + " level " + std::to_string(p.level) + ", " +
                              std::to_string(a.target_faces) + " faces, seed " + std::to_string(a.seed) + ": " +
                              md_escape(a.outcome) + (a.faces ? " (" + std::to_string(*a.faces) + " faces)" : "") + "\n";
    }

    md += "\n## Pictures\n";
    for (const MeshResult& m : r.meshes) {
        md += "\n### " + md_escape(m.input.name) + "\n\n";
        md += "Status: " + md_escape(m.status) + (m.reason.empty() ? "" : " - " + md_escape(m.reason)) + ". Log: [" +
              "meshes/" + m.input.dir_name + "/log.txt](meshes/" + m.input.dir_name + "/log.txt)\n\n";
        if (!m.layout_png.empty()) md += "![layout of " + md_escape(m.input.name) + "](" + m.layout_png + ")\n\n";
        for (const LevelResult& l : m.levels)
            if (!l.deviation_png.empty())
                md += "![deviation at level " + std::to_string(l.level) + "](" + l.deviation_png + ")\n\n";
        for (const std::string& n : m.notes) md += "- " + md_escape(n) + "\n";
    }
    return md;
}

void write_bench_tables(const std::string& dir, const BenchResult& r) {
    const std::filesystem::path d(dir);
    write_text_file((d / "bench.csv").string(), bench_csv(r));
    write_text_file((d / "bench.json").string(), bench_json(r));
    write_text_file((d / "bench.md").string(), bench_markdown(r));
}

}  // namespace quadcage::bench
