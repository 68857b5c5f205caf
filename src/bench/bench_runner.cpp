#include "quadcage/bench/bench_runner.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "quadcage/bench/child_process.h"
#include "quadcage/bench/peer.h"
#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "quadcage/render/image.h"
#include "quadcage/render/plot.h"

namespace quadcage::bench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

std::string fmt_g(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

std::vector<std::string> substitute(const std::vector<std::string>& tmpl, const std::map<std::string, std::string>& vars) {
    std::vector<std::string> out;
    for (std::string arg : tmpl) {
        for (const auto& [key, value] : vars) {
            const std::string token = "{" + key + "}";
            for (size_t at = arg.find(token); at != std::string::npos; at = arg.find(token, at + value.size()))
                arg.replace(at, token.size(), value);
        }
        out.push_back(arg);
    }
    return out;
}

// The line of a child's stderr that says what went wrong: the last one that is neither a progress
// line nor CLI11's "Run with --help" hint; "quadcage: " / "error: " prefixes dropped.
std::string reason_line(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) {
        while (!l.empty() && (l.back() == '\r' || l.back() == ' ')) l.pop_back();
        if (!l.empty()) lines.push_back(l);
    }
    for (auto it = lines.rbegin(); it != lines.rend(); ++it) {
        std::string l = *it;
        if (l.find("Run with --help") != std::string::npos || l.rfind("quadcage: [", 0) == 0) continue;
        for (const char* prefix : {"quadcage: ", "error: "})
            if (l.rfind(prefix, 0) == 0) l = l.substr(std::string(prefix).size());
        return l;
    }
    return {};
}

// "ok", "rejected" (exit 3) or "failed: ..." for a finished child.
std::string outcome(const ChildResult& r, double timeout, std::string* reason) {
    switch (r.end) {
        case ChildResult::End::not_started: return "failed: " + r.error;
        case ChildResult::End::timed_out: return "failed: timeout after " + fmt_g(timeout) + " s";
        case ChildResult::End::signalled: return "failed: crashed (signal " + std::to_string(r.signal) + ")";
        case ChildResult::End::exited: break;
    }
    if (r.exit_code == 0) return "ok";
    const std::string line = reason_line(r.stderr_text);
    if (r.exit_code == 3) {
        if (reason) *reason = line.empty() ? "invalid input (exit code 3)" : line;
        return "rejected";
    }
    // Exit 2 is the CLI's usage error: e.g. a stage command this quadcage does not have yet.
    const std::string what = r.exit_code == 2 ? "usage error (exit 2): " : "";
    return "failed: " + what + (line.empty() ? "exit code " + std::to_string(r.exit_code) : line);
}

std::optional<json> read_json(const fs::path& p) {
    std::ifstream in(p);
    if (!in) return std::nullopt;
    std::stringstream s;
    s << in.rdbuf();
    json j = json::parse(s.str(), nullptr, false);
    if (j.is_discarded()) return std::nullopt;
    return j;
}

const json* at_path(const json& j, std::initializer_list<const char*> keys) {
    const json* cur = &j;
    for (const char* k : keys) {
        if (!cur->is_object()) return nullptr;
        auto it = cur->find(k);
        if (it == cur->end()) return nullptr;
        cur = &*it;
    }
    return cur;
}

std::optional<int> get_int(const json& j, std::initializer_list<const char*> keys) {
    const json* v = at_path(j, keys);
    if (!v || !v->is_number()) return std::nullopt;
    const double d = v->get<double>();
    if (!std::isfinite(d) || std::abs(d) > 2e9) return std::nullopt;
    return static_cast<int>(std::llround(d));
}

std::optional<double> get_double(const json& j, std::initializer_list<const char*> keys) {
    const json* v = at_path(j, keys);
    if (!v || !v->is_number()) return std::nullopt;
    return v->get<double>();
}

// "seconds": {"total": x, ...} or "seconds": x.
std::optional<double> get_seconds(const json& j) {
    if (auto s = get_double(j, {"seconds", "total"})) return s;
    return get_double(j, {"seconds"});
}

