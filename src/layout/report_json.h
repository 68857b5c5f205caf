#pragma once
// LayoutReport as a JSON object, for the reports that embed it (`quadcage fit`'s report.json has it
// under "layout"). Private to the source tree.

#include <nlohmann/json.hpp>

#include "quadcage/layout/outputs.h"

namespace quadcage::layout::detail {

/// The object LayoutReport::to_json() prints (keys sorted, as nlohmann::json keeps them).
nlohmann::json layout_report_object(const LayoutReport& report);

}  // namespace quadcage::layout::detail
