#include "quadcage/core/errors.h"

namespace quadcage::detail {

void fail_check(const char* expr, const char* file, int line, const std::string& msg) {
    throw InternalError(std::string("internal check failed: ") + expr + " (" + file + ":" +
                        std::to_string(line) + "): " + msg);
}

}  // namespace quadcage::detail