// What a fit's report.json says about one level: the entry of `levels` with that level (or the
// only entry), else nothing; seconds from the entry or else the whole report.
struct FitFigures {
    std::optional<int> control_points;
    std::optional<double> relative_rms, relative_hausdorff, seconds;
};

FitFigures fit_figures(const json& j, int level) {
    FitFigures f;
    const json* entry = nullptr;
    if (const json* ls = at_path(j, {"levels"}); ls && ls->is_array()) {
        for (const json& e : *ls)
            if (get_int(e, {"level"}) == level) entry = &e;
        if (!entry && ls->size() == 1) entry = &(*ls)[0];
    }
    if (entry) {
        f.control_points = get_int(*entry, {"control_points"});
        f.relative_rms = get_double(*entry, {"relative", "rms"});
        f.relative_hausdorff = get_double(*entry, {"relative", "hausdorff"});
        f.seconds = get_seconds(*entry);
    }
    if (!f.seconds) f.seconds = get_seconds(j);
    return f;
}

void remove_quietly(const fs::path& p) {
    std::error_code ec;
    fs::remove(p, ec);
}

// One mesh, all stages, in the calling worker thread.
class MeshJob {
public:
    MeshJob(const BenchInput& in, const BenchOptions& o, int index, int count, Clock::time_point start,
            std::mutex& progress_mutex)
        : in_(in), o_(o), index_(index), count_(count), start_(start), progress_mutex_(progress_mutex) {
        dir_ = fs::path(o.output_dir) / "meshes" / in.dir_name;
        rel_ = "meshes/" + in.dir_name;
        log_ = dir_ / "log.txt";
    }

    MeshResult run() {
        const Clock::time_point t0 = Clock::now();
        m_.input = in_;
        prepare_folder();
        if (run_info() && run_layout()) run_fits();
        run_peer();
        if (m_.status == "-") m_.status = "ok";
        m_.wall_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
        std::string end = m_.status;
        if (!m_.reason.empty()) end += ": " + m_.reason;
        if (!m_.stage.empty()) end += " (" + m_.stage + ")";
        say(end);
        return m_;
    }

private:
    void say(const std::string& what) {
        if (!o_.progress) return;
        const double t = std::chrono::duration<double>(Clock::now() - start_).count();
        char buf[48];
        std::snprintf(buf, sizeof buf, " (%.1f s)", t);
        std::lock_guard<std::mutex> lock(progress_mutex_);
        o_.progress("bench [" + std::to_string(index_ + 1) + "/" + std::to_string(count_) + "] " + in_.name + ": " +
                    what + buf);
    }

    void log(const std::string& line) {
        std::ofstream out(log_, std::ios::app);
        out << line << "\n";
    }

    // Outputs of an earlier run in the same folder must not be mistaken for this run's.
    void prepare_folder() {
        std::error_code ec;
        fs::create_directories(dir_, ec);
        for (const char* f : {"log.txt", "info.json", "report.json", "layout.ply", "cage.obj", "layout.png"})
            remove_quietly(dir_ / f);
        for (int level : o_.levels)
            for (const char* f : {"report.json", "deviation.ply", "limit.ply", "deviation.png"})
                remove_quietly(dir_ / ("level" + std::to_string(level)) / f);
        fs::remove_all(dir_ / "peer", ec);  // the peer's remeshes and fits: all of it is this run's
        log("# quadcage bench: " + in_.path);
    }

    ChildResult stage(const std::string& name, const std::vector<std::string>& argv, const std::string& stdout_path = {}) {
        say(name);
        std::string line = "== " + name + ":";
        for (const std::string& a : argv) line += " " + a;
        log(line);
        ChildOptions co;
        co.timeout_seconds = o_.timeout_seconds;
        co.stdout_path = stdout_path;
        co.stderr_path = log_.string();
        ChildResult r = run_child(argv, co);
        char buf[160];
        std::snprintf(buf, sizeof buf, "== %s ended: %s, %.2f s, peak %.1f MiB", name.c_str(),
                      r.end == ChildResult::End::exited      ? ("exit " + std::to_string(r.exit_code)).c_str()
                      : r.end == ChildResult::End::signalled ? ("signal " + std::to_string(r.signal)).c_str()
                      : r.end == ChildResult::End::timed_out ? "timeout, process group killed"
                                                             : r.error.c_str(),
                      r.seconds, r.peak_memory_mib);
        log(buf);
        return r;
    }

