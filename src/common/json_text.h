#pragma once
// Reports as JSON text, shared by the modules that write report.json (private to the source tree:
// no installed header mentions nlohmann).

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "quadcage/core/errors.h"

namespace quadcage::detail {

/// Throws InternalError if `j` holds a non-finite number (nlohmann would write it as null and hide
/// a bug); `where` is the JSON pointer of `j` in the report.
template <class Json>
void require_finite(const Json& j, const std::string& where = "") {
    if (j.is_number_float() && !std::isfinite(j.template get<double>()))
        throw InternalError("a report would hold a non-finite number at " + (where.empty() ? "/" : where));
    if (j.is_object())
        for (const auto& [k, v] : j.items()) require_finite(v, where + "/" + k);
    if (j.is_array())
        for (size_t i = 0; i < j.size(); ++i) require_finite(j[i], where + "/" + std::to_string(i));
}

/// `j` as text: indent < 0 compact on one line, else pretty-printed with that indent; a final
/// newline. \throw InternalError if it holds a non-finite number.
template <class Json>
std::string report_text(const Json& j, int indent) {
    require_finite(j);
    return j.dump(indent) + "\n";
}

}  // namespace quadcage::detail
