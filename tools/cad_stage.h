#pragma once
// STEP/IGES files of `export` and of `fit --step/--iges`: staged through OutputDir like every other
// output, so nothing is written unless everything succeeded (issue 22).

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "quadcage/cad/cad_export.h"
#include "quadcage/core/output_dir.h"
#include "quadcage/fit/fit.h"

namespace quadcage::cli {

/// What to write and how exactly.
struct CadFileOptions {
    std::string step;         ///< STEP file to write ("" none).
    std::string iges;         ///< IGES file to write ("" none).
    double tolerance = 1e-5;  ///< Max deviation from the limit surface, relative to the diagonal.
    bool any() const { return !step.empty() || !iges.empty(); }
};

/// The CAD files of one run. Construct before the work (checks the outputs), call write() with the
/// surface (builds, checks and stages), then commit() after the other outputs are committed.
class CadStage {
public:
    /// \param primary the run's own OutputDir (may be null) and `primary_dir` its directory: a file
    ///        there is staged through it; files elsewhere get an OutputDir of their own directory.
    /// \param inputs the files the run reads (an output may not replace one).
    CadStage(const CadFileOptions& files, OutputDir* primary, const std::string& primary_dir,
             const std::vector<std::string>& inputs);
    /// Builds the patches and the solid, checks them and writes the files into staging. Throws
    /// InvalidInput when the tolerance cannot be met or the solid is not a valid closed solid.
    /// `irregular_level` is the fit's FitOptions::irregular_level (the depth to which OpenSubdiv's
    /// surface is polynomial). Returns the export report.
    cad::ExportReport write(const fit::FittedSurface& surface, double diagonal, int irregular_level,
                         const std::function<void(const std::string&)>& progress);
    /// Moves the files staged outside the primary directory in.
    void commit();

private:
    std::string staged(const std::string& file);
    CadFileOptions files_;
    OutputDir* primary_;
    std::string primary_dir_;
    std::vector<std::string> inputs_;
    std::vector<std::pair<std::string, std::unique_ptr<OutputDir>>> others_;  // canonical dir -> OutputDir
};

/// Prints the summary lines of an export report.
void print_cad_summary(const std::string& tag, const cad::ExportReport& report);

}  // namespace quadcage::cli