    std::map<std::string, std::string> vars() const {
        return {{"exe", o_.executable}, {"mesh", in_.path}, {"title", in_.name}};
    }

    void fail(const std::string& stage, const std::string& status, const std::string& reason) {
        if (m_.status != "-") return;  // the first failure is the mesh's status
        m_.status = status;
        m_.stage = stage;
        m_.reason = reason;
    }

    bool run_info() {
        const fs::path out = dir_ / "info.json";
        const ChildResult r = stage("info", substitute(o_.commands.info, vars()), out.string());
        std::string reason;
        const std::string status = outcome(r, o_.timeout_seconds, &reason);
        if (const auto j = read_json(out)) {
            m_.triangles = get_int(*j, {"triangles"});
            m_.minimal_quads = get_int(*j, {"minimal_quads"});
            if (const json* comps = at_path(*j, {"components"}); comps && comps->is_array()) {
                m_.components = static_cast<int>(comps->size());
                std::string g;
                bool known = true;
                for (const json& c : *comps) {
                    const auto cg = get_int(c, {"genus"});
                    known = known && cg.has_value();
                    if (cg) g += (g.empty() ? "" : "+") + std::to_string(*cg);
                }
                if (known && comps->size() <= 8) m_.genus = g;
                else if (known) m_.genus = std::to_string(comps->size()) + " components";
                if (known) {
                    genus_total_ = 0;
                    for (const json& c : *comps) *genus_total_ += *get_int(c, {"genus"});
                }
            }
        }
        if (status != "ok") {
            fail("info", status, reason);
            return false;
        }
        return true;
    }

    bool run_layout() {
        auto v = vars();
        v["dir"] = dir_.string();
        std::vector<std::string> argv = substitute(o_.commands.layout, v);
        argv.insert(argv.end(), o_.layout_flags.begin(), o_.layout_flags.end());
        const ChildResult r = stage("layout", argv);
        m_.peak_memory_mib = r.peak_memory_mib;
        std::string reason;
        const std::string status = outcome(r, o_.timeout_seconds, &reason);
        if (status != "ok") {
            fail("layout", status, reason);
            return false;
        }
        const auto j = read_json(dir_ / "report.json");
        if (!j) {
            fail("layout", "failed: no readable report.json", "");
            return false;
        }
        m_.quads = get_int(*j, {"quads"});
        m_.corners = get_int(*j, {"corners"});
        m_.edges = get_int(*j, {"edges"});
        m_.layout_seconds = get_seconds(*j);
        if (!m_.peak_memory_mib || *m_.peak_memory_mib <= 0) m_.peak_memory_mib = get_double(*j, {"peak_memory_mib"});
        if (const json* h = at_path(*j, {"degree_histogram"}); h && h->is_object())
            for (const auto& [key, value] : h->items())
                if (value.is_number_integer()) {
                    try {
                        m_.corner_degrees[std::stoi(key)] = value.get<int>();
                    } catch (const std::exception&) {
                        log("# ignored degree_histogram key '" + key + "'");
                    }
                }
        if (const json* ver = at_path(*j, {"verified"}); ver && ver->is_boolean()) m_.verified = ver->get<bool>();
        if (m_.verified && !*m_.verified) {
            fail("layout", "failed: the layout verifier rejected the layout", "");
            return false;
        }
        if (o_.pictures) picture("layout picture", dir_ / "layout.ply", dir_ / "layout.png", "layout", m_.layout_png);
        return true;
    }

