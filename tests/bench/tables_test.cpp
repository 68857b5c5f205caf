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
    PeerResult p;
    p.target = "minimal";
    p.target_faces = 10;
    p.status = "ok";
    p.quads = 12;
    p.genus = 2;
    p.irregular_vertices = 14;
    p.seconds = 0.4;
    a.peers = {p};
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
    EXPECT_EQ(rows[1][col("peer_minimal_quads")], "12");
    EXPECT_EQ(rows[1][col("peer_level2_status")], "-");
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
              "bench: 3 meshes: 1 ok, 1 rejected, 1 failed; 1050 triangles; layout 1.5 s, fit 5.0 s, wall 12.5 s");
}

}  // namespace
