// The table writers: CSV quoting, well-formed JSON with nulls for missing values, markdown columns.

#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <sstream>

#include "quadcage/bench/tables.h"

namespace {

using namespace quadcage::bench;

// A run with an awkward name, a rejected mesh, a mesh failed at layout and one with two levels.
BenchResult sample() {
    BenchResult r;
    r.levels = {0, 1};
    r.wall_seconds = 12.5;
    MeshResult a;
    a.input = {"/data/a,\"b\"|c.obj", "a,\"b\"|c", "a__b__c"};
    a.status = "ok";
    a.triangles = 1000;
    a.components = 1;
    a.genus = "2";
    a.minimal_quads = 10;
    a.quads = 10;
    a.corners = 8;
    a.corner_degrees = {{5, 8}};
    a.verified = true;
    a.layout_seconds = 1.5;
    a.peak_memory_mib = 40;
    for (int l = 0; l < 2; ++l) {
        LevelResult lr;
        lr.level = l;
        lr.status = "ok";
        lr.control_points = 10 << (2 * l);
        lr.relative_rms = 0.01 / (l + 1);
        lr.relative_hausdorff = 0.05 / (l + 1);
        lr.fit_seconds = 2.0 + l;
        a.levels.push_back(lr);
    }
    // The peer at level 0 fitted with 8 control points like ours (ratios count), at level 1 with 30
    // against our 40 (more than 10% apart: no ratio).
    for (int l = 0; l < 2; ++l) {
        PeerResult p;
        p.level = l;
        p.target_faces = 10 << (2 * l);
        p.status = "ok";
        p.attempts.push_back({p.target_faces.value(), 0, "wrong genus 1 (input 2)", 12, 12, 14, 1, 0.3});
        p.attempts.push_back({p.target_faces.value(), 1, "ok", 12, 12, 10, 2, 0.4});
        p.faces = 12;
        p.quads = 12;
        p.irregular_vertices = 14;
        p.control_points = l == 0 ? 10 : 30;
        p.relative_rms = 0.004;
        p.relative_hausdorff = 0.1;
        p.fit_seconds = 0.7;
        p.quadriflow_seconds = 0.4;
        a.peers.push_back(p);
    }
    MeshResult b;
    b.input = {"open.off", "open", "open"};
    b.status = "rejected";
    b.stage = "info";
    b.reason = "open.off: cannot be quadded: 12 boundary edges, 1 loop";
    b.triangles = 50;
    MeshResult c;
    c.input = {"crash.ply", "crash", "crash"};
    c.status = "failed: crashed (signal 11)";
    c.stage = "layout";
    r.meshes = {a, b, c};
    return r;
}

// Minimal RFC 4180 reader: rows of fields.
std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
    std::vector<std::vector<std::string>> rows(1);
    std::string field;
    bool quoted = false, in_quotes = false;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (in_quotes) {
            if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') field += '"', ++i;
            else if (c == '"') in_quotes = false;
            else field += c;
        } else if (c == '"' && field.empty() && !quoted) {
            in_quotes = quoted = true;
        } else if (c == ',') {
            rows.back().push_back(field), field.clear(), quoted = false;
        } else if (c == '\n') {
            rows.back().push_back(field), field.clear(), quoted = false;
            rows.emplace_back();
        } else {
            field += c;
        }
    }
    if (rows.back().empty()) rows.pop_back();
    return rows;
}