    void picture(const std::string& name, const fs::path& input, const fs::path& png, const std::string& kind,
                 std::string& rel_out) {
        std::error_code ec;
        if (!fs::exists(input, ec)) {
            m_.notes.push_back(name + ": not drawn (" + input.filename().string() + " missing)");
            return;
        }
        auto v = vars();
        v["input"] = input.string();
        v["png"] = png.string();
        v["kind"] = kind;
        const ChildResult r = stage(name, substitute(o_.commands.render, v));
        const std::string status = outcome(r, o_.timeout_seconds, nullptr);
        if (status == "ok" && fs::exists(png, ec)) rel_out = rel_ + "/" + fs::relative(png, dir_).generic_string();
        else m_.notes.push_back(name + ": not drawn (" + (status == "ok" ? "no file written" : status) + ")");
    }

    // The fitter settings both fits of a level share, ours and the peer's.
    void add_fit_settings(std::vector<std::string>* argv) const {
        if (o_.fit_rounds > 0) argv->insert(argv->end(), {"--rounds", std::to_string(o_.fit_rounds)});
        if (o_.turned_over_weight)
            argv->insert(argv->end(), {"--turned-over-weight", fmt_g(*o_.turned_over_weight)});
    }

    void run_fits() {
        for (int level : o_.levels) {
            LevelResult l;
            l.level = level;
            const fs::path ldir = dir_ / ("level" + std::to_string(level));
            auto v = vars();
            v["dir"] = ldir.string();
            v["level"] = std::to_string(level);
            std::vector<std::string> argv = substitute(o_.commands.fit, v);
            argv.insert(argv.end(), o_.layout_flags.begin(), o_.layout_flags.end());
            if (o_.tolerance > 0) argv.insert(argv.end(), {"--tolerance", fmt_g(o_.tolerance)});
            add_fit_settings(&argv);
            const ChildResult r = stage("fit level " + std::to_string(level), argv);
            l.peak_memory_mib = r.peak_memory_mib;
            l.status = outcome(r, o_.timeout_seconds, &l.reason);
            if (l.status == "ok") {
                if (const auto j = read_json(ldir / "report.json")) {
                    const FitFigures f = fit_figures(*j, level);
                    l.control_points = f.control_points;
                    l.relative_rms = f.relative_rms;
                    l.relative_hausdorff = f.relative_hausdorff;
                    l.fit_seconds = f.seconds;
                    if (l.peak_memory_mib.value_or(0) <= 0) l.peak_memory_mib = get_double(*j, {"peak_memory_mib"});
                } else {
                    l.status = "failed: no readable report.json";
                }
            }
            if (l.status == "ok" && o_.pictures)
                picture("deviation picture level " + std::to_string(level), ldir / "deviation.ply",
                        ldir / "deviation.png", "deviation", l.deviation_png);
            if (l.status != "ok") fail("fit", l.status, l.reason);
            m_.levels.push_back(l);
        }
    }

    // The first QuadriFlow attempt that has not been tried yet: after a valid remesh whose count is
    // off, the target scaled by ours / its vertices; else other seeds, then nearby targets.
    static std::pair<int, int> next_attempt(const std::vector<PeerAttempt>& done, int target, int want_points,
                                            bool last_count_off) {
        auto tried = [&](int t, int seed) {
            for (const PeerAttempt& a : done)
                if (a.target_faces == t && a.seed == seed) return true;
            return false;
        };
        if (done.empty()) return {target, 0};
        const PeerAttempt& last = done.back();
        if (last_count_off && last.vertices && *last.vertices > 0) {
            const int t = std::max(1, static_cast<int>(std::lround(double(last.target_faces) * want_points / *last.vertices)));
            if (!tried(t, last.seed)) return {t, last.seed};
        }
        const auto near = [&](double f) { return std::max(1, static_cast<int>(std::lround(target * f))); };
        const std::pair<int, int> plan[] = {{target, 1},     {target, 2},     {near(1.05), 0},
                                            {near(0.95), 0}, {near(1.10), 0}, {near(0.90), 0}};
        for (const auto& [t, seed] : plan)
            if (!tried(t, seed)) return {t, seed};
        return {near(1.0 + 0.05 * (done.size() + 1)), 0};
    }

