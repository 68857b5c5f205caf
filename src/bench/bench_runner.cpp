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
        for (const char* f : {"input.obj", "quadriflow_minimal.obj", "quadriflow_minimal.obj.json",
                              "quadriflow_level2.obj", "quadriflow_level2.obj.json"})
            remove_quietly(dir_ / "peer" / f);
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
        const ChildResult r = stage("layout", substitute(o_.commands.layout, v));
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

    void run_fits() {
        for (int level : o_.levels) {
            LevelResult l;
            l.level = level;
            const fs::path ldir = dir_ / ("level" + std::to_string(level));
            auto v = vars();
            v["dir"] = ldir.string();
            v["level"] = std::to_string(level);
            std::vector<std::string> argv = substitute(o_.commands.fit, v);
            if (o_.tolerance > 0) argv.insert(argv.end(), {"--tolerance", fmt_g(o_.tolerance)});
            const ChildResult r = stage("fit level " + std::to_string(level), argv);
            l.peak_memory_mib = r.peak_memory_mib;
            l.status = outcome(r, o_.timeout_seconds, &l.reason);
            if (l.status == "ok") {
                if (const auto j = read_json(ldir / "report.json")) {
                    const json* entry = nullptr;
                    if (const json* ls = at_path(*j, {"levels"}); ls && ls->is_array()) {
                        for (const json& e : *ls)
                            if (get_int(e, {"level"}) == level) entry = &e;
                        if (!entry && ls->size() == 1) entry = &(*ls)[0];
                    }
                    if (entry) {
                        l.control_points = get_int(*entry, {"control_points"});
                        l.relative_rms = get_double(*entry, {"relative", "rms"});
                        l.relative_hausdorff = get_double(*entry, {"relative", "hausdorff"});
                        l.fit_seconds = get_seconds(*entry);
                    }
                    if (!l.fit_seconds) l.fit_seconds = get_seconds(*j);
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

    void run_peer() {
        PeerResult a, b;
        a.target = "minimal";
        b.target = "level2";
        if (m_.minimal_quads && *m_.minimal_quads > 0) {
            a.target_faces = *m_.minimal_quads;
            b.target_faces = 16 * *m_.minimal_quads;
        }
        m_.peers = {a, b};
        const std::string blender = o_.peer ? find_on_path(o_.blender) : std::string();
        for (PeerResult& p : m_.peers) {
            if (!o_.peer) p.status = "disabled";
            else if (blender.empty()) p.status = "not installed";
            else if (m_.stage == "info") p.status = "not run (" + m_.status + ")";
            else if (!p.target_faces) p.status = "failed: minimal quad count unknown";
        }
        if (!o_.peer || blender.empty() || m_.stage == "info" || !a.target_faces) return;
        std::error_code ec;
        if (o_.peer_script.empty() || !fs::exists(o_.peer_script, ec)) {
            for (PeerResult& p : m_.peers) p.status = "failed: peer script not found (" + o_.peer_script + ")";
            return;
        }
        // Blender reads OBJ everywhere; every input is handed over as OBJ written by quadcage.
        const fs::path pdir = dir_ / "peer";
        const fs::path obj = pdir / "input.obj";
        try {
            fs::create_directories(pdir, ec);
            write_obj(obj.string(), read_mesh(in_.path));
        } catch (const std::exception& e) {
            for (PeerResult& p : m_.peers) p.status = std::string("failed: cannot convert the input: ") + e.what();
            return;
        }
        for (PeerResult& p : m_.peers) {
            const fs::path out = pdir / ("quadriflow_" + p.target + ".obj");
            auto v = vars();
            v["blender"] = blender;
            v["script"] = o_.peer_script;
            v["mesh"] = obj.string();
            v["out"] = out.string();
            v["faces"] = std::to_string(*p.target_faces);
            const ChildResult r = stage("quadriflow " + p.target, substitute(o_.commands.peer, v));
            p.status = outcome(r, o_.timeout_seconds, nullptr);
            if (p.status == "rejected") p.status = "failed: " + reason_line(r.stderr_text);
            if (p.status != "ok") continue;
            if (const auto j = read_json(out.string() + ".json")) p.seconds = get_double(*j, {"seconds"});
            if (!fs::exists(out, ec)) {
                p.status = "failed: no output written";
                continue;
            }
            try {
                const PolygonMeshStats st = polygon_obj_stats(out.string());
                if (st.faces == 0) {
                    p.status = "empty";
                    continue;
                }
                p.faces = st.faces;
                p.quads = st.quads;
                p.genus = st.genus;
                p.irregular_vertices = st.irregular_vertices;
            } catch (const InvalidInput& e) {
                p.status = std::string("failed: ") + e.what();
            }
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
};

void write_plot(BenchResult& result, const std::string& dir) {
    std::vector<render::Series> series;
    for (const MeshResult& m : result.meshes) {
        render::Series s;
        s.name = m.input.name;
        for (const LevelResult& l : m.levels)
            if (l.control_points && l.relative_rms && *l.control_points > 0 && *l.relative_rms > 0) {
                s.x.push_back(*l.control_points);
                s.y.push_back(*l.relative_rms);
            }
        if (!s.x.empty()) series.push_back(s);
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
    if (!(timeout_seconds > 0) || !std::isfinite(timeout_seconds)) return "timeout must be a positive number of seconds";
    if (!(tolerance >= 0) || !std::isfinite(tolerance)) return "tolerance must be >= 0";
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
