#include "quadcage/core/errors.h"
#include "quadcage/fit/fit.h"

namespace quadcage::fit {

CageFit fit_cage(const Mesh& mesh, const layout::QuadLayoutOptions& layout_options,
                 const FitOptions& fit_options) {
    if (const std::string e = fit_options.validate(); !e.empty()) throw InvalidInput("fit options: " + e);
    CageFit out;
    out.layout = layout::build_quad_layout(mesh, layout_options);
    out.fit = fit_surface(out.layout, fit_options);
    return out;
}

}  // namespace quadcage::fit