    // Fits a remesh with `peer_fit`; "ok" (figures in p), "rejected: ..." (exit 3) or "failed: ...".
    std::string fit_peer_cage(PeerResult& p, const fs::path& cage, const fs::path& fit_dir) {
        std::error_code ec;
        fs::remove_all(fit_dir, ec);
        auto v = vars();
        v["cage"] = cage.string();
        v["dir"] = fit_dir.string();
        std::vector<std::string> argv = substitute(o_.commands.peer_fit, v);
        add_fit_settings(&argv);
        const ChildResult r = stage("peer fit level " + std::to_string(p.level), argv);
        std::string reason;
        const std::string status = outcome(r, o_.timeout_seconds, &reason);
        if (status == "rejected") return "rejected: " + reason;
        if (status != "ok") return status;
        const auto j = read_json(fit_dir / "report.json");
        if (!j) return "failed: no readable report.json";
        const FitFigures f = fit_figures(*j, 0);
        p.control_points = f.control_points;
        p.relative_rms = f.relative_rms;
        p.relative_hausdorff = f.relative_hausdorff;
        p.fit_seconds = f.seconds;
        p.cage = rel_ + "/" + fs::relative(cage, dir_).generic_string();
        return "ok";
    }

    // The peer at one level (see run_bench()): QuadriFlow attempts, then our fit of the chosen remesh.
    void run_peer_level(PeerResult& p, const std::string& blender, const fs::path& input_obj) {
        const fs::path pdir = dir_ / "peer" / ("level" + std::to_string(p.level));
        std::error_code ec;
        fs::create_directories(pdir, ec);
        const int target = *p.target_faces;
        int want_points = target + 2 - 2 * *genus_total_;
        for (const LevelResult& l : m_.levels)
            if (l.level == p.level && l.control_points) want_points = *l.control_points;
        const auto count_ok = [&](int vertices) {
            return vertices > 0 && std::max(vertices, want_points) <= kPeerCountTolerance * std::min(vertices, want_points);
        };
        struct Candidate {
            size_t attempt;
            fs::path obj;
            PolygonMeshStats stats;
            std::optional<double> seconds;
        };
        std::vector<Candidate> off_count;  // valid remeshes whose count is off
        bool last_count_off = false;
        const int max_attempts = std::max(1, o_.peer_attempts);
        for (int i = 0; i < max_attempts; ++i) {
            const auto [t, seed] = next_attempt(p.attempts, target, want_points, last_count_off);
            last_count_off = false;
            PeerAttempt a;
            a.target_faces = t;
            a.seed = seed;
            const fs::path out = pdir / ("quadriflow_" + std::to_string(t) + "_seed" + std::to_string(seed) + ".obj");
            remove_quietly(out);
            remove_quietly(out.string() + ".json");
            auto v = vars();
            v["blender"] = blender;
            v["script"] = o_.peer_script;
            v["mesh"] = input_obj.string();
            v["out"] = out.string();
            v["faces"] = std::to_string(t);
            v["seed"] = std::to_string(seed);
            const ChildResult r = stage("quadriflow level " + std::to_string(p.level) + " target " + std::to_string(t) +
                                            " seed " + std::to_string(seed),
                                        substitute(o_.commands.peer, v));
            a.outcome = outcome(r, o_.timeout_seconds, nullptr);
            if (a.outcome == "rejected") a.outcome = "failed: " + reason_line(r.stderr_text);
            if (const auto j = read_json(out.string() + ".json")) a.seconds = get_double(*j, {"seconds"});
            PolygonMeshStats st;
            if (a.outcome == "ok" && !fs::exists(out, ec)) a.outcome = "failed: no output written";
            if (a.outcome == "ok") {
                try {
                    st = polygon_obj_stats(out.string());
                    a.faces = st.faces;
                    a.quads = st.quads;
                    a.vertices = st.vertices;
                    a.genus = st.genus;
                    const std::string problem = peer_cage_problem(st, *genus_total_, m_.components.value_or(1));
                    if (!problem.empty()) a.outcome = problem;
                } catch (const InvalidInput& e) {
                    a.outcome = std::string("failed: ") + e.what();
                }
            }
            if (a.outcome == "ok" && !count_ok(st.vertices)) {
                a.outcome = "control points " + std::to_string(st.vertices) + " not within 10% of ours " +
                            std::to_string(want_points);
                off_count.push_back({p.attempts.size(), out, st, a.seconds});
                last_count_off = true;
            }
            p.attempts.push_back(a);
            if (a.outcome != "ok") continue;
            const std::string fitted = fit_peer_cage(p, out, pdir / "fit");
            if (fitted == "ok") {
                p.status = "ok";
                p.faces = st.faces;
                p.quads = st.quads;
                p.irregular_vertices = st.irregular_vertices;
                p.quadriflow_seconds = a.seconds;
                return;
            }
            if (fitted.rfind("rejected: ", 0) == 0) {
                p.attempts.back().outcome = "fit " + fitted;  // our fitter refused it: try another remesh
                continue;
            }
            p.attempts.back().outcome = "fit " + fitted;
            p.status = "fit " + fitted;
            return;
        }
        if (!off_count.empty()) {
            // No remesh matched the count: fit the closest one; its ratios will not count.
            const auto distance = [&](const Candidate& c) { return std::abs(std::log(double(c.stats.vertices) / want_points)); };
            const Candidate best = *std::min_element(off_count.begin(), off_count.end(), [&](const Candidate& x, const Candidate& y) {
                return distance(x) < distance(y);
            });
            const std::string fitted = fit_peer_cage(p, best.obj, pdir / "fit");
            p.attempts[best.attempt].outcome += fitted == "ok" ? " (fitted: the closest count)" : "; fit " + fitted;
            if (fitted == "ok") {
                p.status = "ok";
                p.faces = best.stats.faces;
                p.quads = best.stats.quads;
                p.irregular_vertices = best.stats.irregular_vertices;
                p.quadriflow_seconds = best.seconds;
            } else {
                p.status = "fit " + fitted;
            }
            return;
        }
        const std::string& last = p.attempts.back().outcome;
        p.status = last.rfind("failed: ", 0) == 0 ? last : "failed: " + last;
    }