TEST(BenchTables, CsvQuotesNamesAndHasOneRowPerMeshAndLevel) {
    const BenchResult r = sample();
    const std::string csv = bench_csv(r);
    EXPECT_NE(csv.find("\"a,\"\"b\"\"|c\""), std::string::npos) << csv;
    const auto rows = parse_csv(csv);
    ASSERT_EQ(rows.size(), 1u + 2 + 1 + 1);  // header, mesh a at 2 levels, b, c
    const std::vector<std::string> cols = table_columns();
    for (const auto& row : rows) EXPECT_EQ(row.size(), cols.size());
    EXPECT_EQ(rows[0], cols);
    auto col = [&](const std::string& name) {
        return static_cast<size_t>(std::find(cols.begin(), cols.end(), name) - cols.begin());
    };
    EXPECT_EQ(rows[1][col("name")], "a,\"b\"|c");
    EXPECT_EQ(rows[1][col("level")], "0");
    EXPECT_EQ(rows[2][col("level")], "1");
    EXPECT_EQ(rows[2][col("control_points")], "40");
    EXPECT_EQ(rows[2][col("relative_rms")], "0.005");
    EXPECT_EQ(rows[1][col("corners_by_degree")], "5:8");
    EXPECT_EQ(rows[1][col("peer_status")], "ok");
    EXPECT_EQ(rows[1][col("peer_attempts")], "2");
    EXPECT_EQ(rows[1][col("peer_control_points")], "10");
    EXPECT_EQ(rows[1][col("peer_relative_rms")], "0.004");
    EXPECT_EQ(rows[1][col("rms_ratio")], "2.5");  // 0.01 / 0.004
    EXPECT_EQ(rows[1][col("hausdorff_ratio")], "0.5");  // 0.05 / 0.1
    EXPECT_EQ(rows[1][col("ratio_note")], "-");
    EXPECT_EQ(rows[2][col("rms_ratio")], "-");
    EXPECT_EQ(rows[2][col("ratio_note")], "n/a (40 vs 30 control points)");
    EXPECT_EQ(rows[3][col("peer_status")], "-");
    EXPECT_EQ(rows[3][col("status")], "rejected");
    EXPECT_EQ(rows[3][col("reason")], "open.off: cannot be quadded: 12 boundary edges, 1 loop");
    EXPECT_EQ(rows[3][col("level")], "-");
    EXPECT_EQ(rows[3][col("quads")], "-");
    EXPECT_EQ(rows[4][col("status")], "failed: crashed (signal 11)");
    EXPECT_EQ(rows[4][col("stage")], "layout");
}

TEST(BenchTables, JsonIsWellFormedWithNullsForMissingValues) {
    const auto j = nlohmann::json::parse(bench_json(sample()));
    EXPECT_EQ(j["summary"]["meshes"], 3);
    EXPECT_EQ(j["summary"]["ok"], 1);
    EXPECT_EQ(j["summary"]["rejected"], 1);
    EXPECT_EQ(j["summary"]["failed"], 1);
    EXPECT_EQ(j["summary"]["triangles"], 1050);
    EXPECT_DOUBLE_EQ(j["summary"]["fit_seconds"].get<double>(), 5.0);
    EXPECT_EQ(j["meshes"][0]["name"], "a,\"b\"|c");
    EXPECT_EQ(j["meshes"][0]["corner_degrees"]["5"], 8);
    EXPECT_EQ(j["meshes"][0]["levels"][1]["control_points"], 40);
    EXPECT_EQ(j["meshes"][0]["peer"][0]["irregular_vertices"], 14);
    EXPECT_EQ(j["meshes"][0]["peer"][0]["attempts"][0]["outcome"], "wrong genus 1 (input 2)");
    EXPECT_DOUBLE_EQ(j["meshes"][0]["peer"][0]["rms_ratio"].get<double>(), 2.5);
    EXPECT_TRUE(j["meshes"][0]["peer"][1]["rms_ratio"].is_null());
    EXPECT_EQ(j["summary"]["peer_ratios"]["rows"], 1);
    EXPECT_DOUBLE_EQ(j["summary"]["peer_ratios"]["hausdorff"]["worst"].get<double>(), 0.5);
    EXPECT_TRUE(j["meshes"][1]["quads"].is_null());
    EXPECT_TRUE(j["meshes"][2]["triangles"].is_null());
    EXPECT_EQ(j["meshes"][2]["status"], "failed: crashed (signal 11)");
}

TEST(BenchTables, MarkdownRowsHaveTheHeaderColumnsAndEscapedPipes) {
    const std::string md = bench_markdown(sample());
    EXPECT_NE(md.find("a,\"b\"\\|c"), std::string::npos);
    EXPECT_NE(md.find(summary_line(sample())), std::string::npos);
    // Count unescaped '|' on each line of the results table.
    std::istringstream in(md.substr(md.find("## Results"), md.find("## Peer") - md.find("## Results")));
    std::vector<int> bars;
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] != '|') continue;
        int n = 0;
        for (size_t i = 0; i < line.size(); ++i) n += line[i] == '|' && (i == 0 || line[i - 1] != '\\');
        bars.push_back(n);
    }
    ASSERT_EQ(bars.size(), 2u + 4u);  // header, rule, 4 rows
    for (int n : bars) EXPECT_EQ(n, bars[0]);
    EXPECT_EQ(bars[0], 16);  // 15 columns
}

TEST(BenchTables, SummaryLineCountsAndTotals) {
    EXPECT_EQ(summary_line(sample()),
              "bench: 3 meshes: 1 ok, 1 rejected, 1 failed; 1050 triangles; layout 1.5 s, fit 5.0 s, wall 12.5 s; "
              "ours / QuadriFlow over 1 row: RMS worst 2.5 median 2.5, Hausdorff worst 0.5 median 0.5");
}

