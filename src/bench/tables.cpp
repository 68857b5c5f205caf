#include "quadcage/bench/tables.h"

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

const PeerResult* peer(const MeshResult& m, const std::string& target) {
    for (const PeerResult& p : m.peers)
        if (p.target == target) return &p;
    return nullptr;
}

void add_peer_cells(std::vector<std::string>& row, const PeerResult* p) {
    if (!p) {
        row.insert(row.end(), {kMissing, kMissing, kMissing, kMissing, kMissing, kMissing});
        return;
    }
    row.push_back(cell(p->status));
    row.push_back(cell(p->target_faces));
    row.push_back(cell(p->quads));
    row.push_back(cell(p->genus));
    row.push_back(cell(p->irregular_vertices));
    row.push_back(cell(p->seconds, "%.2f"));
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
    return buf;
}

std::vector<std::string> table_columns() {
    std::vector<std::string> c = {"name",          "file",           "status",     "stage",          "reason",
                                  "triangles",     "components",     "genus",      "minimal_quads",  "quads",
                                  "corners",       "corners_by_degree", "verified", "layout_s",      "level",
                                  "control_points", "relative_rms",  "relative_hausdorff", "fit_s",  "peak_mib"};
    for (const char* t : {"peer_minimal", "peer_level2"})
        for (const char* f : {"status", "target_faces", "quads", "genus", "irregular", "s"})
            c.push_back(std::string(t) + "_" + f);
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
        add_peer_cells(c, peer(m, "minimal"));
        add_peer_cells(c, peer(m, "level2"));
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
                    {"line", summary_line(r)}};
    j["levels"] = r.levels;
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
        for (const PeerResult& p : m.peers)
            peers.push_back({{"tool", "quadriflow"},
                             {"target", p.target},
                             {"target_faces", opt(p.target_faces)},
                             {"status", p.status},
                             {"faces", opt(p.faces)},
                             {"quads", opt(p.quads)},
                             {"genus", opt(p.genus)},
                             {"irregular_vertices", opt(p.irregular_vertices)},
                             {"seconds", opt(p.seconds)}});
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

    md += "\n## Peer: QuadriFlow (Blender)\n\n"
          "QuadriFlow remeshes each input at (a) our minimal quad count and (b) 16 times it (the quad count of "
          "our level-2 cage). Irregular vertices: valence other than 4.\n\n";
    const std::vector<std::string> phead = {"name", "our quads", "target", "status", "faces", "quads", "genus",
                                            "irregular", "seconds"};
    md += md_row(phead) + md_rule(phead.size(), 4);
    for (const MeshResult& m : r.meshes) {
        if (m.peers.empty()) {
            md += md_row({m.input.name, cell(m.quads), kMissing, "-", kMissing, kMissing, kMissing, kMissing, kMissing});
            continue;
        }
        for (const PeerResult& p : m.peers)
            md += md_row({m.input.name, cell(m.quads), p.target + " (" + cell(p.target_faces) + ")", cell(p.status),
                          cell(p.faces), cell(p.quads), cell(p.genus), cell(p.irregular_vertices),
                          cell(p.seconds, "%.2f")});
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