    void run_peer() {
        for (int level : o_.levels) {
            PeerResult p;
            p.level = level;
            const std::optional<int> quads = m_.quads ? m_.quads : m_.minimal_quads;
            if (quads && *quads > 0 && level <= 8) p.target_faces = *quads << (2 * level);
            m_.peers.push_back(p);
        }
        if (m_.peers.empty()) return;
        const std::string blender = o_.peer ? find_on_path(o_.blender) : std::string();
        std::string common;
        if (!o_.peer) common = "disabled";
        else if (blender.empty()) common = "not installed";
        else if (m_.stage == "info") common = "not run (" + m_.status + ")";
        else if (!genus_total_) common = "failed: the input's genus is unknown";
        std::error_code ec;
        if (common.empty() && (o_.peer_script.empty() || !fs::exists(o_.peer_script, ec)))
            common = "failed: peer script not found (" + o_.peer_script + ")";
        // Blender reads OBJ everywhere; every input is handed over as OBJ written by quadcage.
        const fs::path obj = dir_ / "peer" / "input.obj";
        if (common.empty()) {
            try {
                fs::create_directories(obj.parent_path(), ec);
                write_obj(obj.string(), read_mesh(in_.path));
            } catch (const std::exception& e) {
                common = std::string("failed: cannot convert the input: ") + e.what();
            }
        }
        for (PeerResult& p : m_.peers) {
            if (!common.empty()) p.status = common;
            else if (!p.target_faces) p.status = "failed: our quad count is unknown";
            else run_peer_level(p, blender, obj);
        }
        remove_quietly(obj);  // a copy of the input; not worth keeping
    }

    const BenchInput& in_;
    const BenchOptions& o_;
    int index_, count_;
    Clock::time_point start_;
    std::mutex& progress_mutex_;
    fs::path dir_, log_;
    std::string rel_;
    MeshResult m_;
    std::optional<int> genus_total_;  // the input's genus summed over its components (from info)
};