// Worst (largest) and median ratio over the rows that count; rows whose counts differ by more than
// 10% or whose peer failed are left out.
TEST(BenchTables, SummaryWorstAndMedianRatioOverTheCountedRows) {
    BenchResult r;
    r.levels = {3};
    const double ours_rms[] = {2e-4, 3e-4, 8e-4, 1e-4, 5e-4};
    const double peer_rms[] = {1e-4, 1e-4, 2e-4, 1e-4, 1e-4};  // ratios 2, 3, 4, 1, (5: not counted)
    const double ours_hd[] = {4e-3, 1e-3, 6e-3, 2e-3, 1e-3};
    const double peer_hd[] = {2e-3, 2e-3, 2e-3, 1e-3, 1e-4};  // ratios 2, 0.5, 3, 2, (10)
    for (int i = 0; i < 6; ++i) {
        MeshResult m;
        m.input = {"m" + std::to_string(i), "m" + std::to_string(i), "m" + std::to_string(i)};
        m.status = "ok";
        LevelResult l;
        l.level = 3;
        l.status = "ok";
        l.control_points = 1000;
        l.relative_rms = ours_rms[i % 5];
        l.relative_hausdorff = ours_hd[i % 5];
        m.levels = {l};
        PeerResult p;
        p.level = 3;
        p.status = i == 5 ? "failed: wrong genus 1 (input 2)" : "ok";
        p.control_points = i == 4 ? 1120 : 1050;  // 1120 / 1000 > 1.1
        p.relative_rms = peer_rms[i % 5];
        p.relative_hausdorff = peer_hd[i % 5];
        m.peers = {p};
        r.meshes.push_back(m);
    }
    const BenchSummary s = summarize(r);
    EXPECT_EQ(s.peer_rows, 4);
    EXPECT_DOUBLE_EQ(s.rms_ratio_worst.value_or(-1), 4.0);
    EXPECT_DOUBLE_EQ(s.rms_ratio_median.value_or(-1), 2.5);
    EXPECT_DOUBLE_EQ(s.hausdorff_ratio_worst.value_or(-1), 3.0);
    EXPECT_DOUBLE_EQ(s.hausdorff_ratio_median.value_or(-1), 2.0);
    EXPECT_EQ(compare_with_peer(r.meshes[4].levels[0], &r.meshes[4].peers[0]).note, "n/a (1000 vs 1120 control points)");
    EXPECT_EQ(compare_with_peer(r.meshes[5].levels[0], &r.meshes[5].peers[0]).note,
              "n/a (peer failed)");
    const std::string line = summary_line(r);
    EXPECT_NE(line.find("; ours / QuadriFlow over 4 rows: RMS worst 4 median 2.5, Hausdorff worst 3 median 2"),
              std::string::npos)
        << line;
    // bench.md's peer table: one row per mesh and level with both sides and the ratios.
    const std::string md = bench_markdown(r);
    EXPECT_NE(md.find("| m2 | 3 | 1000 / 1050 | 0.0008 / 0.0002 | 0.006 / 0.002 | 4 | 3 | ok |"), std::string::npos)
        << md;
}

// Exactly 10% apart still counts; just over does not.
TEST(BenchTables, RatioCountsWithinTenPercentOfControlPoints) {
    LevelResult ours;
    ours.status = "ok";
    ours.control_points = 1000;
    ours.relative_rms = 2e-4;
    ours.relative_hausdorff = 2e-3;
    PeerResult peer;
    peer.status = "ok";
    peer.relative_rms = 1e-4;
    peer.relative_hausdorff = 4e-3;
    peer.control_points = 1100;
    PeerComparison c = compare_with_peer(ours, &peer);
    ASSERT_TRUE(c.counted()) << c.note;
    EXPECT_DOUBLE_EQ(*c.rms_ratio, 2.0);
    EXPECT_DOUBLE_EQ(*c.hausdorff_ratio, 0.5);
    peer.control_points = 909;  // 1000 / 909 = 1.10011
    EXPECT_FALSE(compare_with_peer(ours, &peer).counted());
    peer.control_points = 910;
    EXPECT_TRUE(compare_with_peer(ours, &peer).counted());
    ours.status = "failed: crashed (signal 11)";
    EXPECT_EQ(compare_with_peer(ours, &peer).note, "n/a (our fit failed)");
    EXPECT_EQ(compare_with_peer(ours, nullptr).note, "n/a (no peer)");
}

}  // namespace
