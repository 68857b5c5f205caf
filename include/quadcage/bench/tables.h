#pragma once
// The tables of a benchmark run: bench.csv, bench.json and bench.md.

#include <string>
#include <vector>

#include "quadcage/bench/results.h"

namespace quadcage::bench {

/// Column names of the flat table (one row per mesh and level), in order.
std::vector<std::string> table_columns();

/// The flat table: one row per mesh and level (one row with level "-" when no level ran), cells as
/// text, "-" for a missing value. Same order as table_columns().
std::vector<std::vector<std::string>> table_rows(const BenchResult& result);

/// The flat table as CSV (RFC 4180: comma-separated, "\n" line ends, a cell quoted when it holds a
/// comma, quote, CR or LF, quotes doubled), header first.
std::string bench_csv(const BenchResult& result);

/// The whole result as JSON: {"summary": {...}, "levels": [...], "meshes": [{..., "levels": [...],
/// "peer": [...]}]}; missing values are null.
std::string bench_json(const BenchResult& result);

/// A markdown report: summary line, the plot, the flat table, the peer table and per mesh its
/// pictures (relative links, so the file can be moved with its folder).
std::string bench_markdown(const BenchResult& result);

/// Writes DIR/bench.csv, DIR/bench.json and DIR/bench.md atomically.
/// \throw InvalidInput if a file cannot be written.
void write_bench_tables(const std::string& dir, const BenchResult& result);

}  // namespace quadcage::bench