// Our curve and, beside it, the peer's (QuadriFlow cages fitted by our fitter) for every mesh.
void write_plot(BenchResult& result, const std::string& dir) {
    std::vector<render::Series> series;
    const auto add = [&series](render::Series s) {
        if (!s.x.empty()) series.push_back(std::move(s));
    };
    for (const MeshResult& m : result.meshes) {
        render::Series ours, peer;
        ours.name = m.input.name;
        peer.name = m.input.name + " (QuadriFlow)";
        for (const LevelResult& l : m.levels)
            if (l.control_points && l.relative_rms && *l.control_points > 0 && *l.relative_rms > 0) {
                ours.x.push_back(*l.control_points);
                ours.y.push_back(*l.relative_rms);
            }
        for (const PeerResult& p : m.peers)
            if (p.status == "ok" && p.control_points && p.relative_rms && *p.control_points > 0 && *p.relative_rms > 0) {
                peer.x.push_back(*p.control_points);
                peer.y.push_back(*p.relative_rms);
            }
        add(ours);
        add(peer);
    }
    if (series.empty()) return;
    render::PlotOptions po;
    po.title = "relative RMS distance against control points";
    po.x_label = "control points";
    po.y_label = "RMS / bbox diagonal";
    render::write_png((fs::path(dir) / "plot.png").string(), render::plot_log_log(series, po));
    result.plot_png = "plot.png";
}

}  // namespace

std::string BenchOptions::validate() const {
    if (output_dir.empty()) return "no output folder given";
    if (executable.empty()) return "no quadcage executable given";
    if (jobs < 1 || jobs > 64) return "jobs must be 1..64";
    if (peer_attempts < 1 || peer_attempts > 16) return "peer attempts must be 1..16";
    if (!(timeout_seconds > 0) || !std::isfinite(timeout_seconds)) return "timeout must be a positive number of seconds";
    if (!(tolerance >= 0) || !std::isfinite(tolerance)) return "tolerance must be >= 0";
    if (fit_rounds < 0 || fit_rounds > 1000) return "fit rounds must be 1..1000 (0: fit's default)";
    if (turned_over_weight && (!(*turned_over_weight >= 0) || !std::isfinite(*turned_over_weight)))
        return "turned-over weight must be a number >= 0";
    for (size_t i = 0; i < levels.size(); ++i) {
        if (levels[i] < 0 || levels[i] > 8) return "level " + std::to_string(levels[i]) + " is outside 0..8";
        for (size_t k = 0; k < i; ++k)
            if (levels[k] == levels[i]) return "level " + std::to_string(levels[i]) + " is given twice";
    }
    return {};
}

BenchResult run_bench(const std::vector<BenchInput>& inputs, const BenchOptions& o) {
    if (const std::string e = o.validate(); !e.empty()) throw InvalidInput("bench: " + e);
    std::error_code ec;
    fs::create_directories(o.output_dir, ec);
    if (!fs::is_directory(o.output_dir, ec))
        throw InvalidInput(o.output_dir + ": cannot create the output folder (" + ec.message() + ")");
    BenchResult result;
    result.levels = o.levels;
    result.layout_flags = o.layout_flags;
    result.fit_rounds = o.fit_rounds;
    result.turned_over_weight = o.turned_over_weight;
    result.meshes.resize(inputs.size());
    const Clock::time_point start = Clock::now();
    std::mutex progress_mutex;
    std::atomic<size_t> next{0};
    auto worker = [&] {
        for (size_t i = next++; i < inputs.size(); i = next++) {
            MeshJob job(inputs[i], o, static_cast<int>(i), static_cast<int>(inputs.size()), start, progress_mutex);
            try {
                result.meshes[i] = job.run();
            } catch (const std::exception& e) {
                // Only the bench's own bookkeeping can get here (a log that cannot be written, ...).
                MeshResult m;
                m.input = inputs[i];
                m.status = std::string("failed: ") + e.what();
                m.stage = "bench";
                result.meshes[i] = m;
            }
        }
    };
    const int n = std::min<int>(o.jobs, static_cast<int>(inputs.size()));
    std::vector<std::thread> threads;
    for (int t = 1; t < n; ++t) threads.emplace_back(worker);
    worker();
    for (std::thread& t : threads) t.join();
    result.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
    write_plot(result, o.output_dir);
    return result;
}

}  // namespace quadcage::bench
